//! Development probe: why the vertices a strip cut added are, or are not, taken out again
//! (`GeometryConfig::coarsen_flat_regions`, `sim_core::sheet::coarsen`).
//!
//! `cargo run --release -p sim-core --example coarsen_probe -- NAME[@SEED]|SCRIPT.toml [EVERY]`
//!
//! Plays the scene with strip cutting on and, every EVERY frames (default 100) and at the end,
//! lists each S_P vertex beyond the initial lattice that is not singular: its star's largest
//! |dihedral| (rad), whether a triangle of its star is curved, its largest speed relative to
//! a neighbour (m/s), whether an edge of its star is creased, and what the collapse says.
use sim_core::geometry::TriKind;
use sim_core::room::RoomConfig;
use sim_core::scenario;
use sim_core::script_runner::ScriptRunner;
use sim_core::sheet::coarsen::collapse_vertex;
use sim_core::sim::{FrameOutput, Sim, SimConfig};

fn report(sim: &Sim, lattice_nv: usize) {
    let sp = &sim.sheet().sp;
    let g = sim.geometry();
    println!(
        "frame {}: {} vertices ({} lattice), {} cuts, {} taken out",
        sim.frame(),
        sp.num_vertices(),
        lattice_nv,
        sim.cut_strips(),
        sim.collapsed_vertices()
    );
    for v in lattice_nv as u32..sp.num_vertices() as u32 {
        if sp.singular.contains(&v) {
            continue;
        }
        let (mut dih, mut creased, mut rel) = (0.0f64, false, 0.0f64);
        for &j in sp.topo.neighbours(v) {
            let e = sp.topo.find_edge(v, j).unwrap() as usize;
            dih = dih.max(g.edge_dihedral_rad[e].abs());
            creased |= sp.edge_rest_angle[e] != 0.0 || sp.edge_damage[e] != 0.0;
            rel = rel.max((sp.vel[v as usize] - sp.vel[j as usize]).norm());
        }
        let curved = (0..sp.num_triangles())
            .filter(|&t| sp.triangles[t].contains(&v))
            .any(|t| g.tri_kind[t] != TriKind::Flat);
        let c = collapse_vertex(sp, v, sim_core::geometry::THETA0_RAD);
        println!(
            "  v {v:4}: dihedral {dih:.4} curved {curved:5} rel speed {rel:.4} creased {creased:5} border {:5} -> {}",
            sp.topo.vertex_on_boundary[v as usize],
            match c {
                Ok(c) => format!("collapses into {}", c.into),
                Err(e) => e.to_string(),
            }
        );
    }
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let name = args
        .first()
        .map_or("s1_slide_release_pinch", String::as_str);
    let every: u64 = args.get(1).and_then(|a| a.parse().ok()).unwrap_or(100);
    // A scene name, or a script file.
    let script = if name.ends_with(".toml") {
        sim_core::script::Script::from_file(std::path::Path::new(name)).expect("script file")
    } else {
        scenario::get_seeded(name).expect("scenario")
    };
    let mut cfg = SimConfig::default();
    cfg.geometry.cut_strips = true;
    let mut runner =
        ScriptRunner::new(&script, cfg.frame_rate_hz, RoomConfig::default()).expect("runner");
    let mut sim = runner.start(cfg);
    let lattice_nv = sim.sheet().sp.num_vertices();
    let mut out = FrameOutput::default();
    while runner.drive(&mut sim, &mut out) {
        if sim.frame().is_multiple_of(every) {
            report(&sim, lattice_nv);
        }
    }
    report(&sim, lattice_nv);
}
