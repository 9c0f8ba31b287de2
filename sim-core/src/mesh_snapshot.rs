//! # Mesh snapshot: a copy of the simulation mesh for display and export
//!
//! The simulation mesh S_P (3D positions, 2D pattern positions, triangles) copied out in
//! single precision, with the handle points, for the editor's 3D view and the OBJ export of
//! `papier-render --obj-dir`, and the torn lips' millimetre detail as 3D polylines (each lip
//! edge's walk, [`crate::tearing::lips`], mapped through its triangle: the barycentric
//! coordinates of each pattern point, applied to the triangle's 3D corners).
//! [`MeshSnapshot::with_capacity`] reserves storage up front; writing a mesh that fits the
//! capacity does not allocate; lip detail past [`LIP_CAPACITY_POINTS`] is left out (those lip
//! edges are drawn straight).

use crate::math::{V2, V3};
use crate::tearing::lips::LipRun;

/// Lip points a snapshot reserves (a 30 cm tear's two lips need ≈ 1 300).
pub const LIP_CAPACITY_POINTS: usize = 8192;

/// One lip edge's polyline in [`MeshSnapshot::lip_points_m`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct LipPolyline {
    /// The edge's two vertices (the polyline runs from the first to the second).
    pub edge: [u32; 2],
    /// First point.
    pub start: u32,
    /// Number of points.
    pub len: u32,
}

/// What a vertex is, for colouring in the editor.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum VertexTag {
    /// An ordinary vertex.
    #[default]
    Plain,
    /// Held by a hand.
    Handle,
    /// A persistent singular vertex (d-cone apex).
    Singular,
}

/// A copy of the simulation mesh.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MeshSnapshot {
    /// Frame index the snapshot was taken at.
    pub frame: u64,
    /// 3D vertex positions, world metres.
    pub positions_m: Vec<[f32; 3]>,
    /// 2D pattern (rest) positions, metres, origin at the sheet centre.
    pub pattern_m: Vec<[f32; 2]>,
    /// Per-vertex tags.
    pub tags: Vec<VertexTag>,
    /// Triangles (counter-clockwise in the pattern).
    pub triangles: Vec<[u32; 3]>,
    /// The torn lips' jagged polylines, world metres (empty on a whole sheet).
    pub lip_points_m: Vec<[f32; 3]>,
    /// One entry per lip edge drawn jagged.
    pub lips: Vec<LipPolyline>,
}

impl MeshSnapshot {
    /// Reserves room for `vertices` vertices and `triangles` triangles.
    pub fn with_capacity(vertices: usize, triangles: usize) -> Self {
        Self {
            frame: 0,
            positions_m: Vec::with_capacity(vertices),
            pattern_m: Vec::with_capacity(vertices),
            tags: Vec::with_capacity(vertices),
            triangles: Vec::with_capacity(triangles),
            lip_points_m: Vec::with_capacity(LIP_CAPACITY_POINTS),
            lips: Vec::with_capacity(LIP_CAPACITY_POINTS / 2),
        }
    }

    /// Empties the snapshot, keeping its storage.
    pub fn clear(&mut self) {
        self.positions_m.clear();
        self.pattern_m.clear();
        self.tags.clear();
        self.triangles.clear();
        self.lip_points_m.clear();
        self.lips.clear();
    }

    /// Appends the lips' polylines in 3D: each point of a run, in barycentric coordinates of
    /// its triangle's pattern corners, applied to the corners' `positions`. Runs that do not
    /// fit the reserved capacity, or whose triangle is degenerate, are left out. No allocation.
    pub fn write_lips(&mut self, runs: &[LipRun], pattern: &[V2], positions: &[V3]) {
        for run in runs {
            let pts = run.points();
            if self.lips.len() == self.lips.capacity()
                || self.lip_points_m.len() + pts.len() > self.lip_points_m.capacity()
            {
                return;
            }
            let Some(&[a, b, c]) = self.triangles.get(run.triangle as usize) else {
                continue;
            };
            let (Some(pa), Some(pb), Some(pc)) = (
                pattern.get(a as usize),
                pattern.get(b as usize),
                pattern.get(c as usize),
            ) else {
                continue;
            };
            let (e1, e2) = (pb - pa, pc - pa);
            let det = e1.x * e2.y - e1.y * e2.x;
            if det.abs() < 1e-18 {
                continue;
            }
            let start = self.lip_points_m.len() as u32;
            for q in pts {
                let d = V2::new(q[0], q[1]) - pa;
                let u = (d.x * e2.y - d.y * e2.x) / det;
                let v = (e1.x * d.y - e1.y * d.x) / det;
                let p = positions[a as usize] * (1.0 - u - v)
                    + positions[b as usize] * u
                    + positions[c as usize] * v;
                self.lip_points_m.push([p.x as f32, p.y as f32, p.z as f32]);
            }
            self.lips.push(LipPolyline {
                edge: run.edge,
                start,
                len: pts.len() as u32,
            });
        }
    }

    /// True if every position is finite.
    pub fn is_finite(&self) -> bool {
        self.positions_m
            .iter()
            .all(|p| p.iter().all(|c| c.is_finite()))
    }

    /// Writes the mesh as a Wavefront OBJ: `v` = 3D positions (m), `vt` = pattern positions (m,
    /// not normalised), faces `f v/vt …` (1-based, the same index for both).
    pub fn write_obj(&self, w: &mut impl std::io::Write) -> std::io::Result<()> {
        writeln!(w, "# Papier sheet, frame {}", self.frame)?;
        writeln!(
            w,
            "# v: world position (m); vt: 2D pattern position (m, not normalised)"
        )?;
        writeln!(w, "o sheet")?;
        for p in &self.positions_m {
            writeln!(w, "v {} {} {}", p[0], p[1], p[2])?;
        }
        for q in &self.pattern_m {
            writeln!(w, "vt {} {}", q[0], q[1])?;
        }
        for t in &self.triangles {
            let (a, b, c) = (t[0] + 1, t[1] + 1, t[2] + 1);
            writeln!(w, "f {a}/{a} {b}/{b} {c}/{c}")?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn obj_has_positions_pattern_and_faces() {
        let m = MeshSnapshot {
            frame: 3,
            positions_m: vec![[0.0, 0.0, 1.0], [0.1, 0.0, 1.0], [0.0, 0.1, 1.0]],
            pattern_m: vec![[0.0, 0.0], [0.1, 0.0], [0.0, 0.1]],
            tags: vec![VertexTag::Plain; 3],
            triangles: vec![[0, 1, 2]],
            ..MeshSnapshot::default()
        };
        let mut out = Vec::new();
        m.write_obj(&mut out).unwrap();
        let s = String::from_utf8(out).unwrap();
        assert_eq!(s.lines().filter(|l| l.starts_with("v ")).count(), 3);
        assert_eq!(s.lines().filter(|l| l.starts_with("vt ")).count(), 3);
        assert!(s.contains("f 1/1 2/2 3/3"));
    }

    #[test]
    fn a_lip_point_follows_its_triangle_into_3d() {
        let pattern = [V2::new(0.0, 0.0), V2::new(0.1, 0.0), V2::new(0.0, 0.1)];
        // The triangle stood up: pattern y becomes world z.
        let pos = [
            V3::new(0.0, 0.0, 1.0),
            V3::new(0.1, 0.0, 1.0),
            V3::new(0.0, 0.0, 1.1),
        ];
        let mut m = MeshSnapshot::with_capacity(3, 1);
        m.triangles.push([0, 1, 2]);
        let mut run = LipRun {
            edge: [0, 1],
            triangle: 0,
            len: 3,
            pattern_m: [[0.0; 2]; crate::tearing::lips::LIP_POINTS],
        };
        // Along the edge, and 1 mm past it (outside the triangle).
        run.pattern_m[1] = [0.05, -0.001];
        run.pattern_m[2] = [0.1, 0.0];
        m.write_lips(&[run], &pattern, &pos);
        assert_eq!(m.lips.len(), 1);
        let p = &m.lip_points_m;
        assert_eq!(p[0], [0.0, 0.0, 1.0]);
        assert!((p[1][0] - 0.05).abs() < 1e-6 && (p[1][2] - 0.999).abs() < 1e-6);
        assert!((p[2][0] - 0.1).abs() < 1e-6 && (p[2][2] - 1.0).abs() < 1e-6);
    }
}
