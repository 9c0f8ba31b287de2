//! # Mesh snapshot: a copy of the simulation mesh for display and export
//!
//! The simulation mesh S_P (3D positions, 2D pattern positions, triangles) copied out in
//! single precision, with the handle points, for the editor's 3D view and the OBJ export of
//! `papier-render --obj-dir`. [`MeshSnapshot::with_capacity`] reserves storage up front; writing
//! a mesh that fits the capacity does not allocate.

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
        }
    }

    /// Empties the snapshot, keeping its storage.
    pub fn clear(&mut self) {
        self.positions_m.clear();
        self.pattern_m.clear();
        self.tags.clear();
        self.triangles.clear();
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
        };
        let mut out = Vec::new();
        m.write_obj(&mut out).unwrap();
        let s = String::from_utf8(out).unwrap();
        assert_eq!(s.lines().filter(|l| l.starts_with("v ")).count(), 3);
        assert_eq!(s.lines().filter(|l| l.starts_with("vt ")).count(), 3);
        assert!(s.contains("f 1/1 2/2 3/3"));
    }
}
