//! # The sheet as Wavefront OBJ files (`--obj-dir`): `frame_00000.obj`, … with `v` = positions in
//! metres and `vt` = the 2D pattern position in metres (not normalized), so the isometry can be
//! measured from the files ([`sim_core::MeshSnapshot::write_obj`]).

use std::io::BufWriter;
use std::path::Path;

use sim_core::{MeshSnapshot, Sim};

use super::OfflineError;

/// Writes `sim`'s mesh as `dir/frame_{index:05}.obj` (through `mesh`, a snapshot of sufficient
/// capacity).
pub fn write_obj(
    dir: &Path,
    index: u64,
    sim: &Sim,
    mesh: &mut MeshSnapshot,
) -> Result<(), OfflineError> {
    sim.write_mesh(mesh);
    let path = dir.join(format!("frame_{index:05}.obj"));
    let file = std::fs::File::create(&path)
        .map_err(|e| OfflineError::Output(format!("cannot write {}: {e}", path.display())))?;
    let mut w = BufWriter::new(file);
    mesh.write_obj(&mut w)
        .and_then(|_| std::io::Write::flush(&mut w))
        .map_err(|e| OfflineError::Output(format!("cannot write {}: {e}", path.display())))
}
