//! # Solving one substep, and solving it again when it ends badly (the parent module's sections
//! "A substep solved again" and "A substep solved as shorter ones"), and the obstacles' depth
//! limit after it.

use super::*;

impl Sim {
    /// A substep (its report `r`) that turned a triangle over, or that stalled or pinned and
    /// left the sheet strained beyond [`HOLD_BACK_STRAIN`] and more than at its start, is
    /// solved again from its start at rest with the hands back where the frame started
    /// (module doc, "A substep solved again"). The second solve stands if it turns nothing over
    /// and leaves at most [`HOLD_BACK_GAIN`] of the first one's strain (after a turn-over: no
    /// more than the first, or [`HOLD_BACK_STRAIN`]); else the first stands, hands and all.
    /// `r` becomes the report of the solve that stands. Returns `None` if nothing was tried,
    /// else whether the second solve stood and the other solve's report.
    pub(super) fn solve_substep_again(
        &mut self,
        frac: f64,
        h: f64,
        r: &mut SubstepReport,
    ) -> Option<(bool, SubstepReport)> {
        let sp = &self.sheet.sp;
        let start = self.physics.substep_start();
        let turned = crate::physics::turns_a_triangle_over(sp, start, &sp.pos);
        if !(turned || r.stalled || r.pinned) {
            return None;
        }
        let first_strain = crate::metrics::max_strain(sp, &sp.pos);
        let strained =
            first_strain > HOLD_BACK_STRAIN && first_strain > crate::metrics::max_strain(sp, start);
        if !turned && !strained {
            return None;
        }
        self.stalled_pos.clone_from(&sp.pos);
        self.stalled_vel.clone_from(&sp.vel);
        let hands = self.rig.state.hands;
        self.physics.restore_substep_start(&mut self.sheet.sp);
        // The substep's start with its momentum, for a split after this (the second solve
        // starts at rest and overwrites the physics' copy).
        self.split_start_pos.clone_from(&self.sheet.sp.pos);
        self.split_start_vel.clone_from(&self.sheet.sp.vel);
        self.split_start_saved = true;
        self.sheet.sp.vel.fill(V3::zeros());
        self.rig.undo_frame_motion();
        self.fill_held(frac);
        let second = self.solve_substep(h);
        let sp = &mut self.sheet.sp;
        let start = self.physics.substep_start();
        let strain = crate::metrics::max_strain(sp, &sp.pos);
        let stands = !crate::physics::turns_a_triangle_over(sp, start, &sp.pos)
            && if turned {
                strain <= first_strain.max(HOLD_BACK_STRAIN)
            } else {
                strain <= HOLD_BACK_GAIN * first_strain
            };
        if stands {
            return Some((true, std::mem::replace(r, second)));
        }
        // The second solve did no better: the first stands.
        sp.pos.clone_from(&self.stalled_pos);
        sp.vel.clone_from(&self.stalled_vel);
        self.rig.state.hands = hands;
        self.fill_held(frac);
        Some((false, second))
    }

    /// A substep (its report `r`, from `frac0` to `frac` of the frame, `h` seconds) that
    /// turned a triangle over, or whose solve ended short of its solution — at the iteration
    /// cap, stalled or pinned — and left the sheet strained beyond [`HOLD_BACK_STRAIN`] and
    /// more than at its start, is solved again from its start as `n` substeps of `h / n` for
    /// each `n` of [`SPLIT_FACTORS`] in turn, the hands' targets interpolated between (module
    /// doc, "A substep solved as shorter ones"). A split counts if none of its substeps turns
    /// a triangle over or recovers and it leaves at most [`HOLD_BACK_GAIN`] of the strain of
    /// the best solve so far (after a turn-over, the first solve counts with the larger of its
    /// strain and [`HOLD_BACK_STRAIN`], divided by [`HOLD_BACK_GAIN`]). The ladder stops at the
    /// first split that counts and leaves no more than [`HOLD_BACK_STRAIN`]; if none counts and
    /// a held vertex starts away from its hand's hold, it is climbed again with that offset
    /// faded out over the split. The best split that counted stands, with the flipped-triangle
    /// reference advanced to its last substep's start; if none counted, the first solve
    /// stands. `r` becomes the report of what stands (a split's substeps summed). Returns
    /// `None` if nothing was tried, else whether a split stood and the summed report of the
    /// solves that did not.
    pub(super) fn solve_substep_split(
        &mut self,
        frac0: f64,
        frac: f64,
        h: f64,
        r: &mut SubstepReport,
    ) -> Option<(bool, SubstepReport)> {
        if r.recovered {
            return None;
        }
        let sp = &self.sheet.sp;
        let start = self.physics.substep_start();
        let first_turned = crate::physics::turns_a_triangle_over(sp, start, &sp.pos);
        let short = r.capped || r.stalled || r.pinned;
        if !first_turned && !short {
            return None;
        }
        let first_strain = crate::metrics::max_strain(sp, &sp.pos);
        let strained = short
            && first_strain > HOLD_BACK_STRAIN
            && first_strain > crate::metrics::max_strain(sp, start);
        if !first_turned && !strained {
            return None;
        }
        let sp = &mut self.sheet.sp;
        // The first solve is the best so far.
        self.split_best_pos.clone_from(&sp.pos);
        self.split_best_vel.clone_from(&sp.vel);
        if !self.split_start_saved {
            self.physics.restore_substep_start(sp);
            self.split_start_pos.clone_from(&sp.pos);
            self.split_start_vel.clone_from(&sp.vel);
        }
        self.split_start_normals.clear();
        self.split_start_normals
            .extend_from_slice(self.metrics.previous_normals());
        // Where a held vertex is away from where its hand held it at the substep's start (the
        // hand slipped or took a new grip since), a second ladder moves it there in equal parts
        // over the split instead of in its first substep.
        self.fill_held(frac0);
        self.split_jump.clear();
        self.split_jump.extend(
            self.split_start_pos
                .iter()
                .zip(&self.kin_target)
                .zip(&self.fixed)
                .map(|((x, t), &f)| if f { x - t } else { V3::zeros() }),
        );
        let mut discarded = SubstepReport::default();
        let mut best: Option<SubstepReport> = None;
        // A first solve that turned a triangle over does not count: a split counts if it
        // turns nothing and strains no more than it, or than HOLD_BACK_STRAIN.
        let mut best_strain = if first_turned {
            first_strain.max(HOLD_BACK_STRAIN) / HOLD_BACK_GAIN
        } else {
            first_strain
        };
        let jumped = self
            .split_jump
            .iter()
            .any(|j| j.norm() > crate::handles::SAME_POSE_M);
        for (fade, n) in SPLIT_FACTORS
            .iter()
            .map(|&n| (false, n))
            .chain(SPLIT_FACTORS.iter().map(|&n| (true, n)))
        {
            if fade && (best.is_some() || !jumped) {
                break;
            }
            let sp = &mut self.sheet.sp;
            sp.pos.clone_from(&self.split_start_pos);
            sp.vel.clone_from(&self.split_start_vel);
            self.metrics.set_previous_normals(&self.split_start_normals);
            let mut split = SubstepReport::default();
            let mut turned = false;
            for k in 1..=n {
                let part = f64::from(k) / f64::from(n);
                self.fill_held(frac0 + (frac - frac0) * part);
                if fade {
                    for (t, j) in self.kin_target.iter_mut().zip(&self.split_jump) {
                        *t += j * (1.0 - part);
                    }
                }
                split.add(&self.solve_substep(h / f64::from(n)));
                let sp = &self.sheet.sp;
                turned = crate::physics::turns_a_triangle_over(
                    sp,
                    self.physics.substep_start(),
                    &sp.pos,
                );
                if turned || split.recovered {
                    break;
                }
                if k < n {
                    self.limit_penetration();
                    // Orientation continuity at the split's own resolution: the next
                    // substep's turn-over is measured from here.
                    self.metrics.reset_normals(&self.sheet.sp);
                }
            }
            let sp = &self.sheet.sp;
            let strain = crate::metrics::max_strain(sp, &sp.pos);
            if turned || split.recovered || strain > HOLD_BACK_GAIN * best_strain {
                discarded.add(&split);
                continue;
            }
            if let Some(b) = best.replace(split) {
                discarded.add(&b);
            }
            best_strain = strain;
            self.split_best_pos.clone_from(&sp.pos);
            self.split_best_vel.clone_from(&sp.vel);
            self.split_best_normals.clear();
            self.split_best_normals
                .extend_from_slice(self.metrics.previous_normals());
            if strain <= HOLD_BACK_STRAIN {
                break;
            }
        }
        let sp = &mut self.sheet.sp;
        sp.pos.clone_from(&self.split_best_pos);
        sp.vel.clone_from(&self.split_best_vel);
        let Some(b) = best else {
            // No split did better: the first solve stands.
            self.metrics.set_previous_normals(&self.split_start_normals);
            self.fill_held(frac);
            return Some((false, discarded));
        };
        self.metrics.set_previous_normals(&self.split_best_normals);
        if !self.frame_normals_saved {
            self.frame_start_normals
                .clone_from(&self.split_start_normals);
            self.frame_normals_saved = true;
        }
        discarded.add(r);
        *r = b;
        Some((true, discarded))
    }

    /// One physics substep of `h` seconds towards the kinematic targets filled in.
    pub(super) fn solve_substep(&mut self, h: f64) -> SubstepReport {
        self.physics.substep(
            &mut self.sheet.sp,
            Kinematics {
                fixed: &self.fixed,
                target: &self.kin_target,
            },
            &self.obstacles,
            &self.params,
            &self.cfg.solver,
            h,
        )
    }

    /// The contact depth limit (collision.rs "Depth limit") after a substep, without turning
    /// a facet over: putting a deep vertex back at the limit depth moves it along the plane
    /// normal, which can turn a triangle standing edge-on against the plane past 90° from its
    /// orientation at the end of the previous frame; the vertices of a triangle the limit
    /// would turn over keep their simulated positions, a little deeper. So do those of a
    /// triangle the limit would strain beyond [`HOLD_BACK_STRAIN`], and more than the solve
    /// left it: a vertex the solve left centimetres deep, put back at the limit, stretches its
    /// edges to the neighbours that stayed (docs/decisions.md, "Smaller rules and the runs that
    /// found them").
    pub(super) fn limit_penetration(&mut self) {
        let sp = &mut self.sheet.sp;
        self.pre_limit_pos.clone_from(&sp.pos);
        if self
            .obstacles
            .limit_penetration(&mut sp.pos, &mut sp.vel, &self.fixed)
            == 0
        {
            return;
        }
        let normal = |p: &[V3], t: &[u32; 3]| {
            let x = t.map(|i| p[i as usize]);
            (x[1] - x[0]).cross(&(x[2] - x[0]))
        };
        // Restoring a vertex can turn over or strain another triangle that shares it; a few
        // passes settle it (each pass only restores, so it ends).
        for _ in 0..4 {
            let mut restored = false;
            for (k, t) in sp.triangles.iter().enumerate() {
                if t.iter()
                    .all(|&i| sp.pos[i as usize] == self.pre_limit_pos[i as usize])
                {
                    continue;
                }
                let prev = self.metrics.previous_normal(k);
                let turned = normal(&sp.pos, t).dot(&prev) < 0.0
                    && normal(&self.pre_limit_pos, t).dot(&prev) >= 0.0;
                let strained = || {
                    let at = |p: &[V3]| t.map(|i| p[i as usize]);
                    let strain = crate::metrics::triangle_strain(sp, k, at(&sp.pos));
                    strain > HOLD_BACK_STRAIN
                        && strain > crate::metrics::triangle_strain(sp, k, at(&self.pre_limit_pos))
                };
                if turned || strained() {
                    for &i in t {
                        sp.pos[i as usize] = self.pre_limit_pos[i as usize];
                    }
                    restored = true;
                }
            }
            if !restored {
                break;
            }
        }
    }
}
