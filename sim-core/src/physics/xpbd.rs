//! # XPBD: extended position-based dynamics (for comparison with the Newton solver)
//!
//! Macklin, Müller & Chentanez 2016 (XPBD) with "small steps" (Macklin et al. 2019: many
//! substeps, one constraint iteration each). The same mesh, material, damping, obstacles and
//! handles as the Newton solver, written as compliant constraints:
//!
//! ```text
//! edges   C_e = |x_a − x_b| − l̄_e,   compliance α_e = 1 / k_e,  k_e = k_s (Ā_A + Ā_B) / l̄_e²
//! hinges  C_h = θ_h − θ̄_h,           compliance α_h = 1 / (2 k_h)   (k_h of [`super::bending`])
//!
//! Δλ = (−C − α̃ λ − γ ∇C·(x − x_n)) / ((1 + γ) Σ w |∇C|² + α̃),   α̃ = α/h²,  γ = τ/h
//! x += w ∇C Δλ
//! ```
//!
//! The edge stiffness is the spring constant that gives an equilateral spring lattice the
//! membrane's stretching stiffness (E·t = 2k/√3 for springs on an equilateral lattice, and
//! (Ā_A+Ā_B)/l̄² = √3/2 there). γ is the XPBD constraint damping with the same damping times τ as
//! the Newton solver's dissipation potentials.
//!
//! **Contacts** are position projections onto the free side of each plane after the
//! constraints, with Coulomb friction as a position correction limited by μ × the normal
//! correction (Macklin et al. 2014, "Unified particle physics", §6); kinematic vertices have
//! zero inverse mass. Air drag is applied to the predicted velocity (implicitly, per vertex
//! normal). This is the usual XPBD cloth recipe; it is a different discretization of the
//! same model, not the same equations as the Newton solver.

use crate::collision::Obstacles;
use crate::math::{GRAVITY_M_S2, V3, wrap_angle};
use crate::physics::sheet_contact::SHEET_CONTACT_DIST_M;
use crate::physics::{Kinematics, PhysParams, SolverConfig, SubstepFrame, SubstepReport, bending};
use crate::sheet::physical::PhysMesh;

/// XPBD workspace for one mesh.
#[derive(Debug)]
pub struct XpbdSolver {
    lambda_edge: Vec<f64>,
    lambda_hinge: Vec<f64>,
    edge_weight: Vec<f64>,
    inv_mass: Vec<f64>,
    /// `PhysMesh::rest_version` the edge weights were computed for.
    rest_version: u64,
}

impl XpbdSolver {
    /// Workspace for a mesh.
    pub fn new(mesh: &PhysMesh) -> Self {
        let mut s = Self {
            lambda_edge: vec![0.0; mesh.num_edges()],
            lambda_hinge: vec![0.0; mesh.hinges.len()],
            edge_weight: vec![0.0; mesh.num_edges()],
            inv_mass: vec![0.0; mesh.num_vertices()],
            rest_version: mesh.rest_version,
        };
        s.refresh_rest(mesh);
        s
    }

    /// Edge weights from the mesh's rest shape (again after it changed). No allocation.
    fn refresh_rest(&mut self, mesh: &PhysMesh) {
        for (e, ed) in mesh.topo.edges.iter().enumerate() {
            let mut area = 0.0;
            for &h in &ed.he {
                if h != crate::sheet::topology::NONE {
                    area += mesh.tri_rest[mesh.topo.half_edges[h as usize].face as usize].area_m2;
                }
            }
            let l = mesh.edge_rest_len_m[e];
            self.edge_weight[e] = area / (l * l);
        }
        self.rest_version = mesh.rest_version;
    }

    /// One XPBD substep.
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
        if self.rest_version != mesh.rest_version {
            self.refresh_rest(mesh);
        }
        let n = mesh.num_vertices();
        let g = V3::new(0.0, 0.0, -GRAVITY_M_S2);
        for i in 0..n {
            if kin.fixed[i] {
                self.inv_mass[i] = 0.0;
                mesh.pos[i] = kin.target[i];
                continue;
            }
            self.inv_mass[i] = 1.0 / mesh.mass_kg[i];
            let mut v = frame.v_n[i] + g * h;
            // Implicit drag: normal component and isotropic part.
            let nrm = frame.normal[i];
            let vn = v.dot(&nrm);
            v -= nrm * (vn * (params.drag_normal_per_s * h) / (1.0 + params.drag_normal_per_s * h));
            v /= 1.0 + params.drag_per_s * h;
            mesh.pos[i] = frame.x_n[i] + v * h;
        }
        self.lambda_edge.iter_mut().for_each(|l| *l = 0.0);
        self.lambda_hinge.iter_mut().for_each(|l| *l = 0.0);
        let h2 = h * h;
        let gamma_s = params.membrane_damping_s / h;
        let gamma_b = params.bending_damping_s / h;
        for _ in 0..cfg.iterations {
            // Edges.
            for (e, ed) in mesh.topo.edges.iter().enumerate() {
                let (a, b) = (ed.v[0] as usize, ed.v[1] as usize);
                let (wa, wb) = (self.inv_mass[a], self.inv_mass[b]);
                let wsum = wa + wb;
                if wsum == 0.0 {
                    continue;
                }
                let d = mesh.pos[a] - mesh.pos[b];
                let l = d.norm();
                if l <= 1e-12 {
                    continue;
                }
                let gdir = d / l; // ∇_a C
                let c = l - mesh.edge_rest_len_m[e];
                let k = params.stretch_n_m * self.edge_weight[e];
                let alpha = 1.0 / (k * h2);
                let rate = gdir.dot(&((mesh.pos[a] - frame.x_n[a]) - (mesh.pos[b] - frame.x_n[b])));
                let dl = (-c - alpha * self.lambda_edge[e] - gamma_s * rate)
                    / ((1.0 + gamma_s) * wsum + alpha);
                self.lambda_edge[e] += dl;
                mesh.pos[a] += gdir * (wa * dl);
                mesh.pos[b] -= gdir * (wb * dl);
            }
            // Hinges.
            for (k, hg) in mesh.hinges.iter().enumerate() {
                let xs = hg.v.map(|i| mesh.pos[i as usize]);
                let Some((theta, gt)) = bending::dihedral_grad(&xs) else {
                    continue;
                };
                let ei = hg.edge as usize;
                let ke =
                    bending::hinge_stiffness(params.bending_n_m, hg.weight, mesh.edge_damage[ei]);
                let c = wrap_angle(theta - mesh.edge_rest_angle[ei]);
                let mut wsum = 0.0;
                let mut rate = 0.0;
                for (&v, g) in hg.v.iter().zip(&gt) {
                    let v = v as usize;
                    wsum += self.inv_mass[v] * g.norm_squared();
                    rate += g.dot(&(mesh.pos[v] - frame.x_n[v]));
                }
                if wsum <= 0.0 {
                    continue;
                }
                let alpha = 1.0 / (2.0 * ke * h2);
                let dl = (-c - alpha * self.lambda_hinge[k] - gamma_b * rate)
                    / ((1.0 + gamma_b) * wsum + alpha);
                self.lambda_hinge[k] += dl;
                for (&v, g) in hg.v.iter().zip(&gt) {
                    let v = v as usize;
                    mesh.pos[v] += g * (self.inv_mass[v] * dl);
                }
            }
            // Sheet–sheet contact (sheet_contact.rs): each active pair as an inequality
            // constraint g ≥ d̂ along its frozen normal.
            for pair in frame.sheet.pairs() {
                let c = pair.gap_m(&mesh.pos) - SHEET_CONTACT_DIST_M;
                if c >= 0.0 {
                    continue;
                }
                let wsum: f64 = pair
                    .v
                    .iter()
                    .zip(&pair.w)
                    .map(|(&v, &w)| self.inv_mass[v as usize] * w * w)
                    .sum();
                if wsum <= 0.0 {
                    continue;
                }
                let dl = -c / wsum;
                for (&v, &w) in pair.v.iter().zip(&pair.w) {
                    mesh.pos[v as usize] += pair.n * (self.inv_mass[v as usize] * w * dl);
                }
            }
            // Contacts with friction.
            for i in 0..n {
                if self.inv_mass[i] == 0.0 {
                    continue;
                }
                for pl in obstacles.planes.iter().filter(|p| p.active) {
                    let d = pl.distance(&mesh.pos[i]);
                    if d >= 0.0 {
                        continue;
                    }
                    mesh.pos[i] -= pl.normal * d; // normal correction of length −d
                    let dx = mesh.pos[i] - frame.x_n[i];
                    let t = dx - pl.normal * dx.dot(&pl.normal);
                    let tl = t.norm();
                    let limit = params.friction_mu * (-d);
                    if tl <= limit {
                        mesh.pos[i] -= t;
                    } else if tl > 0.0 {
                        mesh.pos[i] -= t * (limit / tl);
                    }
                }
            }
        }
        let inv_h = 1.0 / h;
        for i in 0..n {
            mesh.vel[i] = (mesh.pos[i] - frame.x_n[i]) * inv_h;
        }
        SubstepReport {
            iterations: cfg.iterations,
            ..SubstepReport::default()
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::control::Material;
    use crate::material::PaperMaterial;
    use crate::room::RoomConfig;
    use crate::sheet::pattern::lattice;

    #[test]
    fn resting_sheet_stays_on_the_table_and_hanging_sheet_is_taut() {
        let room = RoomConfig::default();
        let obstacles = Obstacles::new(&room);
        let mut mesh = PhysMesh::from_pattern(&lattice(0.1, 0.1, 0.02), 0.75, 0.1).unwrap();
        let cfg = SolverConfig {
            kind: crate::physics::SolverKind::Xpbd,
            substeps: 10,
            iterations: 1,
            ..SolverConfig::default()
        };
        let params = PhysParams::new(&PaperMaterial::of(Material::Printer), &cfg);
        let mut s = XpbdSolver::new(&mesh);
        let mut frame = SubstepFrame::new(&mesh);
        let fixed = vec![false; mesh.num_vertices()];
        let target = mesh.pos.clone();
        for _ in 0..100 {
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
                0.0005,
            );
        }
        for x in &mesh.pos {
            assert!((x.z - 0.75).abs() < 1e-4, "{}", x.z);
        }
        for e in 0..mesh.num_edges() {
            let r = mesh.edge_length_m(e) / mesh.edge_rest_len_m[e];
            assert!((r - 1.0).abs() < 1e-3);
        }
    }
}
