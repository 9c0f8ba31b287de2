//! Placing the frontier plot's point labels so that none covers another label or a point.
//!
//! The report's configurations cluster (a dozen geometry-layer rows within a few tenths of a
//! millisecond and of c_mean), and labels written at a fixed offset from each point overprint
//! each other there. [`place_labels`] puts each label, in the caller's order (most important
//! first), at the first of a list of candidate places around its point — beside it, then
//! farther out in eight directions (the plot draws a leader line to a label set off) — that
//! stays inside the plot and overlaps no label placed before and no point. A label with no free
//! place is left out, and the caller lists it in a numbered key instead.

/// An axis-aligned pixel rectangle: left, top, width, height.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Rect {
    pub x: i32,
    pub y: i32,
    pub w: i32,
    pub h: i32,
}

impl Rect {
    /// True if the two rectangles share any pixel.
    pub fn overlaps(&self, o: &Rect) -> bool {
        self.x < o.x + o.w && o.x < self.x + self.w && self.y < o.y + o.h && o.y < self.y + self.h
    }

    /// True if `self` lies inside `o`.
    pub fn inside(&self, o: &Rect) -> bool {
        self.x >= o.x
            && self.y >= o.y
            && self.x + self.w <= o.x + o.w
            && self.y + self.h <= o.y + o.h
    }
}

/// Distances (pixels) from a point at which its label is tried, nearest first; 0 is "beside it".
const RINGS_PX: [i32; 5] = [0, 16, 32, 50, 72];
/// Gap between a point's centre and its label when beside it, pixels.
const GAP_PX: i32 = 8;

/// Candidate top-left corners of a `w` × `h` label for a point at `p`, nearest first.
fn candidates(p: (i32, i32), w: i32, h: i32) -> Vec<(i32, i32)> {
    let (px, py) = p;
    let mut out = Vec::with_capacity(8 * RINGS_PX.len());
    for r in RINGS_PX {
        let g = GAP_PX + r;
        out.extend([
            (px + g, py - h / 2),     // right
            (px - g - w, py - h / 2), // left
            (px + g, py - g - h),     // upper right
            (px + g, py + g),         // lower right
            (px - g - w, py - g - h), // upper left
            (px - g - w, py + g),     // lower left
            (px - w / 2, py - g - h), // above
            (px - w / 2, py + g),     // below
        ]);
    }
    out
}

/// Places labels of sizes `sizes[i]` (w, h) for points `points[i]` (pixels), in index order,
/// inside `bounds`, clear of every point (a square of `point_r` about each), of `obstacles`
/// and of each other. Returns each label's top-left corner, or `None` where none was free.
pub fn place_labels(
    points: &[(i32, i32)],
    sizes: &[(i32, i32)],
    point_r: i32,
    bounds: Rect,
    obstacles: &[Rect],
) -> Vec<Option<(i32, i32)>> {
    let dots: Vec<Rect> = points
        .iter()
        .map(|&(x, y)| Rect {
            x: x - point_r,
            y: y - point_r,
            w: 2 * point_r + 1,
            h: 2 * point_r + 1,
        })
        .collect();
    let mut placed: Vec<Rect> = Vec::with_capacity(points.len());
    points
        .iter()
        .zip(sizes)
        .map(|(&p, &(w, h))| {
            let spot = candidates(p, w, h).into_iter().find(|&(x, y)| {
                let r = Rect { x, y, w, h };
                r.inside(&bounds)
                    && !dots.iter().any(|d| d.overlaps(&r))
                    && !obstacles.iter().any(|o| o.overlaps(&r))
                    && !placed.iter().any(|l| l.overlaps(&r))
            })?;
            placed.push(Rect {
                x: spot.0,
                y: spot.1,
                w,
                h,
            });
            Some(spot)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    const BOUNDS: Rect = Rect {
        x: 0,
        y: 0,
        w: 400,
        h: 300,
    };

    #[test]
    fn an_isolated_label_goes_right_beside_its_point() {
        let got = place_labels(&[(100, 100)], &[(60, 12)], 6, BOUNDS, &[]);
        assert_eq!(got, vec![Some((108, 94))]);
    }

    #[test]
    fn clustered_labels_never_overlap_each_other_or_a_point() {
        // Twelve points within 20 px of each other, as the geometry-layer rows are.
        let points: Vec<(i32, i32)> = (0..12).map(|i| (150 + 3 * i, 140 + (i * 7) % 20)).collect();
        let sizes = vec![(120, 12); points.len()];
        let got = place_labels(&points, &sizes, 6, BOUNDS, &[]);
        let rects: Vec<Rect> = got
            .iter()
            .zip(&sizes)
            .filter_map(|(p, &(w, h))| p.map(|(x, y)| Rect { x, y, w, h }))
            .collect();
        assert!(rects.len() >= 8, "only {} of 12 placed", rects.len());
        for (i, a) in rects.iter().enumerate() {
            assert!(a.inside(&BOUNDS));
            for b in &rects[i + 1..] {
                assert!(!a.overlaps(b), "{a:?} overlaps {b:?}");
            }
            for &(x, y) in &points {
                let dot = Rect {
                    x: x - 6,
                    y: y - 6,
                    w: 13,
                    h: 13,
                };
                assert!(!a.overlaps(&dot), "{a:?} covers the point at ({x}, {y})");
            }
        }
    }

    #[test]
    fn a_label_with_no_free_place_is_left_out() {
        // The bounds leave no room beside the point at all.
        let tight = Rect {
            x: 90,
            y: 90,
            w: 20,
            h: 20,
        };
        assert_eq!(
            place_labels(&[(100, 100)], &[(60, 12)], 6, tight, &[]),
            vec![None]
        );
    }

    #[test]
    fn obstacles_are_kept_clear() {
        let legend = Rect {
            x: 100,
            y: 80,
            w: 200,
            h: 40,
        };
        let got = place_labels(&[(100, 100)], &[(60, 12)], 6, BOUNDS, &[legend]);
        let (x, y) = got[0].expect("placed");
        assert!(!Rect { x, y, w: 60, h: 12 }.overlaps(&legend));
    }
}
