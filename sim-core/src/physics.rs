//! # The physics step on S_P
//!
//! Step (b) of the seeds' frame loop (Fig. 16 / Fig. 2.3; digest-crumpling §2.1, §3.0): "a
//! standard physical-based simulation … Green strain computation for stretching forces …
//! discrete flexural energy [for bending] … implicit integration" (T 712, P 435–441), with the
//! handles as hard constraints (T 714, P 448–450). The seeds give neither the time step nor the
//! stiffness; they require "medium" stiffness (P 88–91) — see [`crate::material`] for the
//! constants and their scaling.
//!
//! ## Model
//!
//! Backward Euler written as the minimization of the incremental potential (Martin et al.
//! 2011, Gast et al. 2015): over one substep of length h, the new positions minimize
//!
//! ```text
//! E(x) = Σ_i ½ (m_i/h²) |x_i − x̂_i|² − m_i g·x_i                  inertia + gravity, x̂ = x_n + h v_n
//!      + Σ_t W_t(x) + D_t(x)                                      membrane: StVK + strain-rate damping
//!      + Σ_e W_e(x) + D_e(x)                                      hinges: bending (rest angle, damage) + damping
//!      + Σ_i ½ (m_i/h) (α_n ((x_i − x_i,n)·n_i)² + α_t |x_i − x_i,n|²)   air drag (normal ≫ tangential)
//!      + Σ_i E_contact,i(x) + μ λ_i f₀(|P_T(x_i − x_i,n)|)         obstacles + lagged Coulomb friction
//! ```
//!
//! subject to `x_k = target_k` for the kinematic vertices (handles and their tangent-plane
//! neighbours, [`crate::handles`]). Then `v = (x − x_n)/h`. Every term is a potential, so a line
//! search on E makes each Newton step a descent step: large handle motions cannot blow up the
//! integration. Dissipation potentials (damping, drag, friction) are centred on the state at
//! the start of the substep.
//!
//! ## Solver
//!
//! [`newton`]: Newton's method on E with a sparse Cholesky solve (faer) of the PSD-projected
//! Hessian and a backtracking line search. XPBD was built and measured against it and lost
//! (21× the length error at the same cost; docs/decisions.md, "Newton, not XPBD").
//!
//! The benchmark report (`cargo xtask bench-report`, `docs/benchmarks.md`) measures it on the
//! scenario library (run time per frame against the length error c_mean / n_comp);
//! [`SolverConfig::default`] records the chosen parameters.

pub mod bending;
pub mod membrane;
pub mod newton;
pub mod sheet_contact;
pub mod sparse;
pub mod strain_limit;

use crate::collision::{CONTACT_SKIN_M, LaggedContact, Obstacles, penalty_stiffness};
use crate::material::PaperMaterial;
use crate::math::{M2, V3};
use crate::sheet::physical::PhysMesh;
use membrane::MembraneParams;

/// Numerical parameters of the physics step.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SolverConfig {
    /// Substeps per frame (time step = frame / substeps).
    pub substeps: u32,
    /// Maximal Newton iterations per substep that factorize the system (with `reuse_factor`,
    /// as many more may solve with a reused factorization).
    pub iterations: u32,
    /// Newton: stop when the largest vertex update is below this, metres.
    pub tolerance_m: f64,
    /// Newton: also stop when the distance still to go, estimated from the contraction of two
    /// full steps in a row, is below the tolerance ([`newton`] "Stopping"); `false`: stop on
    /// the last step alone.
    pub stop_on_error_estimate: bool,
    /// Multiplier of the material's stretching stiffness k_s (the "medium stiffness" scaling,
    /// see [`crate::material`]).
    pub stretch_scale: f64,
    /// Strain-rate (membrane) damping time τ_s, seconds.
    pub membrane_damping_s: f64,
    /// Bending-rate damping time τ_b, seconds.
    pub bending_damping_s: f64,
    /// Air drag rate against motion along the surface normal, 1/s.
    pub drag_normal_per_s: f64,
    /// Air drag rate against any motion, 1/s.
    pub drag_per_s: f64,
    /// Sheet–sheet contact ([`sheet_contact`]): parts of the sheet closer than
    /// [`sheet_contact::SHEET_CONTACT_DIST_M`] push apart.
    pub sheet_contact: bool,
    /// Newton: active sheet–sheet contact pairs whose whole Hessian (rank one, coupling the
    /// two layers) enters the linear solve through the Woodbury identity
    /// ([`sparse::BlockSystem::add_rank_one`]); further pairs add their diagonal blocks only.
    /// 0 = diagonal blocks only. At most [`sparse::LOW_RANK_CAPACITY`].
    pub contact_coupling_pairs: u32,
    /// Newton: solve with the last iteration's factorization again while the steps contract
    /// ([`newton`] "Reused factorizations").
    pub reuse_factor: bool,
}

impl Default for SolverConfig {
    /// The parameters chosen by measurement on the bench report (`cargo xtask bench-report`);
    /// the figures are in `docs/decisions.md` under the names in quotes:
    ///
    /// - **One substep**: more give the same error at more time; the error comes from the
    ///   model, not the time step ("Newton's parameters: one substep, up to 10 iterations,
    ///   k_s × 0.03").
    /// - **Stretching stiffness × 0.03** (15 kN/m for printer paper): the knee of the stiffness
    ///   sweep (same section).
    /// - **Up to 10 iterations**, stopping at the tolerance (the seeds: "convergence after 10
    ///   to 100 iterations"): an unconverged step's velocity carries energy the sheet never
    ///   had, and a held sheet would never come to rest (same section).
    /// - **Reused factorizations: on** ([`newton`], "Reused factorizations"): the crumples'
    ///   median frame falls by a fifth, with no more strained runs ("Reused factorizations").
    /// - **Contact coupling: 32 pairs**: with diagonal blocks alone Newton creeps to its cap
    ///   where layers lie on each other ("Contact coupling: 32 pairs").
    ///
    /// `stop_on_error_estimate`, `reuse_factor`, `sheet_contact` and `contact_coupling_pairs`
    /// off (or 0): for the bench report's comparison rows.
    fn default() -> Self {
        Self {
            substeps: 1,
            iterations: 10,
            tolerance_m: 1e-6,
            stop_on_error_estimate: true,
            stretch_scale: 0.03,
            membrane_damping_s: 2e-4,
            bending_damping_s: 1e-3,
            drag_normal_per_s: 6.0,
            drag_per_s: 0.3,
            sheet_contact: true,
            contact_coupling_pairs: 32,
            reuse_factor: true,
        }
    }
}

impl SolverConfig {
    /// Largest accepted substep count.
    pub const MAX_SUBSTEPS: u32 = 256;
    /// Largest accepted iteration count.
    pub const MAX_ITERATIONS: u32 = 100;

    /// Returns a copy with every value finite and in range.
    pub fn sanitized(self) -> Self {
        let d = Self::default();
        let pos = |v: f64, dflt: f64, lo: f64, hi: f64| {
            if v.is_finite() { v.clamp(lo, hi) } else { dflt }
        };
        Self {
            substeps: self.substeps.clamp(1, Self::MAX_SUBSTEPS),
            iterations: self.iterations.clamp(1, Self::MAX_ITERATIONS),
            tolerance_m: pos(self.tolerance_m, d.tolerance_m, 1e-12, 1e-2),
            stop_on_error_estimate: self.stop_on_error_estimate,
            stretch_scale: pos(self.stretch_scale, d.stretch_scale, 1e-5, 1.0),
            membrane_damping_s: pos(self.membrane_damping_s, d.membrane_damping_s, 0.0, 1.0),
            bending_damping_s: pos(self.bending_damping_s, d.bending_damping_s, 0.0, 1.0),
            drag_normal_per_s: pos(self.drag_normal_per_s, d.drag_normal_per_s, 0.0, 1e3),
            drag_per_s: pos(self.drag_per_s, d.drag_per_s, 0.0, 1e3),
            sheet_contact: self.sheet_contact,
            contact_coupling_pairs: self
                .contact_coupling_pairs
                .min(sparse::LOW_RANK_CAPACITY as u32),
            reuse_factor: self.reuse_factor,
        }
    }
}

/// Material and damping constants as the solvers use them.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PhysParams {
    /// Membrane Lamé parameters (scaled k_s).
    pub membrane: MembraneParams,
    /// Bending stiffness B, N·m.
    pub bending_n_m: f64,
    /// Membrane damping time, s.
    pub membrane_damping_s: f64,
    /// Bending damping time, s.
    pub bending_damping_s: f64,
    /// Normal air drag, 1/s.
    pub drag_normal_per_s: f64,
    /// Isotropic air drag, 1/s.
    pub drag_per_s: f64,
    /// Friction coefficient.
    pub friction_mu: f64,
    /// Scaled stretching stiffness k_s, N/m.
    pub stretch_n_m: f64,
}

impl PhysParams {
    /// Constants for a material and solver configuration.
    pub fn new(mat: &PaperMaterial, cfg: &SolverConfig) -> Self {
        let k_s = mat.stretch_stiffness_n_m * cfg.stretch_scale;
        let (lambda, mu) = mat.lame_n_m(k_s);
        Self {
            membrane: MembraneParams {
                lambda_n_m: lambda,
                mu_n_m: mu,
            },
            bending_n_m: mat.bending_stiffness_n_m,
            membrane_damping_s: cfg.membrane_damping_s,
            bending_damping_s: cfg.bending_damping_s,
            drag_normal_per_s: cfg.drag_normal_per_s,
            drag_per_s: cfg.drag_per_s,
            friction_mu: mat.friction_mu,
            stretch_n_m: k_s,
        }
    }
}

/// Kinematic (hard) constraints of one substep.
#[derive(Clone, Copy, Debug)]
pub struct Kinematics<'a> {
    /// True for vertices whose position is prescribed.
    pub fixed: &'a [bool],
    /// Prescribed positions at the end of the substep (read for fixed vertices only).
    pub target: &'a [V3],
}

/// What one substep reports.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SubstepReport {
    /// Solver iterations done.
    pub iterations: u32,
    /// Line-search halvings (Newton).
    pub halvings: u32,
    /// True if the solver had to fall back (non-finite state, failed factorization).
    pub recovered: bool,
    /// Newton: some free vertices were pinned for the rest of the substep, where every step
    /// the line search tried would have turned their triangle over
    /// ([`newton`] module doc, "Pinning").
    pub pinned: bool,
    /// Newton: the solve ended on an iterate from which no step was acceptable, even damped
    /// and after any pinning: the substep stopped short of its solution.
    pub stalled: bool,
    /// Newton: iterations whose step was solved with the factorization of an earlier one
    /// ([`newton`] "Reused factorizations"); counted in `iterations` too.
    pub reused_iterations: u32,
    /// Newton: numeric factorizations done (Levenberg–Marquardt retries included).
    pub factorizations: u32,
    /// Newton: the solve ended at the iteration cap, short of its stopping rule.
    pub capped: bool,
}

impl SubstepReport {
    /// Adds the work of `other` (iterations, halvings, factorizations) to this report and
    /// ORs its flags in: the report of several substeps taken as one.
    pub fn add(&mut self, other: &Self) {
        self.iterations += other.iterations;
        self.halvings += other.halvings;
        self.reused_iterations += other.reused_iterations;
        self.factorizations += other.factorizations;
        self.recovered |= other.recovered;
        self.pinned |= other.pinned;
        self.stalled |= other.stalled;
        self.capped |= other.capped;
    }
}

/// True if some triangle of `mesh` turns by more than 90° (its normal reverses) between
/// positions `a` and `b` (false if the positions do not fit the mesh).
pub fn turns_a_triangle_over(mesh: &PhysMesh, a: &[V3], b: &[V3]) -> bool {
    let n = mesh.num_vertices();
    if a.len() != n || b.len() != n {
        return false;
    }
    mesh.triangles.iter().any(|t| {
        let [i, j, k] = t.map(|v| v as usize);
        let na = (a[j] - a[i]).cross(&(a[k] - a[i]));
        let nb = (b[j] - b[i]).cross(&(b[k] - b[i]));
        na.dot(&nb) <= 0.0 && na.norm_squared() > 0.0
    })
}

/// State frozen at the start of a substep, shared by both solvers.
#[derive(Clone, Debug, Default)]
pub struct SubstepFrame {
    /// Positions at the start of the substep.
    pub x_n: Vec<V3>,
    /// Velocities at the start of the substep.
    pub v_n: Vec<V3>,
    /// Area-weighted unit vertex normals.
    pub normal: Vec<V3>,
    /// Green strain per triangle.
    pub strain: Vec<M2>,
    /// Dihedral angle per hinge.
    pub theta: Vec<f64>,
    /// Lagged contact per vertex.
    pub contact: Vec<LaggedContact>,
    /// Sheet–sheet contact pairs of the substep ([`sheet_contact`]; empty when it is off).
    pub sheet: sheet_contact::SheetContact,
}

impl SubstepFrame {
    /// Storage for a mesh.
    pub fn new(mesh: &PhysMesh) -> Self {
        let n = mesh.num_vertices();
        Self {
            x_n: vec![V3::zeros(); n],
            v_n: vec![V3::zeros(); n],
            normal: vec![V3::zeros(); n],
            strain: vec![M2::zeros(); mesh.num_triangles()],
            theta: vec![0.0; mesh.hinges.len()],
            contact: vec![LaggedContact::default(); n],
            sheet: sheet_contact::SheetContact::new(mesh),
        }
    }

    /// Freezes the start-of-substep state.
    pub fn capture(&mut self, mesh: &PhysMesh, obstacles: &Obstacles) {
        self.x_n.copy_from_slice(&mesh.pos);
        self.v_n.copy_from_slice(&mesh.vel);
        for n in &mut self.normal {
            *n = V3::zeros();
        }
        for (t, tri) in mesh.triangles.iter().enumerate() {
            let x = tri.map(|i| mesh.pos[i as usize]);
            let n = (x[1] - x[0]).cross(&(x[2] - x[0]));
            for &i in tri {
                self.normal[i as usize] += n;
            }
            self.strain[t] = crate::sheet::measure::green_strain(x, &mesh.tri_rest[t]).0;
        }
        for n in &mut self.normal {
            let l = n.norm();
            *n = if l > 0.0 { *n / l } else { V3::z() };
        }
        for (k, h) in mesh.hinges.iter().enumerate() {
            self.theta[k] = crate::sheet::measure::dihedral(&h.v.map(|i| mesh.pos[i as usize]));
        }
        for (i, c) in self.contact.iter_mut().enumerate() {
            *c = LaggedContact {
                plane: u8::MAX,
                lambda_n: 0.0,
            };
            let x = &mesh.pos[i];
            let mut best = 0.0;
            for (pi, pl) in obstacles.planes.iter().enumerate() {
                if !pl.active {
                    continue;
                }
                let pen = CONTACT_SKIN_M - pl.distance(x);
                if pen > best {
                    best = pen;
                    c.plane = pi as u8;
                    c.lambda_n = penalty_stiffness(mesh.mass_kg[i]) * pen;
                }
            }
        }
    }
}

/// The physics engine of one mesh: the solver's workspaces.
#[derive(Debug)]
pub struct Physics {
    frame: SubstepFrame,
    newton: newton::NewtonSolver,
    /// Substeps integrated since creation (the work counter: it does not move while the
    /// sheet sleeps).
    pub substeps_done: u64,
}

impl Physics {
    /// Workspaces for a mesh (allocates; everything later reuses them).
    pub fn new(mesh: &PhysMesh) -> Self {
        Self {
            frame: SubstepFrame::new(mesh),
            newton: newton::NewtonSolver::new(mesh),
            substeps_done: 0,
        }
    }

    /// Triangles `a` and `b` crossed in an undone frame: their contact pairs stiffen.
    pub fn boost_crossing(&mut self, a: [u32; 3], b: [u32; 3]) {
        self.frame.sheet.boost_crossing(a, b);
    }

    /// The sheet–sheet contact pairs of the last substep ([`sheet_contact`]; empty when it is
    /// off or no substep has run since the mesh was made).
    pub fn sheet_pairs(&self) -> &[sheet_contact::SheetPair] {
        self.frame.sheet.pairs()
    }

    /// The active contact boosts (saved with the sheet).
    pub fn contact_boosts(&self) -> &[sheet_contact::Boost] {
        self.frame.sheet.boosts()
    }

    /// Drops every contact boost (the contact's own stiffness everywhere again).
    pub fn clear_contact_boosts(&mut self) {
        self.frame.sheet.clear_boosts();
    }

    /// Restores saved contact boosts.
    pub fn set_contact_boosts(
        &mut self,
        boosts: &[sheet_contact::Boost],
        num_vertices: usize,
    ) -> Result<(), String> {
        self.frame.sheet.set_boosts(boosts, num_vertices)
    }

    /// Positions at the start of the last substep.
    pub fn substep_start(&self) -> &[V3] {
        &self.frame.x_n
    }

    /// Puts `mesh` back where the last substep started (positions and velocities), so the
    /// substep can be solved again with other kinematic targets.
    pub fn restore_substep_start(&self, mesh: &mut PhysMesh) {
        if self.frame.x_n.len() == mesh.pos.len() && self.frame.v_n.len() == mesh.vel.len() {
            mesh.pos.copy_from_slice(&self.frame.x_n);
            mesh.vel.copy_from_slice(&self.frame.v_n);
        }
    }

    /// One frame passed: contact boosts age.
    pub fn age_contact_boosts(&mut self) {
        self.frame.sheet.age_boosts();
    }

    /// Number of sparse factorizations done by the Newton solver.
    pub fn factorizations(&self) -> u64 {
        self.newton.factorizations()
    }

    /// Advances the mesh by one substep of `h_s` seconds.
    pub fn substep(
        &mut self,
        mesh: &mut PhysMesh,
        kin: Kinematics<'_>,
        obstacles: &Obstacles,
        params: &PhysParams,
        cfg: &SolverConfig,
        h_s: f64,
    ) -> SubstepReport {
        self.substeps_done += 1;
        self.frame.capture(mesh, obstacles);
        if cfg.sheet_contact {
            // Reach: both sides of a pair may travel as far as the fastest vertex this
            // substep (free: its velocity; kinematic: its prescribed move).
            let travel_m = (0..mesh.num_vertices())
                .map(|i| {
                    if kin.fixed[i] {
                        (kin.target[i] - mesh.pos[i]).norm()
                    } else {
                        mesh.vel[i].norm() * h_s
                    }
                })
                .fold(0.0, f64::max);
            self.frame.sheet.find(mesh, 2.0 * travel_m);
        } else {
            self.frame.sheet.clear();
        }
        let report = self
            .newton
            .substep(mesh, &self.frame, kin, obstacles, params, cfg, h_s);
        // Last line of defence: a non-finite state is replaced by the start of the substep,
        // at rest (never observed in the stress tests; counted if it happens).
        let bad = mesh
            .pos
            .iter()
            .chain(&mesh.vel)
            .any(|v| !crate::math::finite3(v));
        if bad {
            mesh.pos.copy_from_slice(&self.frame.x_n);
            for v in &mut mesh.vel {
                *v = V3::zeros();
            }
            return SubstepReport {
                recovered: true,
                ..report
            };
        }
        report
    }
}

/// Elastic forces (membrane + bending, no damping) on every vertex, N: `out[i] = −∂W/∂x_i`.
/// Used to measure how hard the sheet pulls on the hands ([`crate::gesture_rig`]).
pub fn elastic_forces(mesh: &PhysMesh, params: &PhysParams, out: &mut [V3]) {
    for f in out.iter_mut() {
        *f = V3::zeros();
    }
    let mut g3 = [V3::zeros(); 3];
    let mut h3 = [[crate::math::M3::zeros(); 3]; 3];
    for (t, tri) in mesh.triangles.iter().enumerate() {
        let xs = tri.map(|i| mesh.pos[i as usize]);
        membrane::grad_hess::<true>(
            xs,
            &mesh.tri_rest[t],
            &M2::zeros(),
            0.0,
            &params.membrane,
            &mut g3,
            &mut h3,
        );
        for a in 0..3 {
            out[tri[a] as usize] -= g3[a];
        }
    }
    for hg in &mesh.hinges {
        let xs = hg.v.map(|i| mesh.pos[i as usize]);
        let Some((theta, gt)) = bending::dihedral_grad(&xs) else {
            continue;
        };
        let ei = hg.edge as usize;
        let ke = bending::hinge_stiffness(params.bending_n_m, hg.weight, mesh.edge_damage[ei]);
        let (de, _) = bending::dtheta_coeffs(theta, mesh.edge_rest_angle[ei], theta, ke, 0.0);
        for a in 0..4 {
            out[hg.v[a] as usize] -= gt[a] * de;
        }
    }
}
