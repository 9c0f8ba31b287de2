//! # Backward Euler by Newton's method with a sparse Cholesky solve
//!
//! The seeds' integrator is "implicit integration and we usually obtain convergence after 10 to
//! 100 iterations" (P 440–441, T 712), measured at 4–11 iterations on average (Table V, digest
//! §6.2). Here each substep minimizes the incremental potential E of [`crate::physics`]:
//!
//! ```text
//! x ← x_n + h v_n  (free vertices),  x_k ← target_k  (kinematic vertices)
//! repeat ≤ iterations (factorized; ≤ as many again reusing a factorization):
//!     g = ∇E(x),  H = PSD approximation of ∇²E(x)        (membrane: clamped geometric term;
//!                                                        hinges and friction: Gauss–Newton)
//!     solve H Δ = −g  on the free vertices               (faer sparse Cholesky, fixed pattern;
//!                                                        sheet–sheet contact pairs' rank-one
//!                                                        terms by the Woodbury identity;
//!                                                        H and its factor kept from the last
//!                                                        iteration while its steps shrink,
//!                                                        "Reused factorizations")
//!     α = 1; while E(x + αΔ) > E(x) + 10⁻⁴ α gᵀΔ
//!                  or a triangle of x + αΔ is turned by > 90° from x_n: α ← α/2   (≤ 8 halvings)
//!     (no acceptable α: retry with H + ρ M/h², ρ = 10, 1000 — Levenberg–Marquardt)
//!     (still none: pin the free vertices of the triangles the last trial turned over, go on)
//!     x ← x + αΔ;  δ_k = max_i |αΔ_i| (this iteration's step, largest over the vertices)
//!     stop when δ_k < tolerance,
//!       or when Θ/(1 − Θ)·δ_k < tolerance with Θ = δ_k / δ_{k−1} < ½
//!       (two full steps in a row: α = 1, no damping; "Stopping" below)
//! v = (x − x_n) / h
//! ```
//!
//! H is positive definite on the free vertices (mass term m/h² plus PSD element terms), so the
//! Cholesky factorization exists and Δ is a descent direction; the Armijo line search makes
//! every accepted step decrease E, which is what keeps large, clamped handle motions from
//! exploding. The line search also refuses steps that turn a triangle over with respect to
//! the start of the substep (more than 90° in one substep, an angular speed the sheet never
//! reaches at 200 frames/s except in a numerical blow-up); together with the collapse barrier
//! of the membrane this keeps the mesh from inverting. An iteration cap below convergence (the
//! usual real-time setting) still returns a state of lower energy than the start.
//!
//! **Stopping** (impl. choice). The tolerance bounds how far the returned x may lie from the
//! minimizer, i.e. the velocity error `(x − x*)/h`. Our Hessian is an approximation (the
//! membrane's geometric term clamped, hinges and friction Gauss–Newton, contact pairs past the
//! coupling limit diagonal only), so the iterations converge linearly, not quadratically:
//! traced over C5 and C2, each full step is 0.15–0.5 of the one before. With a contraction
//! Θ < 1 the distance still to go after a step δ_k is at most about Θ/(1 − Θ)·δ_k (the
//! geometric series of the steps to come), so the solve stops once that estimate is below the
//! tolerance, as well as when the step itself is: stopping on the step alone
//! (`SolverConfig::stop_on_error_estimate = false`, a bench-report axis) runs one more
//! iteration to learn what the estimate already said. The estimate is used only between two
//! full Newton steps (no halving, no damping, no pinning in between) with Θ < ½, both solved
//! with a fresh factorization or both with the same reused one, since a fresh step followed by
//! a reused one contracts faster than the reused ones after it; slower or damped iterations
//! stop on the step. It saves 2–18 % of the iterations at the same accuracy
//! (docs/decisions.md, "Stopping on the error estimate"). Unit test: each substep of a swinging
//! sheet stops sooner and within 2× the tolerance of the step rule's iterate.
//!
//! **Reused factorizations** (impl. choice; a modified Newton method). Our H is an
//! approximation anyway (above), so the iterations converge linearly, and late in a substep,
//! when the steps are small, the H of the iteration before is hardly a worse one. A numeric
//! factorization with its Woodbury terms and the assembly of H were about half of a crumple's
//! frame (`perf`, C5 and S4). So after a full step (α = 1, no damping) the next iteration
//! assembles only the gradient and solves with the factor it already has
//! ([`BlockSystem::solve_again`]: the previous H, its contact pairs' rank-one terms and their
//! capacitance factor included), and it keeps doing so while each such step is shorter than
//! `REUSE_MAX_CONTRACTION` of the one before; a slower step, any halving, damping or
//! pinning, and the next iteration factorizes afresh. A reused step the line search refuses
//! at α = 1, or that is not a descent direction, is not halved: H is assembled and factorized
//! at the same iterate and the iteration goes on as usual. Every accepted step still lowers
//! E (the Armijo test is the same), so the method converges to the same minimizer; it takes
//! more iterations, each much cheaper. The cap [`SolverConfig::iterations`] counts the
//! factorized iterations, and the reused ones may add as many again
//! (`REUSE_ITERATION_FACTOR`): capping all iterations at 10 left more substeps unconverged
//! than the plain method. The crumples' median frame falls by a fifth to a quarter
//! (docs/decisions.md, "Reused factorizations"). `SolverConfig::reuse_factor = false` restores
//! the plain method (for the bench report's comparison rows).
//!
//! **Pinning** (impl. choice). The line search scales the whole step, so one triangle that
//! every trial would turn over stops the solve for the entire sheet, and the sheet stays where
//! it stalled — held vertices at their targets, their free neighbours behind — with the
//! triangles between them stretched. So when the Levenberg–Marquardt retries fail too, the
//! free vertices of the triangles that the shortest damped trial turns over are held where
//! they are for the rest of the substep, and the next iteration solves for the other vertices,
//! which then follow the hands (docs/decisions.md, "Pinning"). A stall whose shortest trial
//! turns nothing over (a failure of the energy test alone) still ends the substep. Frames that
//! never stall are unchanged (no seed scene pins a vertex). Regression test:
//! `sim-core/tests/stalled_substeps.rs`. Not a cure for every stall: a pinned vertex held
//! where the predictor carried it can still stretch a small triangle a hand holds by its
//! other corner, so a substep that stalls or pins and leaves the sheet strained is solved
//! again from rest with the hands held back (`crate::sim`, "A substep solved again"); the
//! solve reports the stall ([`SubstepReport::stalled`]).

use crate::collision::{
    CONTACT_SKIN_M, HARD_CONTACT_FACTOR, MAX_PENETRATION_M, Obstacles, STICK_SPEED_M_S,
    friction_f0, friction_f1, penalty_stiffness,
};
use crate::math::{GRAVITY_M_S2, M3, V3};
use crate::physics::sparse::BlockSystem;
use crate::physics::{
    Kinematics, PhysParams, SolverConfig, SubstepFrame, SubstepReport, bending, membrane,
};
use crate::sheet::physical::PhysMesh;

/// Local vertex pairs of a triangle's off-diagonal blocks.
const TRI_PAIRS: [(usize, usize); 3] = [(0, 1), (0, 2), (1, 2)];
/// Local vertex pairs of a hinge's off-diagonal blocks.
const HINGE_PAIRS: [(usize, usize); 6] = [(0, 1), (0, 2), (0, 3), (1, 2), (1, 3), (2, 3)];
/// Maximal line-search halvings per direction.
const MAX_HALVINGS: u32 = 8;
/// Levenberg–Marquardt retries when the line search fails along the Newton direction.
const MAX_LM_RETRIES: u32 = 2;
/// Largest contraction between two full Newton steps from which the remaining error is
/// estimated (module doc, "Stopping"); slower iterations stop on the step alone.
const MAX_CONTRACTION: f64 = 0.5;
/// A step solved with a reused factorization must shrink below this fraction of the step
/// before it for the next iteration to reuse the factorization again (module doc, "Reused
/// factorizations").
const REUSE_MAX_CONTRACTION: f64 = 0.5;
/// Iterations per substep, reused ones included, as a multiple of the cap on factorized
/// iterations ([`SolverConfig::iterations`]) when factorizations are reused.
const REUSE_ITERATION_FACTOR: u32 = 2;

/// Newton solver workspace for one mesh.
#[derive(Debug)]
pub struct NewtonSolver {
    sys: BlockSystem,
    tri_off: Vec<[(u32, bool); 3]>,
    hinge_off: Vec<[(u32, bool); 6]>,
    x_hat: Vec<V3>,
    grad: Vec<V3>,
    x_trial: Vec<V3>,
    diag_fixed: Vec<f64>,
    /// Vertices held in place for the rest of the substep: the kinematic ones, and free ones
    /// pinned where a stalled line search would turn their triangle over (module doc).
    held: Vec<bool>,
    /// Per hinge: its dihedral angle at the line search's last trial (`x_trial`), and at the
    /// current iterate once that trial was accepted. The assembly that follows an accepted
    /// step reads the angle instead of computing it again (the same bits:
    /// [`bending::dihedral_grad_with`]); a tenth of the assembly's time in the crumples was that
    /// `atan2`.
    theta_trial: Vec<f64>,
    theta_pos: Vec<f64>,
}

/// Per-substep scalars.
#[derive(Clone, Copy)]
struct Ctx<'a> {
    h: f64,
    frame: &'a SubstepFrame,
    obstacles: &'a Obstacles,
    params: &'a PhysParams,
}

impl NewtonSolver {
    /// Workspace and symbolic factorization for a mesh.
    pub fn new(mesh: &PhysMesh) -> Self {
        let n = mesh.num_vertices();
        let mut pairs = Vec::new();
        for e in &mesh.topo.edges {
            pairs.push(e.v);
        }
        for h in &mesh.hinges {
            pairs.push([h.v[2], h.v[3]]);
        }
        let sys = BlockSystem::new(n, pairs);
        let tri_off = mesh
            .triangles
            .iter()
            .map(|t| TRI_PAIRS.map(|(a, b)| sys.off_block(t[a], t[b])))
            .collect();
        let hinge_off = mesh
            .hinges
            .iter()
            .map(|h| HINGE_PAIRS.map(|(a, b)| sys.off_block(h.v[a], h.v[b])))
            .collect();
        Self {
            sys,
            tri_off,
            hinge_off,
            x_hat: vec![V3::zeros(); n],
            grad: vec![V3::zeros(); n],
            x_trial: vec![V3::zeros(); n],
            diag_fixed: vec![1.0; n],
            held: vec![false; n],
            theta_trial: vec![0.0; mesh.hinges.len()],
            theta_pos: vec![0.0; mesh.hinges.len()],
        }
    }

    /// Numeric factorizations done so far.
    pub fn factorizations(&self) -> u64 {
        self.sys.factorizations
    }

    /// Non-zeros of the system matrix and of its Cholesky factor.
    pub fn sparsity(&self) -> (usize, usize) {
        (self.sys.nnz(), self.sys.factor_nnz())
    }

    /// One backward-Euler substep.
    pub fn substep(
        &mut self,
        mesh: &mut PhysMesh,
        frame: &SubstepFrame,
        kin: Kinematics<'_>,
        obstacles: &Obstacles,
        params: &PhysParams,
        cfg: &SolverConfig,
        h: f64,
    ) -> SubstepReport {
        let ctx = Ctx {
            h,
            frame,
            obstacles,
            params,
        };
        let n = mesh.num_vertices();
        for i in 0..n {
            self.x_hat[i] = frame.x_n[i] + frame.v_n[i] * h;
            mesh.pos[i] = if kin.fixed[i] {
                kin.target[i]
            } else {
                self.x_hat[i]
            };
            self.diag_fixed[i] = mesh.mass_kg[i] / (h * h);
        }
        // A predictor that turns a triangle over (fast spin or a kinematic jump) would start the
        // solve beyond the collapse barrier; start the free vertices at rest instead.
        if crate::physics::turns_a_triangle_over(mesh, &frame.x_n, &mesh.pos) {
            for i in 0..n {
                if !kin.fixed[i] {
                    mesh.pos[i] = frame.x_n[i];
                }
            }
        }
        self.sys
            .set_low_rank_limit(cfg.contact_coupling_pairs as usize);
        let mut report = SubstepReport::default();
        let mut e0 = f64::NAN;
        let mut prev_step_m: Option<(f64, bool)> = None;
        let mut last_step_m: Option<f64> = None;
        let mut reuse_next = false;
        // `held` is moved out for the loop (the assembly borrows the solver mutably).
        let mut held = std::mem::take(&mut self.held);
        held.copy_from_slice(kin.fixed);
        // The hinge angles at the current iterate, once a line search has measured them there.
        let mut theta_pos = std::mem::take(&mut self.theta_pos);
        let mut theta_known = false;
        // The cap counts factorized iterations; reused ones are cheap and add at most as
        // many again (module doc, "Reused factorizations").
        let max_iterations = if cfg.reuse_factor {
            REUSE_ITERATION_FACTOR * cfg.iterations
        } else {
            cfg.iterations
        };
        'newton: loop {
            if report.iterations - report.reused_iterations >= cfg.iterations
                || report.iterations >= max_iterations
            {
                report.capped = true;
                break;
            }
            report.iterations += 1;
            let known = theta_known.then_some(theta_pos.as_slice());
            let e = if reuse_next {
                self.assemble::<false>(mesh, &held, ctx, e0.is_nan(), known)
            } else {
                self.assemble::<true>(mesh, &held, ctx, e0.is_nan(), known)
            };
            let e = if e0.is_nan() { e } else { e0 };
            // Newton step; if the line search finds no acceptable step along it (the PSD
            // approximation underestimated the curvature), retry with Levenberg–Marquardt
            // damping (H + ρ M/h²), which shortens the step towards scaled gradient descent.
            let mut reg = 0.0;
            let mut reuse = reuse_next;
            let mut attempt = 0;
            loop {
                for (i, &fixed) in held.iter().enumerate() {
                    let g = if fixed { V3::zeros() } else { -self.grad[i] };
                    self.sys.rhs[3 * i..3 * i + 3].copy_from_slice(g.as_slice());
                }
                if reuse {
                    if !self.sys.solve_again() {
                        reuse = false;
                        self.assemble::<true>(mesh, &held, ctx, false, known);
                        continue;
                    }
                } else {
                    report.factorizations += 1;
                    let solved = self.sys.factorize_and_solve(&held, &self.diag_fixed, reg);
                    if solved.is_err() {
                        report.recovered = true;
                        break 'newton;
                    }
                }
                let mut slope = 0.0;
                let mut max_step: f64 = 0.0;
                for (i, _) in held.iter().enumerate().filter(|(_, f)| !**f) {
                    let d = V3::new(
                        self.sys.rhs[3 * i],
                        self.sys.rhs[3 * i + 1],
                        self.sys.rhs[3 * i + 2],
                    );
                    slope += self.grad[i].dot(&d);
                    max_step = max_step.max(d.amax());
                }
                if !(slope.is_finite() && max_step.is_finite()) {
                    report.recovered = true;
                    break 'newton;
                }
                if slope >= 0.0 {
                    if reuse {
                        reuse = false;
                        self.assemble::<true>(mesh, &held, ctx, false, known);
                        continue;
                    }
                    // Converged to round-off: no descent left.
                    break 'newton;
                }
                let mut alpha = 1.0;
                for _ in 0..=MAX_HALVINGS {
                    for (i, &fixed) in held.iter().enumerate() {
                        self.x_trial[i] = if fixed {
                            mesh.pos[i]
                        } else {
                            mesh.pos[i]
                                + V3::new(
                                    self.sys.rhs[3 * i],
                                    self.sys.rhs[3 * i + 1],
                                    self.sys.rhs[3 * i + 2],
                                ) * alpha
                        };
                    }
                    if !Self::flips_new(mesh, &frame.x_n, &mesh.pos, &self.x_trial) {
                        let e_new = Self::energy(
                            mesh,
                            &self.x_trial,
                            &held,
                            &self.x_hat,
                            ctx,
                            &mut self.theta_trial,
                        );
                        if e_new <= e + 1e-4 * alpha * slope {
                            mesh.pos.copy_from_slice(&self.x_trial);
                            std::mem::swap(&mut theta_pos, &mut self.theta_trial);
                            theta_known = true;
                            e0 = e_new;
                            let step_m = alpha * max_step;
                            if reuse {
                                report.reused_iterations += 1;
                            }
                            if step_m < cfg.tolerance_m {
                                break 'newton;
                            }
                            // A full Newton step (no halving, no damping) after another one
                            // of the same kind (both solved with a fresh factorization, or
                            // both with the same reused one): their ratio is the contraction
                            // Θ, and what is left to go is about Θ/(1 − Θ) of this step
                            // (module doc, "Stopping").
                            let full = alpha == 1.0 && reg == 0.0;
                            if full
                                && cfg.stop_on_error_estimate
                                && let Some((prev_m, prev_reused)) = prev_step_m
                                && prev_reused == reuse
                            {
                                let theta = step_m / prev_m;
                                if theta < MAX_CONTRACTION
                                    && theta / (1.0 - theta) * step_m < cfg.tolerance_m
                                {
                                    break 'newton;
                                }
                            }
                            prev_step_m = full.then_some((step_m, reuse));
                            // Reuse this factorization next while the steps it gives
                            // shrink fast enough (module doc, "Reused factorizations").
                            reuse_next = cfg.reuse_factor
                                && full
                                && last_step_m
                                    .is_none_or(|l| !reuse || step_m < REUSE_MAX_CONTRACTION * l);
                            last_step_m = Some(step_m);
                            continue 'newton;
                        }
                    }
                    if reuse {
                        break;
                    }
                    alpha *= 0.5;
                    report.halvings += 1;
                }
                if reuse {
                    reuse = false;
                    self.assemble::<true>(mesh, &held, ctx, false, known);
                    continue;
                }
                attempt += 1;
                if attempt > MAX_LM_RETRIES {
                    break;
                }
                reg = if reg == 0.0 { 10.0 } else { reg * 100.0 };
            }
            // No acceptable step even with damping. Where the shortest damped step still turns
            // a triangle over, that triangle's free vertices stay where they are for the rest
            // of the substep and the others go on (module doc, "Pinning"); else keep the
            // current iterate.
            reuse_next = false;
            if Self::pin_turning(mesh, &frame.x_n, &self.x_trial, &mut held) {
                report.pinned = true;
                e0 = f64::NAN;
                prev_step_m = None;
                continue;
            }
            report.stalled = true;
            break;
        }
        self.held = held;
        self.theta_pos = theta_pos;
        let inv_h = 1.0 / h;
        for i in 0..n {
            mesh.vel[i] = (mesh.pos[i] - frame.x_n[i]) * inv_h;
        }
        report
    }

    /// Holds the free vertices of every triangle that is not turned over (more than 90°) from
    /// `x_n` at the current positions (`mesh.pos`) but is at `trial`; returns whether it held
    /// any vertex that was free.
    fn pin_turning(mesh: &PhysMesh, x_n: &[V3], trial: &[V3], held: &mut [bool]) -> bool {
        let mut pinned = false;
        for t in &mesh.triangles {
            let [i, j, k] = t.map(|v| v as usize);
            let n0 = (x_n[j] - x_n[i]).cross(&(x_n[k] - x_n[i]));
            let cur = (mesh.pos[j] - mesh.pos[i]).cross(&(mesh.pos[k] - mesh.pos[i]));
            let nt = (trial[j] - trial[i]).cross(&(trial[k] - trial[i]));
            if n0.dot(&nt) <= 0.0 && n0.dot(&cur) > 0.0 {
                for v in [i, j, k] {
                    pinned |= !held[v];
                    held[v] = true;
                }
            }
        }
        pinned
    }

    /// True if some triangle that is not turned over (more than 90°) from `x_n` in `cur` is
    /// turned over in `trial`. Triangles already turned over by a kinematic move do not block
    /// the solve.
    fn flips_new(mesh: &PhysMesh, x_n: &[V3], cur: &[V3], trial: &[V3]) -> bool {
        let normal = |x: &[V3], t: &[u32; 3]| {
            let [i, j, k] = t.map(|v| v as usize);
            (x[j] - x[i]).cross(&(x[k] - x[i]))
        };
        mesh.triangles.iter().any(|t| {
            let n0 = normal(x_n, t);
            n0.dot(&normal(trial, t)) <= 0.0 && n0.dot(&normal(cur, t)) > 0.0
        })
    }

    /// Per-vertex terms: inertia + gravity, drag, contact penalty, lagged friction.
    /// Returns (energy, gradient, Hessian) — the Hessian only if `hess`.
    #[inline]
    fn vertex_terms(
        i: usize,
        x: &V3,
        m: f64,
        x_hat: &V3,
        ctx: Ctx<'_>,
        hess: bool,
    ) -> (f64, V3, M3) {
        let h = ctx.h;
        let p = ctx.params;
        let f = ctx.frame;
        let mh2 = m / (h * h);
        let d = x - x_hat;
        let mut e = 0.5 * mh2 * d.norm_squared() + m * GRAVITY_M_S2 * x.z;
        let mut g = d * mh2 + V3::new(0.0, 0.0, m * GRAVITY_M_S2);
        let mut hm = if hess {
            M3::identity() * mh2
        } else {
            M3::zeros()
        };

        let dx = x - f.x_n[i];
        let n = &f.normal[i];
        let mh = m / h;
        let dn = dx.dot(n);
        e += 0.5 * mh * (p.drag_normal_per_s * dn * dn + p.drag_per_s * dx.norm_squared());
        g += (n * (p.drag_normal_per_s * dn) + dx * p.drag_per_s) * mh;
        if hess {
            hm += (n * n.transpose() * p.drag_normal_per_s + M3::identity() * p.drag_per_s) * mh;
        }

        let k = penalty_stiffness(m);
        for pl in ctx.obstacles.planes.iter().filter(|pl| pl.active) {
            let pen = CONTACT_SKIN_M - pl.distance(x);
            if pen > 0.0 {
                e += 0.5 * k * pen * pen;
                g -= pl.normal * (k * pen);
                if hess {
                    hm += pl.normal * pl.normal.transpose() * k;
                }
                // Hard stage beyond the depth limit (collision.rs "Depth limit").
                let deep = pen - CONTACT_SKIN_M - MAX_PENETRATION_M;
                if deep > 0.0 {
                    let kh = HARD_CONTACT_FACTOR * k;
                    e += 0.5 * kh * deep * deep;
                    g -= pl.normal * (kh * deep);
                    if hess {
                        hm += pl.normal * pl.normal.transpose() * kh;
                    }
                }
            }
        }

        let c = f.contact[i];
        if c.plane != u8::MAX && c.lambda_n > 0.0 {
            let nrm = ctx.obstacles.planes[c.plane as usize].normal;
            let u = dx - nrm * dx.dot(&nrm);
            let y = u.norm();
            let eps = STICK_SPEED_M_S * h;
            let ml = p.friction_mu * c.lambda_n;
            e += ml * friction_f0(y, eps);
            if y > 0.0 {
                g += u * (ml * friction_f1(y / eps) / y);
            }
            if hess {
                let pt = M3::identity() - nrm * nrm.transpose();
                if y < eps {
                    hm += pt * (ml * (2.0 - y / eps) / eps);
                } else {
                    let uh = u / y;
                    hm += (pt - uh * uh.transpose()) * (ml / y);
                }
            }
        }
        (e, g, hm)
    }

    /// Total energy at `x` (constant terms of kinematic vertices omitted); each hinge's
    /// dihedral angle at `x` goes to `theta_out`.
    fn energy(
        mesh: &PhysMesh,
        x: &[V3],
        fixed: &[bool],
        x_hat: &[V3],
        ctx: Ctx<'_>,
        theta_out: &mut [f64],
    ) -> f64 {
        let mut e = 0.0;
        for i in 0..x.len() {
            if !fixed[i] {
                e += Self::vertex_terms(i, &x[i], mesh.mass_kg[i], &x_hat[i], ctx, false).0;
            }
        }
        let damp_s = ctx.params.membrane_damping_s / ctx.h;
        for (t, tri) in mesh.triangles.iter().enumerate() {
            let xs = tri.map(|i| x[i as usize]);
            e += membrane::energy(
                xs,
                &mesh.tri_rest[t],
                &ctx.frame.strain[t],
                damp_s,
                &ctx.params.membrane,
            );
        }
        let damp_b = ctx.params.bending_damping_s / ctx.h;
        for (k, hg) in mesh.hinges.iter().enumerate() {
            let xs = hg.v.map(|i| x[i as usize]);
            let ei = hg.edge as usize;
            let ke =
                bending::hinge_stiffness(ctx.params.bending_n_m, hg.weight, mesh.edge_damage[ei]);
            let theta = crate::sheet::measure::dihedral(&xs);
            theta_out[k] = theta;
            e += bending::energy(
                theta,
                mesh.edge_rest_angle[ei],
                ctx.frame.theta[k],
                ke,
                damp_b,
            );
        }
        for pair in ctx.frame.sheet.pairs() {
            e += pair.energy_of_gap(pair.gap_m(x)).0;
        }
        e
    }

    /// Fills `self.grad` and the system blocks at the current positions; returns the energy
    /// if `want_energy` (else 0). `theta`: the hinges' dihedral angles at the current
    /// positions, if known ([`Self::energy`] measured them there).
    fn assemble<const HESS: bool>(
        &mut self,
        mesh: &PhysMesh,
        fixed: &[bool],
        ctx: Ctx<'_>,
        want_energy: bool,
        theta_at_x: Option<&[f64]>,
    ) -> f64 {
        if HESS {
            self.sys.clear();
        }
        let x = &mesh.pos;
        let mut e = 0.0;
        for i in 0..x.len() {
            if fixed[i] {
                self.grad[i] = V3::zeros();
                continue;
            }
            let (ei, gi, hi) =
                Self::vertex_terms(i, &x[i], mesh.mass_kg[i], &self.x_hat[i], ctx, HESS);
            e += ei;
            self.grad[i] = gi;
            if HESS {
                self.sys.add_diag(i as u32, &hi);
            }
        }
        let damp_s = ctx.params.membrane_damping_s / ctx.h;
        let mut g3 = [V3::zeros(); 3];
        let mut h3 = [[M3::zeros(); 3]; 3];
        for (t, tri) in mesh.triangles.iter().enumerate() {
            let xs = tri.map(|i| x[i as usize]);
            e += membrane::grad_hess::<HESS>(
                xs,
                &mesh.tri_rest[t],
                &ctx.frame.strain[t],
                damp_s,
                &ctx.params.membrane,
                &mut g3,
                &mut h3,
            );
            for a in 0..3 {
                self.grad[tri[a] as usize] += g3[a];
            }
            if HESS {
                for a in 0..3 {
                    self.sys.add_diag(tri[a], &h3[a][a]);
                }
                for (k, &(a, b)) in TRI_PAIRS.iter().enumerate() {
                    self.sys.add_off(self.tri_off[t][k], &h3[a][b]);
                }
            }
        }
        let damp_b = ctx.params.bending_damping_s / ctx.h;
        for (k, hg) in mesh.hinges.iter().enumerate() {
            let xs = hg.v.map(|i| x[i as usize]);
            let Some((theta, gt)) = bending::dihedral_grad_with(&xs, theta_at_x.map(|t| t[k]))
            else {
                continue;
            };
            let ei = hg.edge as usize;
            let ke =
                bending::hinge_stiffness(ctx.params.bending_n_m, hg.weight, mesh.edge_damage[ei]);
            let rest = mesh.edge_rest_angle[ei];
            let th_n = ctx.frame.theta[k];
            if want_energy {
                e += bending::energy(theta, rest, th_n, ke, damp_b);
            }
            let (de, c) = bending::dtheta_coeffs(theta, rest, th_n, ke, damp_b);
            for (&v, g) in hg.v.iter().zip(&gt) {
                self.grad[v as usize] += g * de;
            }
            if HESS {
                for (&v, g) in hg.v.iter().zip(&gt) {
                    self.sys.add_diag(v, &(g * g.transpose() * c));
                }
                for (p, &(a, b)) in HINGE_PAIRS.iter().enumerate() {
                    self.sys
                        .add_off(self.hinge_off[k][p], &(gt[a] * gt[b].transpose() * c));
                }
            }
        }
        // Sheet–sheet contact (sheet_contact.rs): the pairs' coupling is not in the sparsity
        // pattern; each active pair's rank-one Hessian goes to the solve's Woodbury term, its
        // diagonal blocks only beyond that term's capacity.
        for pair in ctx.frame.sheet.pairs() {
            let sys = &mut self.sys;
            e += pair.accumulate(x, fixed, &mut self.grad, |p, d2e| {
                if HESS && !sys.add_rank_one(&p.v, &p.w, &p.n, d2e, fixed) {
                    p.diagonal_blocks(d2e, fixed, |v, b| sys.add_diag(v, b));
                }
            });
        }
        if want_energy {
            // Membrane energies were accumulated above; add nothing else.
            e
        } else {
            0.0
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::collision::Obstacles;
    use crate::control::Material;
    use crate::material::PaperMaterial;
    use crate::physics::{PhysParams, SolverConfig, SubstepFrame};
    use crate::room::RoomConfig;
    use crate::sheet::pattern::lattice;

    fn setup(table: bool) -> (PhysMesh, Obstacles, PhysParams, SolverConfig) {
        let room = RoomConfig {
            table,
            ..RoomConfig::default()
        };
        let mesh = PhysMesh::from_pattern(&lattice(0.1, 0.1, 0.02), 0.75, 0.1).unwrap();
        let cfg = SolverConfig::default();
        let params = PhysParams::new(&PaperMaterial::of(Material::Printer), &cfg);
        (mesh, Obstacles::new(&room), params, cfg)
    }

    #[test]
    fn free_fall_matches_backward_euler_of_gravity() {
        // Far from every obstacle and without drag, a flat sheet falls exactly as a point mass
        // under backward Euler: v₁ = −g h, x₁ = x₀ − g h².
        let (mut mesh, obstacles, mut params, cfg) = setup(false);
        params.drag_normal_per_s = 0.0;
        params.drag_per_s = 0.0;
        let mut s = NewtonSolver::new(&mesh);
        let mut frame = SubstepFrame::new(&mesh);
        frame.capture(&mesh, &obstacles);
        let fixed = vec![false; mesh.num_vertices()];
        let target = mesh.pos.clone();
        let h = 0.005;
        let r = s.substep(
            &mut mesh,
            &frame,
            Kinematics {
                fixed: &fixed,
                target: &target,
            },
            &obstacles,
            &params,
            &cfg,
            h,
        );
        assert!(!r.recovered);
        for (x, v) in mesh.pos.iter().zip(&mesh.vel) {
            assert!(
                (x.z - (0.75 - GRAVITY_M_S2 * h * h)).abs() < 1e-9,
                "{}",
                x.z
            );
            assert!((v.z + GRAVITY_M_S2 * h).abs() < 1e-6);
        }
    }

    #[test]
    fn resting_on_the_table_stays_put() {
        let (mut mesh, obstacles, params, cfg) = setup(true);
        let mut s = NewtonSolver::new(&mesh);
        let mut frame = SubstepFrame::new(&mesh);
        let fixed = vec![false; mesh.num_vertices()];
        let target = mesh.pos.clone();
        for _ in 0..50 {
            frame.capture(&mesh, &obstacles);
            s.substep(
                &mut mesh,
                &frame,
                Kinematics {
                    fixed: &fixed,
                    target: &target,
                },
                &obstacles,
                &params,
                &cfg,
                0.005,
            );
        }
        for (x, v) in mesh.pos.iter().zip(&mesh.vel) {
            assert!((x.z - 0.75).abs() < 2e-5, "z {}", x.z);
            assert!(v.norm() < 1e-3, "v {v:?}");
        }
    }

    #[test]
    fn the_error_estimate_stops_sooner_and_within_the_tolerance() {
        // A sheet held along one edge swings down under gravity: every substep takes several
        // iterations. Each substep is solved from the same start with both stopping rules.
        let (mut mesh, obstacles, params, cfg) = setup(false);
        let (fixed, target) = left_edge_held(&mesh);
        assert!(fixed.iter().any(|&f| f) && !fixed.iter().all(|&f| f));
        let kin = Kinematics {
            fixed: &fixed,
            target: &target,
        };
        let by_step = SolverConfig {
            stop_on_error_estimate: false,
            ..cfg
        };
        let by_estimate = SolverConfig {
            stop_on_error_estimate: true,
            ..cfg
        };
        let mut s = NewtonSolver::new(&mesh);
        let mut frame = SubstepFrame::new(&mesh);
        let (mut it_step, mut it_estimate, mut worst_m) = (0, 0, 0.0f64);
        for _ in 0..60 {
            frame.capture(&mesh, &obstacles);
            let mut early = mesh.clone();
            let r_est = s.substep(
                &mut early,
                &frame,
                kin,
                &obstacles,
                &params,
                &by_estimate,
                0.005,
            );
            let r_step = s.substep(&mut mesh, &frame, kin, &obstacles, &params, &by_step, 0.005);
            assert!(!r_est.recovered && !r_step.recovered);
            assert!(r_est.iterations <= r_step.iterations);
            it_estimate += r_est.iterations;
            it_step += r_step.iterations;
            // The step rule's iterate is the closer one to the minimizer (its last step is
            // below the tolerance); the estimate's may lie at most about one tolerance away.
            worst_m = worst_m.max(largest_difference_m(&early.pos, &mesh.pos));
        }
        assert!(it_estimate < it_step, "{it_estimate} vs {it_step}");
        assert!(worst_m < 2.0 * cfg.tolerance_m, "{worst_m}");
    }

    /// The swinging sheet's kinematics: the vertices of its left edge held where they are.
    fn left_edge_held(mesh: &PhysMesh) -> (Vec<bool>, Vec<V3>) {
        let fixed = mesh.pattern.iter().map(|p| p.x < 1e-9).collect();
        (fixed, mesh.pos.clone())
    }

    /// Largest coordinate difference between two sets of positions, metres.
    fn largest_difference_m(a: &[V3], b: &[V3]) -> f64 {
        a.iter()
            .zip(b)
            .map(|(a, b)| (a - b).amax())
            .fold(0.0, f64::max)
    }

    #[test]
    fn reused_factorizations_reach_the_same_state_with_fewer_factorizations() {
        // The swinging sheet of the test above: each substep solved from the same start with
        // and without reusing factorizations, stopping on the step alone so that both end
        // within the tolerance of the minimizer.
        let (mut mesh, obstacles, params, cfg) = setup(false);
        let (fixed, target) = left_edge_held(&mesh);
        let kin = Kinematics {
            fixed: &fixed,
            target: &target,
        };
        let plain = SolverConfig {
            reuse_factor: false,
            stop_on_error_estimate: false,
            iterations: 30,
            ..cfg
        };
        let reusing = SolverConfig {
            reuse_factor: true,
            ..plain
        };
        let mut s = NewtonSolver::new(&mesh);
        let mut frame = SubstepFrame::new(&mesh);
        let (mut f_plain, mut f_reuse, mut reused, mut worst_m) = (0, 0, 0, 0.0f64);
        for _ in 0..60 {
            frame.capture(&mesh, &obstacles);
            let mut other = mesh.clone();
            let r = s.substep(
                &mut other, &frame, kin, &obstacles, &params, &reusing, 0.005,
            );
            let p = s.substep(&mut mesh, &frame, kin, &obstacles, &params, &plain, 0.005);
            assert!(!r.recovered && !p.recovered && !r.stalled && !p.stalled);
            // Converged, not stopped by the cap.
            assert!(r.iterations - r.reused_iterations < reusing.iterations);
            assert_eq!(p.reused_iterations, 0);
            assert_eq!(p.factorizations, p.iterations);
            f_plain += p.factorizations;
            f_reuse += r.factorizations;
            reused += r.reused_iterations;
            worst_m = worst_m.max(largest_difference_m(&other.pos, &mesh.pos));
        }
        assert!(reused > 0);
        assert!(f_reuse < f_plain, "{f_reuse} factorizations vs {f_plain}");
        // Both iterates lie within a few tolerances of the same minimizer.
        assert!(worst_m < 5.0 * cfg.tolerance_m, "{worst_m}");
    }

    #[test]
    fn the_cap_counts_factorized_iterations() {
        // A hard substep (a corner yanked 2 cm) with a cap of 2: at most 2 factorized
        // iterations, and with reuse at most 2 more.
        let (mesh, obstacles, params, cfg) = setup(false);
        let mut fixed = vec![false; mesh.num_vertices()];
        fixed[0] = true;
        let mut target = mesh.pos.clone();
        target[0] += V3::new(0.02, 0.0, 0.01);
        let mut frame = SubstepFrame::new(&mesh);
        frame.capture(&mesh, &obstacles);
        for reuse_factor in [false, true] {
            let c = SolverConfig {
                iterations: 2,
                reuse_factor,
                ..cfg
            };
            let mut m = mesh.clone();
            let mut s = NewtonSolver::new(&m);
            let kin = Kinematics {
                fixed: &fixed,
                target: &target,
            };
            let r = s.substep(&mut m, &frame, kin, &obstacles, &params, &c, 0.005);
            assert!(r.iterations - r.reused_iterations <= 2, "{r:?}");
            assert!(r.iterations <= if reuse_factor { 4 } else { 2 }, "{r:?}");
            if !reuse_factor {
                assert_eq!(r.reused_iterations, 0);
            }
        }
    }

    #[test]
    fn pinning_holds_the_vertices_of_the_triangles_a_trial_turns_over() {
        let (mesh, ..) = setup(false);
        let x_n = mesh.pos.clone();
        // Vertex 0 (a corner) pushed in the plane beyond the far edge of its triangles: those
        // turn over, nothing else does.
        let mut trial = mesh.pos.clone();
        trial[0] += V3::new(0.05, 0.05, 0.0);
        let turned: Vec<usize> = (0..mesh.num_triangles())
            .filter(|&t| {
                let [i, j, k] = mesh.triangles[t].map(|v| v as usize);
                let n0 = (x_n[j] - x_n[i]).cross(&(x_n[k] - x_n[i]));
                let nt = (trial[j] - trial[i]).cross(&(trial[k] - trial[i]));
                n0.dot(&nt) <= 0.0
            })
            .collect();
        assert!(!turned.is_empty());
        let mut held = vec![false; mesh.num_vertices()];
        assert!(NewtonSolver::pin_turning(&mesh, &x_n, &trial, &mut held));
        for (v, &h) in held.iter().enumerate() {
            let in_turned = turned
                .iter()
                .any(|&t| mesh.triangles[t].contains(&(v as u32)));
            assert_eq!(h, in_turned, "vertex {v}");
        }
        // Nothing new to pin the second time.
        assert!(!NewtonSolver::pin_turning(&mesh, &x_n, &trial, &mut held));
        // A triangle the current iterate has already turned over (a kinematic move did) does
        // not count: with the current positions equal to the trial, nothing is pinned.
        let mut turned_mesh = mesh.clone();
        turned_mesh.pos.clone_from(&trial);
        let mut none = vec![false; mesh.num_vertices()];
        assert!(!NewtonSolver::pin_turning(
            &turned_mesh,
            &x_n,
            &trial,
            &mut none
        ));
        assert!(none.iter().all(|&h| !h));
    }

    #[test]
    fn each_accepted_step_lowers_the_energy() {
        // A sheet pulled by one kinematic corner far away: iterations are capped, but the
        // energy after the substep is below the energy of the initial guess.
        let (mut mesh, obstacles, params, cfg) = setup(true);
        let mut s = NewtonSolver::new(&mesh);
        let mut frame = SubstepFrame::new(&mesh);
        frame.capture(&mesh, &obstacles);
        let mut fixed = vec![false; mesh.num_vertices()];
        let mut target = mesh.pos.clone();
        fixed[0] = true;
        target[0] += V3::new(-0.01, -0.01, 0.02);
        let h = 0.005;
        let ctx = Ctx {
            h,
            frame: &frame,
            obstacles: &obstacles,
            params: &params,
        };
        let mut guess = mesh.pos.clone();
        guess[0] = target[0];
        s.x_hat.copy_from_slice(&mesh.pos);
        let mut theta = vec![0.0; mesh.hinges.len()];
        let e_guess = NewtonSolver::energy(&mesh, &guess, &fixed, &s.x_hat, ctx, &mut theta);
        let r = s.substep(
            &mut mesh,
            &frame,
            Kinematics {
                fixed: &fixed,
                target: &target,
            },
            &obstacles,
            &params,
            &cfg,
            h,
        );
        let e_after = NewtonSolver::energy(&mesh, &mesh.pos, &fixed, &s.x_hat, ctx, &mut theta);
        assert!(r.iterations >= 1 && !r.recovered);
        assert!(e_after < e_guess, "{e_after} !< {e_guess}");
        assert_eq!(mesh.pos[0], target[0]);
    }
}
