//! # Undoing a frame: the pass-through guard and an undone frame relaxed (the parent module's
//! sections "The pass-through guard" and "An undone frame relaxed" say what and why).

use super::*;

impl Sim {
    /// Undoes this frame's motion if it passed the sheet through itself: S_P goes back to
    /// where it was at the start of the frame (which did not cross) and stops, and the squeeze
    /// backs off. An impact-zone-like fail-safe at frame granularity for what sheet–sheet
    /// contact ([`crate::physics::sheet_contact`]) does not catch: a fold moving through a
    /// layer faster than the contact skin within one frame. The
    /// whole frame is undone, not only the crossing triangles: moving some vertices back while
    /// their neighbours moved on would strain the sheet by up to the frame's travel over an
    /// edge (measured: strain 0.4–2.4). The sheet–sheet contact between the triangles that
    /// crossed is stiffened first (sheet_contact.rs "Stiffening where the sheet crossed"), so
    /// the replay does not cross the same way again. Returns true if the frame was undone.
    pub(super) fn undo_pass_through(&mut self, frame_scale: f64) -> bool {
        let (physics, sp) = (&mut self.physics, &self.sheet.sp);
        let mut crossed = false;
        self.proximity.for_each_crossing(sp, |a, b| {
            crossed = true;
            physics.boost_crossing(sp.triangles[a as usize], sp.triangles[b as usize]);
        });
        if !crossed {
            return false;
        }
        // A start that crosses already (two layers of one fold: the closest-approach query
        // that armed the guard skips pairs that close in the pattern) has nothing clean to go
        // back to: the frame stands, as when the guard is off (module doc, "The pass-through
        // guard").
        let sp = &self.sheet.sp;
        self.stalled_pos.clone_from(&sp.pos);
        self.stalled_vel.clone_from(&sp.vel);
        self.restore_frame_start();
        if self.proximity.any_crossing(&self.sheet.sp) {
            let sp = &mut self.sheet.sp;
            sp.pos.clone_from(&self.stalled_pos);
            sp.vel.clone_from(&self.stalled_vel);
            self.kept_crossed_start = true;
            return false;
        }
        if self.frame_normals_saved {
            // A split substep advanced the flipped-triangle reference: back to the frame's.
            self.metrics.set_previous_normals(&self.frame_start_normals);
        }
        self.rig.undo_frame_motion();
        self.rig.limit_squeeze(0.0, frame_scale);
        true
    }

    /// An undone frame leaves the sheet where the frame started, at rest (module doc, "An
    /// undone frame relaxed"). When that start is strained beyond [`UNDO_RELAX_STRAIN`], the
    /// frame's substeps are solved again from it with every hand held where the frame
    /// started, and if that passes the sheet through itself, once more with
    /// [`UNDO_RELAX_FINE_FACTOR`] times the substeps; a result stands if it turns no triangle
    /// over, does not pass the sheet through itself and lowers the largest strain. The sheet
    /// is left at rest. Returns whether a relaxation stood.
    pub(super) fn relax_undone_start(&mut self, dt: f64) -> bool {
        let sp = &self.sheet.sp;
        let strain0 = crate::metrics::max_strain(sp, &sp.pos);
        if strain0 <= UNDO_RELAX_STRAIN {
            return false;
        }
        self.stalled_pos.clone_from(&sp.pos);
        let mut stands = false;
        // The frame's substeps first; if the fold springs through a layer in them, four times
        // as many, shorter (the contact search follows a fast fold better).
        for n_sub in [
            self.cfg.solver.substeps,
            UNDO_RELAX_FINE_FACTOR * self.cfg.solver.substeps,
        ] {
            let h = dt / f64::from(n_sub);
            for s in 1..=n_sub {
                self.fill_held(f64::from(s) / f64::from(n_sub));
                self.solve_substep(h);
                self.limit_penetration();
            }
            let sp = &mut self.sheet.sp;
            let strain = crate::metrics::max_strain(sp, &sp.pos);
            stands = strain < strain0
                && !crate::physics::turns_a_triangle_over(sp, &self.stalled_pos, &sp.pos)
                && !self.proximity.any_crossing(sp);
            if stands {
                break;
            }
            sp.pos.clone_from(&self.stalled_pos);
            sp.vel.fill(V3::zeros());
        }
        let sp = &mut self.sheet.sp;
        sp.vel.fill(V3::zeros());
        stands
    }

    /// S_P back to the frame's start, at rest. The pattern is not restored: a singular point
    /// placed this frame is persistent, and the vertex it moved in the pattern
    /// (`PhysMesh::move_pattern_vertex`) goes to the restored surface over its new pattern
    /// position, as the move put it on the simulated one. Restoring its old 3D point instead
    /// left it up to an edge away from where its rest shape puts it (a long stress run:
    /// strain 1.02 after a 1.2 cm move).
    pub(super) fn restore_frame_start(&mut self) {
        let sp = &mut self.sheet.sp;
        sp.pos.clone_from(&self.frame_start_pos);
        sp.vel.fill(V3::zeros());
        for v in 0..sp.pos.len() {
            let (old, new) = (self.frame_start_pattern[v], sp.pattern[v]);
            if old != new
                && let Some(x) = sp.surface_point_over(v as u32, old, new)
                && x.iter().all(|c| c.is_finite())
            {
                sp.pos[v] = x;
            }
        }
    }
}
