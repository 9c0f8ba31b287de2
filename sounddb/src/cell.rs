//! # Cells, the size grid and the nearest-occupied-cell lookup
//!
//! A cell is either the constrained cell (0, 0) or a free cell keyed by the recorded sheet's
//! straight edge l_r and curved edge l_c/2 (see the crate docs for why l_c/2; seeds T 1808,
//! T 1905, S 151). The grid of the seeds is [`GRID_CM`] on both axes (T 1905, S 210).
//!
//! Selection (T 1810–1818, S 153): "the closest recorded (l_r, l_c), considering also the special
//! case (0, 0) when the resonator has no free border". Our metric (digest-sound §3 proposal):
//!
//! ```text
//! d² = (ln l_r − ln L_r)² + (ln(l_c/2) − ln C)²        over the occupied free cells (L_r, C)
//! ```
//!
//! with the query clamped to [0.5, 200] cm on both axes so that degenerate resonators (a
//! zero-length ruling) still find a cell. A constrained query (l_c ≤ 0) goes to (0, 0); if the
//! database has no constrained entry it falls back to the free cell nearest to the smallest grid
//! cell (2.5, 2.5) — the most "damped" sound — which [`CellIndex::lookup`] reports through
//! [`Lookup::fallback`]. A free query in a database with only the constrained cell gets (0, 0).

/// The size grid of the seeds, cm (T 1905, S 210), for both `straight_cm` and `curved_cm`.
pub const GRID_CM: [f32; 9] = [2.5, 5.0, 7.5, 10.0, 12.5, 15.0, 20.0, 25.0, 30.0];

/// Query lengths are clamped to this range before taking logarithms, cm.
pub const QUERY_RANGE_CM: (f32, f32) = (0.5, 200.0);

/// A database cell.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Cell {
    /// The (0, 0) cell: constrained sounds ("clac" clips, constrained friction; T 1808).
    Constrained,
    /// A free cell: the recorded rectangle's edges.
    Free {
        /// Straight edge = l_r (mean ruling length), cm.
        straight_cm: f32,
        /// Curved edge = l_c/2 (half the total free curved border), cm.
        curved_cm: f32,
    },
}

impl Cell {
    /// A free cell from a resonator-style pair: l_r and the **total** free curved border l_c.
    pub fn from_resonator(lr_cm: f32, lc_cm: f32) -> Self {
        if lc_cm.is_nan() || lc_cm <= 0.0 {
            Cell::Constrained
        } else {
            Cell::Free {
                straight_cm: lr_cm,
                curved_cm: 0.5 * lc_cm,
            }
        }
    }

    /// True for the (0, 0) cell.
    pub fn is_constrained(&self) -> bool {
        matches!(self, Cell::Constrained)
    }

    /// Radius of the disk with the recorded sheet's area, metres: √(l_r · l_c/2 / π). This is
    /// the a_ref of digest-sound §5.3 (the dipole a³ factor is applied as (a/a_ref)³ so that the
    /// size already contained in the recording is not counted twice). `None` for (0, 0).
    pub fn reference_radius_m(&self) -> Option<f32> {
        match *self {
            Cell::Constrained => None,
            Cell::Free {
                straight_cm,
                curved_cm,
            } => Some((straight_cm * curved_cm * 1e-4 / std::f32::consts::PI).sqrt()),
        }
    }

    /// True when both lengths are on [`GRID_CM`] (within 1e-3 cm).
    pub fn is_on_grid(&self) -> bool {
        match *self {
            Cell::Constrained => true,
            Cell::Free {
                straight_cm,
                curved_cm,
            } => on_grid(straight_cm) && on_grid(curved_cm),
        }
    }

    /// Same cell (lengths equal within 1e-3 cm).
    pub fn same_as(&self, other: &Cell) -> bool {
        match (*self, *other) {
            (Cell::Constrained, Cell::Constrained) => true,
            (
                Cell::Free {
                    straight_cm: a,
                    curved_cm: b,
                },
                Cell::Free {
                    straight_cm: c,
                    curved_cm: d,
                },
            ) => (a - c).abs() < 1e-3 && (b - d).abs() < 1e-3,
            _ => false,
        }
    }

    /// A short human label: `clac/flat (0,0)` or `s10_c5`.
    pub fn label(&self) -> String {
        match *self {
            Cell::Constrained => "(0,0)".to_string(),
            Cell::Free {
                straight_cm,
                curved_cm,
            } => format!("s{}_c{}", fmt_cm(straight_cm), fmt_cm(curved_cm)),
        }
    }
}

/// Formats a length in cm without trailing zeros (`12.5`, `10`).
pub fn fmt_cm(v: f32) -> String {
    let s = format!("{v:.3}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    s.to_string()
}

fn on_grid(v: f32) -> bool {
    GRID_CM.iter().any(|g| (g - v).abs() < 1e-3)
}

/// Result of a lookup.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Lookup {
    /// Index of the selected cell in the index's cell list.
    pub index: usize,
    /// True when the query's own kind (constrained / free) was absent and the other kind was used.
    pub fallback: bool,
}

/// Nearest-occupied-cell index over a fixed list of cells. Built once (allocates), queried
/// without allocation.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct CellIndex {
    /// (ln straight, ln curved) of each free cell; `None` for the constrained cell.
    logs: Vec<Option<(f32, f32)>>,
    constrained: Option<usize>,
    /// The free cell nearest to (2.5, 2.5): fallback for constrained queries.
    smallest_free: Option<usize>,
}

impl CellIndex {
    /// Indexes `cells` (their order is the tie-break order).
    pub fn new(cells: &[Cell]) -> Self {
        let logs: Vec<Option<(f32, f32)>> = cells
            .iter()
            .map(|c| match *c {
                Cell::Constrained => None,
                Cell::Free {
                    straight_cm,
                    curved_cm,
                } => Some((clamped_ln(straight_cm), clamped_ln(curved_cm))),
            })
            .collect();
        let constrained = cells.iter().position(|c| c.is_constrained());
        let mut index = Self {
            logs,
            constrained,
            smallest_free: None,
        };
        index.smallest_free = index.nearest_free(GRID_CM[0], GRID_CM[0]);
        index
    }

    /// Number of indexed cells.
    pub fn len(&self) -> usize {
        self.logs.len()
    }

    /// True when no cell is indexed.
    pub fn is_empty(&self) -> bool {
        self.logs.is_empty()
    }

    /// The cell for a resonator with mean ruling length `lr_cm` and total free curved border
    /// `lc_cm` (`lc_cm ≤ 0` = constrained). `None` only for an empty index. No allocation.
    pub fn lookup(&self, lr_cm: f32, lc_cm: f32) -> Option<Lookup> {
        if lc_cm.is_nan() || lc_cm <= 0.0 {
            return match (self.constrained, self.smallest_free) {
                (Some(index), _) => Some(Lookup {
                    index,
                    fallback: false,
                }),
                (None, Some(index)) => Some(Lookup {
                    index,
                    fallback: true,
                }),
                (None, None) => None,
            };
        }
        match self.nearest_free(lr_cm, 0.5 * lc_cm) {
            Some(index) => Some(Lookup {
                index,
                fallback: false,
            }),
            None => self.constrained.map(|index| Lookup {
                index,
                fallback: true,
            }),
        }
    }

    /// The free cell nearest to (straight, curved) in the log metric.
    pub fn nearest_free(&self, straight_cm: f32, curved_cm: f32) -> Option<usize> {
        let (qs, qc) = (clamped_ln(straight_cm), clamped_ln(curved_cm));
        let mut best: Option<(usize, f32)> = None;
        for (i, l) in self.logs.iter().enumerate() {
            if let Some((s, c)) = *l {
                let d2 = (s - qs) * (s - qs) + (c - qc) * (c - qc);
                if best.is_none_or(|(_, b)| d2 < b) {
                    best = Some((i, d2));
                }
            }
        }
        best.map(|(i, _)| i)
    }
}

/// ln of a length clamped to [`QUERY_RANGE_CM`]; NaN maps to the lower bound.
fn clamped_ln(v: f32) -> f32 {
    let v = if v.is_nan() { QUERY_RANGE_CM.0 } else { v };
    v.clamp(QUERY_RANGE_CM.0, QUERY_RANGE_CM.1).ln()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn full_grid() -> Vec<Cell> {
        let mut cells = vec![Cell::Constrained];
        for s in GRID_CM {
            for c in GRID_CM {
                cells.push(Cell::Free {
                    straight_cm: s,
                    curved_cm: c,
                });
            }
        }
        cells
    }

    mod lookup {
        use super::*;

        #[test]
        fn constrained_goes_to_zero_cell() {
            let cells = full_grid();
            let idx = CellIndex::new(&cells);
            let l = idx.lookup(10.0, 0.0).unwrap();
            assert_eq!(cells[l.index], Cell::Constrained);
            assert!(!l.fallback);
            // Negative and NaN l_c are constrained too.
            assert_eq!(
                cells[idx.lookup(10.0, -3.0).unwrap().index],
                Cell::Constrained
            );
            assert_eq!(
                cells[idx.lookup(10.0, f32::NAN).unwrap().index],
                Cell::Constrained
            );
        }

        #[test]
        fn digest_example_11_by_6_1() {
            // digest-sound §12 test 15: (l_r, l_c/2) = (11, 6.1) cm, i.e. l_c = 12.2 cm.
            // ln(11/10) = 0.095 < ln(12.5/11) = 0.128; ln(6.1/5) = 0.199 < ln(7.5/6.1) = 0.207.
            let cells = full_grid();
            let idx = CellIndex::new(&cells);
            let l = idx.lookup(11.0, 12.2).unwrap();
            assert_eq!(
                cells[l.index],
                Cell::Free {
                    straight_cm: 10.0,
                    curved_cm: 5.0
                }
            );
        }

        #[test]
        fn nearest_occupied_when_cells_are_missing() {
            let mut cells = full_grid();
            cells.retain(|c| {
                !c.same_as(&Cell::Free {
                    straight_cm: 10.0,
                    curved_cm: 5.0,
                })
            });
            let idx = CellIndex::new(&cells);
            let got = cells[idx.lookup(11.0, 12.2).unwrap().index];
            // Candidates at distance: (12.5,5): √(.128²+.199²)=.236; (10,7.5): √(.095²+.207²)=.228.
            assert_eq!(
                got,
                Cell::Free {
                    straight_cm: 10.0,
                    curved_cm: 7.5
                }
            );
        }

        #[test]
        fn fallbacks_between_kinds() {
            let only_free = vec![
                Cell::Free {
                    straight_cm: 20.0,
                    curved_cm: 20.0,
                },
                Cell::Free {
                    straight_cm: 5.0,
                    curved_cm: 2.5,
                },
            ];
            let idx = CellIndex::new(&only_free);
            let l = idx.lookup(10.0, 0.0).unwrap();
            assert_eq!(l.index, 1);
            assert!(l.fallback);
            let only_constrained = vec![Cell::Constrained];
            let idx = CellIndex::new(&only_constrained);
            let l = idx.lookup(10.0, 10.0).unwrap();
            assert_eq!(l.index, 0);
            assert!(l.fallback);
            assert!(CellIndex::new(&[]).lookup(1.0, 1.0).is_none());
        }

        #[test]
        fn extreme_queries_are_clamped() {
            let cells = full_grid();
            let idx = CellIndex::new(&cells);
            for (lr, lc) in [
                (0.0, 1.0),
                (1e9, 1e9),
                (f32::NAN, 5.0),
                (f32::INFINITY, 3.0),
            ] {
                assert!(idx.lookup(lr, lc).is_some());
            }
        }
    }

    #[test]
    fn reference_radius_and_labels() {
        let c = Cell::Free {
            straight_cm: 10.0,
            curved_cm: 10.0,
        };
        let a = c.reference_radius_m().unwrap();
        assert!((a - (0.01f32 / std::f32::consts::PI).sqrt()).abs() < 1e-6);
        assert_eq!(c.label(), "s10_c10");
        assert_eq!(
            Cell::Free {
                straight_cm: 12.5,
                curved_cm: 2.5
            }
            .label(),
            "s12.5_c2.5"
        );
        assert!(Cell::Constrained.reference_radius_m().is_none());
        assert_eq!(Cell::from_resonator(10.0, 20.0), c);
    }
}
