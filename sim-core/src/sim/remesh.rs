//! # Refining S_P for a singular vertex, flipping a compressed edge, cutting a strip, taking a cut vertex out again (the sim's side of [`crate::sheet::refine`], [`crate::sheet::cut`] and [`crate::sheet::coarsen`])
//!
//! When the geometry layer draws a singular vertex whose nearest S_P vertex cannot move to the
//! drawn position s̄ in full, it leaves the point pending ([`GeometryLayer::take_pending_singular`]).
//! Unless the crumple cap undoes that frame, at the start of the next step (so that a host
//! stepping the sheet on its audio thread knows beforehand that this step allocates,
//! [`Sim::refinement_pending`]; the singular vertex is made 5 ms later than it was drawn, and a
//! sleeping sheet wakes) the sim inserts a vertex
//! at s̄ ([`refine::insert_vertex_near`]: at s̄, or just outside the
//! refusal distance of an existing vertex s̄ falls next to) and carries everything that is sized by S_P over to the
//! refined mesh, the way a saved sheet is restored ([`Sim::restore`]): a new sparse system for
//! the physics, the gesture rig rebuilt on the new mesh with its hands' state and held vertices
//! kept (old vertices keep their indices), the geometry layer carried over
//! ([`GeometryLayer::remeshed`]), fresh metrics references and per-vertex buffers one longer.
//! The sound analysis, the obstacles and the random generators are not touched. Then the new
//! vertex becomes the singular vertex, with its fibre damage.
//!
//! The insertion is refused (the point near a vertex or the boundary, a poorly shaped star,
//! the mesh at the capacity the snapshots were sized for) — then the nearest vertex moves
//! towards s̄ as far as its triangles allow, as without insertion.
//!
//! A compressed flat-region edge the layer found in the last frame
//! ([`GeometryLayer::take_pending_flip`], geometry.rs step 2) is flipped the same way, first:
//! [`refine::flip_edge`], refused if the flip makes the sheet cross itself where it did not,
//! then the same carry-over (vertex and triangle counts unchanged) and a
//! [`crate::geometry::ShapeEvent::EdgeFlipped`] event.
//!
//! With [`crate::geometry::GeometryConfig::cut_strips`] on, a new strip found in the last
//! frame ([`GeometryLayer::take_pending_cut`]) is cut along its imaginary ruling next, before
//! the singular vertex: [`cut::cut_along`] (new vertices on the crossed edges, state carried
//! over), refused if the cut mesh would exceed the capacity or cross itself, then the same
//! carry-over and a [`crate::geometry::ShapeEvent::StripCut`] event.
//!
//! With [`crate::geometry::GeometryConfig::coarsen_flat_regions`] on (the default), a vertex
//! the layer found last frame in a flat, still, unheld part of the sheet
//! ([`GeometryLayer::take_pending_coarsen`]: only a vertex a cut added) is collapsed into a
//! neighbour: [`coarsen::collapse_vertex`] (checked again on the current sheet), refused if
//! the sheet would cross itself, then the same carry-over with one difference — the vertices
//! after the removed one move down by one index, so everything that names vertices is mapped
//! (the layer's singular list and pending changes, the hands' held vertices, the contact
//! boosts, the per-vertex buffers) — and a [`crate::geometry::ShapeEvent::VertexCollapsed`]
//! event. The layer asks for it only when nothing else is pending.
//!
//! Building a mesh allocates: an insertion, a flip, a cut or a collapse is an event (at most one
//! of each per frame, announced by [`Sim::refinement_pending`]), like a reset, not a
//! steady-state step.

use super::Sim;
use crate::collision::VertexContact;
use crate::geometry::THETA0_RAD;
use crate::geometry::{GeometryLayer, PendingFlip, PendingSingular};
use crate::geometry::{RegionKind, TriKind};
use crate::gesture_rig::GestureRig;
use crate::gesture_rig::SavedHandDef;
use crate::math::V3;
use crate::metrics::MetricsTracker;
use crate::physics::Physics;
use crate::physics::sheet_contact::Boost;
use crate::sheet::Sheet;
use crate::sheet::coarsen::{self, Collapse};
use crate::sheet::cut::{self, Cut, EdgeCrossing};
use crate::sheet::geometric::GeomStructure;
use crate::sheet::physical::PhysMesh;
use crate::sheet::refine::{self, Flip, Insertion};
use crate::sheet::regenerate::{self, Regeneration, RulingLine};
use crate::sheet::topology::NONE;

impl Sim {
    /// Makes the pending singular vertex `p`: a new S_P vertex at s̄, else the nearest vertex
    /// moved towards it.
    pub(super) fn place_pending_singular(&mut self, p: &PendingSingular) {
        // Last frame's events were read when its step returned; this one's start here.
        self.geometry.start_events_early();
        self.asleep = false;
        self.quiet_frames = 0;
        let (cap_v, cap_t) = self.mesh_capacity;
        let sp = &self.sheet.sp;
        let room = sp.num_vertices() < cap_v && sp.num_triangles() + 2 <= cap_t;
        let max_start_strain = self.cfg.geometry.insertion_max_start_strain;
        // An insertion that makes the sheet cross itself where it did not (the new vertex's
        // triangles or a flipped edge through a layer of a fold) is refused: the pass-through
        // guard would otherwise undo every following frame from a crossed start. The old
        // mesh is checked only when the new one crosses (one sweep fewer per insertion).
        let inserted = room
            .then(|| refine::insert_vertex_near(sp, p.sampled2, max_start_strain).ok())
            .flatten()
            .filter(|(ins, _)| {
                !self.proximity.any_crossing(&ins.mesh) || self.proximity.any_crossing(sp)
            })
            .and_then(|(ins, _)| {
                let Insertion {
                    mesh,
                    vertex,
                    tri_parent,
                    ..
                } = ins;
                self.adopt_mesh(mesh, &tri_parent, None, false)
                    .ok()
                    .map(|()| vertex)
            });
        match inserted {
            Some(v) => {
                self.geometry
                    .singular_at_inserted(&mut self.sheet.sp, &mut self.sheet.sg, v, p);
                self.inserted_vertices += 1;
            }
            None => {
                self.geometry.singular_by_move(
                    &mut self.sheet.sp,
                    &mut self.sheet.sg,
                    &self.fixed,
                    p,
                );
            }
        }
        self.sheet.sg.pull_positions(&self.sheet.sp);
    }

    /// Flips the edge the geometry layer found compressed in a flat region last frame
    /// ([`GeometryLayer::take_pending_flip`], [`refine::flip_edge`]), if it still exists and
    /// the flip does not make the sheet cross itself where it did not; reports it as an event.
    pub(super) fn flip_pending_edge(&mut self, f: &PendingFlip) {
        let sp = &self.sheet.sp;
        let Some(edge) = sp.topo.find_edge(f.edge[0], f.edge[1]) else {
            return;
        };
        let Ok(flip) = refine::flip_edge(sp, edge) else {
            return;
        };
        // The new diagonal cuts across a quad that is not quite planar: refused if that makes
        // a crossing with another layer (as an insertion is).
        let Flip {
            mesh,
            diagonal,
            tri_parent,
        } = flip;
        if self.adopt_uncrossed(mesh, &tri_parent, None) {
            self.geometry.edge_flipped(f, diagonal);
            self.flipped_edges += 1;
        }
    }

    /// Cuts the strip the geometry layer made last frame along its imaginary ruling
    /// (`line`: its crossed edges in line order, [`cut::cut_along`]), if the cut mesh fits the
    /// capacity the snapshots were sized for and does not make the sheet cross itself where
    /// it did not; reports it as an event.
    pub(super) fn cut_pending_strip(&mut self, line: &[EdgeCrossing]) {
        let sp = &self.sheet.sp;
        let Ok(c) = cut::cut_along(sp, line) else {
            return;
        };
        let (cap_v, cap_t) = self.mesh_capacity;
        if c.mesh.num_vertices() > cap_v || c.mesh.num_triangles() > cap_t {
            return;
        }
        // New vertices lie on old edges, so the surface is unchanged; checked all the same.
        let Cut {
            mesh,
            chain,
            added,
            tri_parent,
            ..
        } = c;
        if self.adopt_uncrossed(mesh, &tri_parent, None) {
            self.geometry.strip_cut(chain.len() as u32, added as u32);
            self.cut_strips += 1;
        }
    }

    /// Takes vertex `v` out of a flat region as the geometry layer found it last frame
    /// ([`GeometryLayer::take_pending_coarsen`], [`coarsen::collapse_vertex`]), if the collapse
    /// is still allowed on the current sheet and does not make the sheet cross itself where it
    /// did not; reports it as an event. Vertices after `v` move down by one index.
    pub(super) fn collapse_pending_vertex(&mut self, v: u32) {
        let Ok(c) = coarsen::collapse_vertex(&self.sheet.sp, v, THETA0_RAD) else {
            return;
        };
        let Collapse {
            mesh,
            removed,
            into,
            tri_parent,
            ..
        } = c;
        let into_now = coarsen::new_index(removed, into).unwrap_or(into);
        let old_to_new: Vec<u32> = (0..self.sheet.sp.num_vertices() as u32)
            .map(|v| coarsen::new_index(removed, v).unwrap_or(NONE))
            .collect();
        if self.adopt_uncrossed(mesh, &tri_parent, Some(&old_to_new)) {
            self.geometry.vertex_collapsed(removed, into_now);
            self.collapsed_vertices += 1;
        }
    }

    /// Regenerates S_P from this frame's S_G ([`regenerate::regenerate`]; the seeds' step (g),
    /// on with [`crate::geometry::GeometryConfig::regenerate_sp`]) and adopts it, unless the
    /// sheet has no curved region (S_P is then what S_G would give), the result is S_P itself,
    /// it would not fit the mesh capacity, or it makes the sheet cross itself where S_P did not.
    /// Runs at the end of an awake step, after the geometry layer: this frame's events stay, the
    /// layer's partition is made afresh on the new mesh (as after an insertion).
    pub(super) fn regenerate_sp(&mut self) {
        let sp = &self.sheet.sp;
        let g = self.geometry.frame();
        if g.tri_kind.len() != sp.num_triangles() {
            return;
        }
        let tri_curved: Vec<bool> = g.tri_kind.iter().map(|&k| k == TriKind::Curved).collect();
        if !tri_curved.contains(&true) {
            return;
        }
        let n = sp.num_vertices();
        let mut must_keep = vec![false; n];
        let mut keep = |v: u32| {
            if let Some(k) = must_keep.get_mut(v as usize) {
                *k = true;
            }
        };
        self.sheet.sg.vertices.iter().for_each(|v| keep(v.sp_index));
        g.held.iter().chain(&g.junctions).for_each(|&v| keep(v));
        let ownership = self.rig.ownership_state().0;
        ownership.iter().for_each(|o| keep(o.0));
        // Every vertex of a holding hand (its handle vertices and their neighbours), so that
        // the hand keeps them (adopt_mesh).
        for (k, d) in self.rig.hand_defs_state().iter().enumerate() {
            if ownership.iter().any(|o| usize::from(o.1) == k) {
                d.vertices.iter().for_each(|&v| keep(v));
            }
        }
        for (v, &f) in self.fixed.iter().enumerate() {
            if f {
                keep(v as u32);
            }
        }
        for b in self.physics.contact_boosts() {
            b.verts.iter().for_each(|&v| keep(v));
        }
        let rulings: Vec<RulingLine> = g
            .rulings
            .iter()
            .filter(|r| {
                r.sp_edge == u32::MAX
                    && g.regions
                        .get(r.region as usize)
                        .is_some_and(|reg| reg.kind == RegionKind::Curved)
            })
            .map(|r| RulingLine {
                region: r.region,
                a2: r.a2,
                b2: r.b2,
                a3: r.a3,
                b3: r.b3,
            })
            .collect();
        let spacing_m = self.cfg.mesh.spacing_m(self.sheet.size);
        let r = match regenerate::regenerate(sp, &tri_curved, &must_keep, &rulings, spacing_m) {
            Ok(r) => r,
            Err(e) => {
                self.regenerations.refuse(&e);
                return;
            }
        };
        if r.unchanged(sp) {
            self.regenerations.unchanged += 1;
            return;
        }
        let (cap_v, cap_t) = self.mesh_capacity;
        if r.mesh.num_vertices() > cap_v || r.mesh.num_triangles() > cap_t {
            self.regenerations.capacity += 1;
            return;
        }
        let Regeneration {
            mesh,
            old_to_new,
            tri_parent,
            ..
        } = r;
        // As an insertion: the old mesh is checked only when the new one crosses.
        if self.proximity.any_crossing(&mesh) && !self.proximity.any_crossing(&self.sheet.sp) {
            self.regenerations.crossing += 1;
            return;
        }
        if self
            .adopt_mesh(mesh, &tri_parent, Some(&old_to_new), true)
            .is_err()
        {
            self.regenerations.adoption += 1;
            return;
        }
        self.sheet.sg.pull_positions(&self.sheet.sp);
        self.regenerations.adopted += 1;
    }

    /// The common end of a flip and a cut (a connectivity change with the sheet's shape kept):
    /// starts this frame's events, wakes the sheet, and adopts `mesh` unless it crosses itself
    /// where S_P did not. Returns whether it was adopted.
    fn adopt_uncrossed(
        &mut self,
        mesh: PhysMesh,
        tri_parent: &[u32],
        old_to_new: Option<&[u32]>,
    ) -> bool {
        self.geometry.start_events_early();
        self.wake();
        // The old mesh is checked only when the new one crosses (one sweep fewer).
        if self.proximity.any_crossing(&mesh) && !self.proximity.any_crossing(&self.sheet.sp) {
            return false;
        }
        if self
            .adopt_mesh(mesh, tri_parent, old_to_new, false)
            .is_err()
        {
            return false;
        }
        self.sheet.sg.pull_positions(&self.sheet.sp);
        true
    }

    /// Replaces S_P by `mesh` (refined, flipped or cut: old vertices keep their index; or
    /// coarsened or regenerated: `old_to_new` gives each old vertex's new index, `NONE` if it
    /// is gone; `tri_parent` names each triangle's old triangle) and rebuilds what is sized by
    /// it. Nothing changes if an error is returned.
    fn adopt_mesh(
        &mut self,
        mesh: PhysMesh,
        tri_parent: &[u32],
        old_to_new: Option<&[u32]>,
        keep_hands: bool,
    ) -> Result<(), String> {
        let map = |v: u32| match old_to_new {
            Some(m) => m
                .get(v as usize)
                .copied()
                .filter(|&n| n != NONE)
                .ok_or_else(|| "a removed vertex is named".to_string()),
            None => Ok(v),
        };
        let n = mesh.num_vertices();
        let sg = GeomStructure::initial(&mesh);
        let mut sheet = Sheet {
            size: self.sheet.size,
            width_m: self.sheet.width_m,
            length_m: self.sheet.length_m,
            sp: mesh,
            sg,
        };
        sheet.sp.singular.reserve(n);
        sheet.sg.vertices.reserve(n);
        let geometry: GeometryLayer = self.geometry.remeshed(
            &sheet.sp,
            &mut sheet.sg,
            tri_parent,
            old_to_new,
            &self.material,
            self.cfg.seed,
        )?;
        let mut rig = GestureRig::new(&sheet, self.cfg.room.home_height_m());
        if keep_hands {
            // The hands hold the vertices they held (renumbered), not the ones the new mesh's
            // neighbourhoods would give: every hand whose vertices all survive keeps them.
            let fresh = rig.hand_defs_state();
            let defs: Vec<SavedHandDef> = self
                .rig
                .hand_defs_state()
                .into_iter()
                .zip(fresh)
                .map(|(mut old, fresh)| {
                    let mapped: Result<Vec<u32>, String> =
                        old.vertices.iter().map(|&v| map(v)).collect();
                    match mapped {
                        Ok(v) => {
                            old.vertices = v;
                            old
                        }
                        Err(_) => fresh,
                    }
                })
                .collect();
            rig.restore_hand_defs(&defs)?;
        }
        rig.state = self.rig.state.clone();
        let (mut ownership, suppressed, pending) = self.rig.ownership_state();
        for o in &mut ownership {
            o.0 = map(o.0)?;
        }
        rig.restore_ownership(&ownership, suppressed, pending, false)?;
        // Old vertices keep their index (or move down with the removed one's): the contact
        // boosts follow them; a boost at a removed vertex goes.
        let mut physics = Physics::new(&sheet.sp);
        let boosts: Vec<Boost> = self
            .physics
            .contact_boosts()
            .iter()
            .filter_map(|b| {
                let mut b = *b;
                for v in &mut b.verts {
                    *v = map(*v).ok()?;
                }
                Some(b)
            })
            .collect();
        physics.set_contact_boosts(&boosts, sheet.sp.num_vertices())?;
        self.physics = physics;
        self.metrics = MetricsTracker::new(&sheet.sp);
        self.geometry = geometry;
        self.rig = rig;
        self.sheet = sheet;
        if let Some(m) = old_to_new {
            remap(&mut self.fixed, m, n, false);
            remap(&mut self.kin_target, m, n, V3::zeros());
            remap(&mut self.forces, m, n, V3::zeros());
            remap(&mut self.contacts, m, n, VertexContact::default());
        }
        self.fixed.resize(n, false);
        self.kin_target.resize(n, V3::zeros());
        self.forces.resize(n, V3::zeros());
        self.contacts.resize(n, VertexContact::default());
        Ok(())
    }
}

/// `v` (one entry per old vertex) re-indexed by `old_to_new` into `n` entries; new vertices get
/// `fill`.
fn remap<T: Copy>(v: &mut Vec<T>, old_to_new: &[u32], n: usize, fill: T) {
    let mut out = vec![fill; n];
    for (&x, &j) in v.iter().zip(old_to_new) {
        if let Some(slot) = out.get_mut(j as usize) {
            *slot = x;
        }
    }
    *v = out;
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::ShapeEvent;
    use crate::math::V2;
    use crate::scenario;
    use crate::scenario_run::state_hash;
    use crate::script_runner::ScriptRunner;
    use crate::sim::{FrameOutput, SimConfig};

    /// Runs the full crumple for `frames` frames, with or without vertex insertion and edge
    /// flips.
    fn crumple(insert: bool, flip: bool, frames: u64) -> (Sim, ScriptRunner) {
        crumple_run("c5_full_crumple", insert, flip, frames)
    }

    /// [`crumple`] for a run `NAME` or `NAME@SEED` (`scenario::get_seeded`).
    fn crumple_run(run: &str, insert: bool, flip: bool, frames: u64) -> (Sim, ScriptRunner) {
        let script = scenario::get_seeded(run).unwrap();
        let mut base = SimConfig::default();
        base.geometry.insert_singular_vertices = insert;
        base.geometry.flip_compressed_edges = flip;
        let mut runner = ScriptRunner::new(&script, base.frame_rate_hz, base.room).unwrap();
        let mut sim = runner.start(base);
        let mut out = FrameOutput::default();
        for _ in 0..frames {
            assert!(runner.drive(&mut sim, &mut out));
            assert_eq!(out.stats.num_flipped, 0);
        }
        (sim, runner)
    }

    /// Plays up to `frames` more frames of `runner`'s script on `sim` and on `restored` (its
    /// saved and restored copy) side by side, asserting after each that the two states and
    /// frame statistics are identical; returns the frames played.
    fn replay_side_by_side(
        sim: &mut Sim,
        restored: &mut Sim,
        runner: &mut ScriptRunner,
        frames: usize,
    ) -> usize {
        let (mut o1, mut o2) = (FrameOutput::default(), FrameOutput::default());
        let mut cmds = Vec::new();
        for played in 0..frames {
            cmds.clear();
            if !runner.next_frame(&mut cmds) {
                return played;
            }
            for c in &cmds {
                sim.apply(*c);
                restored.apply(*c);
            }
            sim.step(&mut o1);
            restored.step(&mut o2);
            assert_eq!(state_hash(sim), state_hash(restored));
            assert_eq!(o1.stats, o2.stats);
        }
        frames
    }

    /// Every inserted vertex is a singular vertex, at its drawn position, at its foot on an
    /// edge it split across a fold (sheet/refine.rs, step 2), or nudged off it by less than
    /// half a triangle, with damage on its edges; and a good part sit at s̄ or its foot.
    /// Counted over three whole courses of the full crumple (seeds 1–3), since where a squeeze
    /// leaves s̄ next to vertices and folds is chaotic and one course can have few (the scene's
    /// own seed: 7 of 18 after its first 300 frames). Over whole runs of seeds 1–10 and the
    /// scene's own, 129 of 254 inserted vertices sit exactly at s̄ (122 of 217 with the plain
    /// Newton solver, `SolverConfig::reuse_factor` off); the test asks for 40 %.
    #[test]
    fn singular_points_get_vertices_of_their_own_at_their_drawn_positions() {
        let (mut inserted_all, mut placed_all) = (0, 0);
        for run in [
            "c5_full_crumple@1",
            "c5_full_crumple@2",
            "c5_full_crumple@3",
        ] {
            let (sim, _) = crumple_run(run, true, true, 890);
            let (inserted, exact, foot) = check_inserted_vertices(&sim);
            println!(
                "{run}: {inserted} inserted: {exact} at s̄, {foot} at its foot on a split edge"
            );
            assert!(inserted >= 3, "{run}: {inserted} vertices inserted");
            inserted_all += inserted;
            placed_all += exact + foot;
        }
        assert!(
            placed_all * 5 >= inserted_all * 2,
            "{placed_all} of {inserted_all} at s̄ or its foot"
        );
    }

    /// Checks the inserted vertices of `sim` (the previous test's doc); returns how many were
    /// inserted, how many sit exactly at s̄ and how many at its foot on a split edge.
    fn check_inserted_vertices(sim: &Sim) -> (usize, usize, usize) {
        let sp = &sim.sheet().sp;
        let lattice_nv = Sim::new(SimConfig::default()).sheet().sp.num_vertices();
        let inserted = sp.num_vertices() - lattice_nv;
        assert_eq!(sim.inserted_vertices() as usize, inserted);
        sp.topo.validate().unwrap();
        sim.sheet().sg.validate(sp).unwrap();
        let g = sim.geometry();
        assert_eq!(g.tri_region.len(), sp.num_triangles());
        assert_eq!(g.edge_dihedral_rad.len(), sp.num_edges());
        let spacing = SimConfig::default().mesh.spacing_m(sim.config().size);
        let (mut exact, mut foot) = (0, 0);
        for v in lattice_nv as u32..sp.num_vertices() as u32 {
            let s = g
                .singular
                .iter()
                .find(|s| s.sp_vertex == v)
                .expect("an inserted vertex is singular");
            let d = (s.pos2 - s.sampled2).norm();
            assert!(d < 0.5 * spacing, "{d} m off s̄");
            exact += usize::from(d < 1e-9);
            // On a split edge: between two of its neighbours, s̄ straight across from it.
            let nb = sp.topo.neighbours(v);
            let q = sp.pattern[v as usize];
            foot += usize::from(
                d >= 1e-9
                    && nb.iter().any(|&j| {
                        nb.iter().any(|&k| {
                            let (a, b) = (sp.pattern[j as usize] - q, sp.pattern[k as usize] - q);
                            let along = (b - a).normalize();
                            a.perp(&b).abs() < 1e-12 * a.norm() * b.norm()
                                && a.dot(&b) < 0.0
                                && (s.sampled2 - q).dot(&along).abs() < 1e-9
                        })
                    }),
            );
            for &j in sp.topo.neighbours(v) {
                let e = sp.topo.find_edge(v, j).unwrap() as usize;
                assert!(sp.edge_damage[e] > 0.0);
            }
        }
        // Per-vertex buffers follow the mesh.
        assert_eq!(sim.contacts().len(), sp.num_vertices());
        let (cv, ct) = sim.mesh_capacity();
        assert!(sp.num_vertices() <= cv && sp.num_triangles() <= ct);
        (inserted, exact, foot)
    }

    #[test]
    fn without_insertion_and_flips_the_mesh_keeps_its_connectivity() {
        let (sim, _) = crumple(false, false, 300);
        let lattice = Sim::new(SimConfig::default());
        assert_eq!(sim.inserted_vertices(), 0);
        assert_eq!(sim.flipped_edges(), 0);
        assert_eq!(sim.sheet().sp.triangles, lattice.sheet().sp.triangles);
        assert!(!sim.geometry().singular.is_empty());
    }

    /// The crumple's first squeeze bends a compressed lattice quad across its other diagonal
    /// (sheet/refine.rs, geometry.rs "Edge flips"): the edge is flipped at the start of the
    /// next step, announced beforehand (`refinement_pending`), reported as an event; the mesh
    /// stays valid and keeps its vertex and triangle counts.
    #[test]
    fn a_compressed_flat_edge_is_flipped_in_the_crumple() {
        // The full crumple with seed 2 flips one edge at frame 21 (one flip or none per run:
        // seeds 2, 3, 4 and 6 of 1–6 flip, the scene's own seed 5 does not; `flip_probe`).
        let script = scenario::get_seeded("c5_full_crumple@2").unwrap();
        let base = SimConfig::default();
        let mut runner = ScriptRunner::new(&script, base.frame_rate_hz, base.room).unwrap();
        let mut sim = runner.start(base);
        let lattice = Sim::new(SimConfig::default());
        let mut out = FrameOutput::default();
        let mut flipped = None;
        for _ in 0..60 {
            let announced = sim.geometry_layer().pending_flip().copied();
            assert_eq!(
                sim.refinement_pending(),
                announced.is_some() || sim.geometry_layer().pending_singular().is_some()
            );
            assert!(runner.drive(&mut sim, &mut out));
            let ev = sim.geometry().events.iter().find_map(|e| match e {
                ShapeEvent::EdgeFlipped { diagonal, .. } => Some(*diagonal),
                _ => None,
            });
            if let Some(d) = ev {
                let f = announced.expect("a flip is announced the frame before");
                let sp = &sim.sheet().sp;
                assert!(sp.topo.find_edge(f.edge[0], f.edge[1]).is_none());
                assert!(sp.topo.find_edge(d[0], d[1]).is_some());
                flipped = Some(d);
                break;
            }
        }
        assert!(
            flipped.is_some(),
            "no flip in the crumple's first 60 frames"
        );
        assert_eq!(sim.flipped_edges(), 1);
        let sp = &sim.sheet().sp;
        sp.topo.validate().unwrap();
        sim.sheet().sg.validate(sp).unwrap();
        assert_eq!(sp.num_triangles(), lattice.sheet().sp.num_triangles());
        assert_ne!(sp.triangles, lattice.sheet().sp.triangles);
    }

    /// With strip cutting on, the crumple's first strips are cut into S_P: announced the frame
    /// before, reported as an event; the new vertices lie on the cut line in the pattern and
    /// on the old surface in 3D, and the sheet stays valid.
    #[test]
    fn a_new_strip_is_cut_into_the_mesh_when_cutting_is_on() {
        let script = scenario::get("c5_full_crumple").unwrap();
        let mut base = SimConfig::default();
        base.geometry.cut_strips = true;
        let mut runner = ScriptRunner::new(&script, base.frame_rate_hz, base.room).unwrap();
        let mut sim = runner.start(base);
        let mut out = FrameOutput::default();
        let mut cut = None;
        for _ in 0..120 {
            let announced = sim.geometry_layer().pending_cut().map(<[_]>::to_vec);
            if announced.is_some() {
                assert!(sim.refinement_pending());
            }
            let before = sim.sheet().sp.clone();
            assert!(runner.drive(&mut sim, &mut out));
            let ev = sim.geometry().events.iter().find_map(|e| match e {
                ShapeEvent::StripCut {
                    chain_vertices,
                    added_vertices,
                } => Some((*chain_vertices, *added_vertices)),
                _ => None,
            });
            if let Some((chain, added)) = ev {
                let line = announced.expect("a cut is announced the frame before");
                cut = Some((before, line, chain, added));
                break;
            }
        }
        let (before, line, chain, added) =
            cut.expect("no strip cut in the crumple's first 120 frames");
        assert_eq!(sim.cut_strips(), 1);
        assert!(added >= 1 && chain >= added);
        let sp = &sim.sheet().sp;
        sp.topo.validate().unwrap();
        sim.sheet().sg.validate(sp).unwrap();
        // Unless a singular vertex was inserted too, the new vertices are the last ones.
        let nv_old = before.num_vertices();
        let cut_points: Vec<V2> = line
            .iter()
            .map(|c| {
                let [a, b] = c.edge.map(|v| before.pattern[v as usize]);
                a + (b - a) * c.u
            })
            .collect();
        let on_line = |p: V2| {
            cut_points.windows(2).any(|w| {
                let d = w[1] - w[0];
                (p - w[0]).perp(&d).abs() <= 1e-12 * d.norm() + 1e-15
            })
        };
        let new_on_line = (nv_old..sp.num_vertices())
            .filter(|&v| on_line(sp.pattern[v]))
            .count();
        assert_eq!(
            new_on_line as u32, added,
            "every new cut vertex is on the line"
        );
        assert_eq!(&sp.pattern[..nv_old], &before.pattern[..]);
        assert!((sp.total_mass_kg() - before.total_mass_kg()).abs() < 1e-12);
        assert_eq!(sim.contacts().len(), sp.num_vertices());
        // The sheet goes on crumpling.
        for _ in 0..60 {
            assert!(runner.drive(&mut sim, &mut out));
            assert!(
                out.stats.max_strain < 0.1,
                "frame {} strain {}",
                sim.frame(),
                out.stats.max_strain
            );
        }
    }

    /// A sheet saved with a strip cut pending restores it and continues bit-identically
    /// through the cut.
    #[test]
    fn a_pending_strip_cut_is_saved_and_replays_exactly() {
        let script = scenario::get("c5_full_crumple").unwrap();
        let mut base = SimConfig::default();
        base.geometry.cut_strips = true;
        let mut runner = ScriptRunner::new(&script, base.frame_rate_hz, base.room).unwrap();
        let mut sim = runner.start(base);
        let mut o1 = FrameOutput::default();
        while sim.geometry_layer().pending_cut().is_none() {
            assert!(runner.drive(&mut sim, &mut o1));
            assert!(sim.frame() < 120, "no strip to cut");
        }
        let mut restored = Sim::restore(*sim.config(), &sim.save()).unwrap();
        assert_eq!(
            restored.geometry_layer().pending_cut(),
            sim.geometry_layer().pending_cut()
        );
        assert_eq!(
            replay_side_by_side(&mut sim, &mut restored, &mut runner, 40),
            40
        );
        assert!(sim.cut_strips() >= 1);
        assert_eq!(sim.cut_strips(), restored.cut_strips());
    }

    /// A sheet held at both short edges is arched (front edge slid halfway to the back) and
    /// let go onto the table: the arch's first strips are cut into S_P, and once the sheet
    /// lies flat and still again, coarsening takes every cut vertex out.
    const ARCH_AND_RELEASE: &str = include_str!("../../tests/fixtures/arch_and_release.toml");

    fn arch_and_release(coarsen: bool) -> (Sim, ScriptRunner) {
        let script = crate::script::Script::parse(ARCH_AND_RELEASE).unwrap();
        let mut base = SimConfig::default();
        base.geometry.cut_strips = true;
        base.geometry.coarsen_flat_regions = coarsen;
        let runner = ScriptRunner::new(&script, base.frame_rate_hz, base.room).unwrap();
        let sim = runner.start(base);
        (sim, runner)
    }

    #[test]
    fn cut_vertices_are_taken_out_once_the_sheet_is_flat_again() {
        let (mut sim, mut runner) = arch_and_release(true);
        let lattice = sim.sheet().sp.clone();
        let mut out = FrameOutput::default();
        let (mut most, mut events) = (0, 0);
        loop {
            let announced = sim.geometry_layer().pending_coarsen();
            if announced.is_some() {
                assert!(sim.refinement_pending());
            }
            let nv = sim.sheet().sp.num_vertices();
            if !runner.drive(&mut sim, &mut out) {
                break;
            }
            most = most.max(sim.sheet().sp.num_vertices());
            assert!(
                out.stats.max_strain < 0.1,
                "strain {}",
                out.stats.max_strain
            );
            for e in &sim.geometry().events {
                if let ShapeEvent::VertexCollapsed { removed, .. } = *e {
                    assert_eq!(Some(removed), announced, "announced the frame before");
                    assert_eq!(sim.sheet().sp.num_vertices(), nv - 1);
                    events += 1;
                }
            }
        }
        assert!(sim.cut_strips() >= 1, "no strip cut");
        assert!(most > lattice.num_vertices(), "the cuts added no vertex");
        assert_eq!(events, sim.collapsed_vertices());
        // Every vertex a cut added is gone: the lattice's vertices remain, unmoved in the
        // pattern, with as many triangles as the lattice has.
        let sp = &sim.sheet().sp;
        assert_eq!(sp.num_vertices(), lattice.num_vertices());
        assert_eq!(sp.pattern, lattice.pattern);
        assert_eq!(sp.num_triangles(), lattice.num_triangles());
        assert_eq!(
            sim.collapsed_vertices() as usize,
            most - lattice.num_vertices()
        );
        sp.topo.validate().unwrap();
        sim.sheet().sg.validate(sp).unwrap();
        assert!((sp.total_mass_kg() - lattice.total_mass_kg()).abs() < 1e-12);
        assert_eq!(sim.contacts().len(), sp.num_vertices());
        assert_eq!(sim.geometry().tri_region.len(), sp.num_triangles());
        // Without coarsening the same gesture keeps them.
        let (mut kept, mut runner) = arch_and_release(false);
        while runner.drive(&mut kept, &mut out) {}
        assert!(kept.cut_strips() >= 1);
        assert_eq!(kept.collapsed_vertices(), 0);
        assert!(kept.sheet().sp.num_vertices() > lattice.num_vertices());
    }

    /// A sheet saved with a vertex waiting to be taken out restores it and continues
    /// bit-identically through the collapse.
    #[test]
    fn a_pending_coarsening_is_saved_and_replays_exactly() {
        let (mut sim, mut runner) = arch_and_release(true);
        let mut o1 = FrameOutput::default();
        while sim.geometry_layer().pending_coarsen().is_none() {
            assert!(runner.drive(&mut sim, &mut o1), "nothing to take out");
        }
        let mut restored = Sim::restore(*sim.config(), &sim.save()).unwrap();
        assert_eq!(
            restored.geometry_layer().pending_coarsen(),
            sim.geometry_layer().pending_coarsen()
        );
        replay_side_by_side(&mut sim, &mut restored, &mut runner, 60);
        assert!(sim.collapsed_vertices() >= 1);
        assert_eq!(sim.collapsed_vertices(), restored.collapsed_vertices());
    }

    /// A refined sheet saved and restored continues bit-identically (the insertion rebuilds
    /// what a restore builds).
    #[test]
    fn a_refined_sheet_restores_and_continues_exactly() {
        let (mut sim, mut runner) = crumple(true, true, 260);
        assert!(sim.inserted_vertices() > 0);
        let mut restored = Sim::restore(*sim.config(), &sim.save()).unwrap();
        replay_side_by_side(&mut sim, &mut restored, &mut runner, 80);
    }
}
