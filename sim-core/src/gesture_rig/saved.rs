//! # The rig's part of a saved sheet: where each hand holds the sheet ([`SavedHandDef`]) and
//! which vertices it holds, saved and restored with validation (the parent module's doc says why
//! the hands are saved).

use super::*;

/// Where a hand holds the sheet ([`HandDef`]), as saved with a sheet.
///
/// A rig works out its hands from the sheet when it is built (a new sheet, a mesh change) and
/// keeps them until the next mesh change, while singular points placed at vertices move those
/// in the pattern: a rig built afresh on the moved pattern can pick another neighbour of a
/// handle vertex or other offsets, so a sheet restored with fresh hands did not continue
/// bit-identically, and one saved while such a hand held the changed neighbour did not restore
/// at all (its held vertex did not fit the fresh hand; a long stress run found both). The
/// hands are therefore part of the saved state.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SavedHandDef {
    /// Held vertices: the handle vertices, then their tangent-plane neighbours.
    pub vertices: Vec<u32>,
    /// Number of handle vertices (they come first).
    pub num_mains: u8,
    /// For each held vertex, the index of the handle vertex it belongs to.
    pub main_of: Vec<u8>,
    /// Pattern offsets of the held vertices from the reference point, metres.
    pub home_offsets_m: Vec<[f64; 3]>,
    /// Reference point in the pattern, metres.
    pub home_ref_m: [f64; 2],
}

impl SavedHandDef {
    fn of(d: &HandDef) -> Self {
        let n = d.num_vertices as usize;
        Self {
            vertices: d.vertices[..n].to_vec(),
            num_mains: d.num_mains,
            main_of: d.main_of[..n].to_vec(),
            home_offsets_m: d.home_offsets[..n]
                .iter()
                .map(|o| [o.x, o.y, o.z])
                .collect(),
            home_ref_m: [d.home_ref.x, d.home_ref.y],
        }
    }

    /// The hand, if it fits a sheet of `num_vertices` vertices.
    fn to_def(&self, num_vertices: usize) -> Result<HandDef, String> {
        let n = self.vertices.len();
        let nm = self.num_mains as usize;
        // Inside the largest sheet's pattern (A3: 0.42 m), with room to spare.
        let fits = |x: &f64| x.is_finite() && x.abs() <= 1.0;
        let finite =
            self.home_offsets_m.iter().flatten().all(fits) && self.home_ref_m.iter().all(fits);
        if n > MAX_HAND_VERTICES
            || !(1..=2).contains(&nm)
            || nm > n
            || self.main_of.len() != n
            || self.home_offsets_m.len() != n
            || self.main_of.iter().any(|&m| usize::from(m) >= nm)
            || self.vertices.iter().any(|&v| v as usize >= num_vertices)
            || (1..n).any(|i| self.vertices[..i].contains(&self.vertices[i]))
            || !finite
        {
            return Err("a saved hand does not fit the sheet".into());
        }
        let mut d = HandDef {
            num_vertices: n as u8,
            num_mains: self.num_mains,
            vertices: [u32::MAX; MAX_HAND_VERTICES],
            main_of: [0; MAX_HAND_VERTICES],
            home_offsets: [V3::zeros(); MAX_HAND_VERTICES],
            home_ref: V2::new(self.home_ref_m[0], self.home_ref_m[1]),
        };
        d.vertices[..n].copy_from_slice(&self.vertices);
        d.main_of[..n].copy_from_slice(&self.main_of);
        for (o, s) in d.home_offsets.iter_mut().zip(&self.home_offsets_m) {
            *o = V3::new(s[0], s[1], s[2]);
        }
        Ok(d)
    }
}

impl GestureRig {
    /// The ownership (vertex, hand, index in the hand), the suppression flags and whether the
    /// ownership is pending recomputation (saved with the sheet for exact continuation).
    pub fn ownership_state(&self) -> (Vec<(u32, u8, u8)>, [bool; NUM_HANDS], bool) {
        (
            self.ownership.clone(),
            self.suppressed,
            self.ownership_dirty,
        )
    }

    /// Where each hand holds the sheet, for a saved sheet ([`SavedHandDef`]).
    pub fn hand_defs_state(&self) -> Vec<SavedHandDef> {
        self.info.iter().map(|i| SavedHandDef::of(&i.def)).collect()
    }

    /// Restores [`Self::hand_defs_state`] (before [`Self::restore_ownership`]); an empty list
    /// (a sheet saved before the hands were kept) keeps the hands this rig worked out. Returns
    /// an error message if a hand does not fit the sheet; nothing changes then.
    pub fn restore_hand_defs(&mut self, defs: &[SavedHandDef]) -> Result<(), String> {
        if defs.is_empty() {
            return Ok(());
        }
        if defs.len() != NUM_HANDS {
            return Err(format!(
                "{} saved hands, the rig has {NUM_HANDS}",
                defs.len()
            ));
        }
        let mut restored = [self.info[0].def; NUM_HANDS];
        for (r, d) in restored.iter_mut().zip(defs) {
            *r = d.to_def(self.claim.len())?;
        }
        for (i, r) in self.info.iter_mut().zip(restored) {
            i.def = r;
        }
        Ok(())
    }

    /// Restores [`Self::ownership_state`] after `state` was restored. Returns an error message
    /// if an entry does not fit the current hands and mesh; no vertex is held then.
    ///
    /// `lenient` (a sheet saved before the hands were saved, [`Self::restore_hand_defs`]):
    /// the hands were worked out afresh and may name another vertex where the saved hand held
    /// one (a vertex moved in the pattern since the hands were built); such an entry is let go
    /// instead (the hand's hold on it cleared, ownership worked out again next frame), so the
    /// sheet still opens. Entries naming no vertex, hand or hand slot are errors either way.
    pub fn restore_ownership(
        &mut self,
        ownership: &[(u32, u8, u8)],
        suppressed: [bool; NUM_HANDS],
        dirty: bool,
        lenient: bool,
    ) -> Result<(), String> {
        if ownership.len() > NUM_HANDS * MAX_HAND_VERTICES {
            return Err("too many held vertices".into());
        }
        let in_range = |&(v, k, j): &(u32, u8, u8)| {
            (v as usize) < self.claim.len()
                && (k as usize) < NUM_HANDS
                && (j as usize) < MAX_HAND_VERTICES
        };
        if let Some(&(v, k, j)) = ownership.iter().find(|e| !in_range(e)) {
            return Err(format!(
                "held vertex entry ({v}, {k}, {j}) does not fit the sheet"
            ));
        }
        for c in &mut self.claim {
            *c = u8::MAX;
        }
        let mut let_go = [0u16; NUM_HANDS];
        for &(v, k, j) in ownership {
            let def = &self.info[k as usize].def;
            let fits = (j as usize) < def.num_vertices as usize
                && def.vertices[j as usize] == v
                && self.claim[v as usize] == u8::MAX;
            if fits {
                self.claim[v as usize] = k;
            } else if lenient {
                let_go[k as usize] |= 1 << j;
            } else {
                for c in &mut self.claim {
                    *c = u8::MAX;
                }
                self.ownership.clear();
                return Err(format!(
                    "held vertex entry ({v}, {k}, {j}) does not fit the sheet"
                ));
            }
        }
        self.ownership.clear();
        for &(v, k, j) in ownership {
            if let_go[k as usize] & (1 << j) == 0 {
                self.ownership.push((v, k, j));
            }
        }
        for (h, bits) in self.state.hands.iter_mut().zip(let_go) {
            h.mask &= !bits;
        }
        self.suppressed = suppressed;
        self.ownership_dirty = dirty || let_go.iter().any(|&b| b != 0);
        Ok(())
    }
}
