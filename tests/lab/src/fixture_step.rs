//! What does a saved sheet do in its next frames? Restores a saved sheet (JSON, as
//! `stress-fixture` writes it, in its room; a bare saved sheet in the default room) and steps it
//! a few frames, printing each frame's largest strain, halvings, iterations, pinned, held-back
//! and split substeps and flipped triangles.
//!
//! `cargo run --release -p papier-lab -- fixture-step STATE.json [FRAMES]` (default 3 frames);
//! `NOGEOM=1` steps with the geometry layer off, `STATS=1` prints each frame's whole stats,
//! `TEST_SESSION=1` steps with the test suite's stress session's configuration,
//! `NOSHEETCONTACT=1` without sheet–sheet contact; `PIECES=1` lists each piece of the sheet
//! after the last frame (triangles, vertices, fastest speed, held vertices and their hands);
//! `CROSSINGS=1` lists each frame's crossing triangle pairs (how many between pieces) and the
//! closest approach; `STRAINEST=1` the most strained triangle and its vertices' hands;
//! `HANDS=1` each active hand's travel in the frame and its slip.

use anyhow::Context;
use sim_core::sim::{FrameOutput, SavedSheet, SimConfig};
use sim_core::stress::StressFixture;

use crate::args::{at_most, bad, nth};

pub const USAGE: &str = "STATE.json [FRAMES]";

pub fn run(args: &[String]) -> anyhow::Result<()> {
    at_most(args, 2)?;
    let path = args.first().ok_or_else(|| bad("STATE.json is missing"))?;
    let frames: u32 = nth(args, 1, "FRAMES")?.unwrap_or(3);
    let json = std::fs::read_to_string(path).with_context(|| format!("reading {path}"))?;
    let fixture = match serde_json::from_str::<StressFixture>(&json) {
        Ok(f) => f,
        Err(_) => StressFixture {
            room: SimConfig::default().room,
            sheet: serde_json::from_str::<SavedSheet>(&json)
                .with_context(|| format!("{path} is neither a fixture nor a saved sheet"))?,
        },
    };
    // TEST_SESSION=1: the test suite's coarse session's configuration (its slip scale).
    let mut cfg = if std::env::var("TEST_SESSION").is_ok_and(|v| v == "1") {
        sim_core::stress::StressConfig::test_session(0, 0).sim
    } else {
        SimConfig::default()
    };
    cfg.geometry.enabled = std::env::var("NOGEOM").is_err();
    if std::env::var("NOSHEETCONTACT").is_ok() {
        cfg.solver.sheet_contact = false;
    }
    let mut sim = fixture.restore(cfg).context("restoring the sheet")?;
    let mut out = FrameOutput::default();
    for k in 1..=frames {
        let before = sim.sheet().sp.pos.clone();
        sim.step(&mut out);
        let s = &out.stats;
        if std::env::var("FLIPS").is_ok() && s.num_flipped > 0 {
            // FLIPS=1: each triangle whose normal turned by more than 90° this frame.
            let sp = &sim.sheet().sp;
            for (t, tri) in sp.triangles.iter().enumerate() {
                let normal = |x: &[sim_core::math::V3]| {
                    let [a, b, c] = tri.map(|i| x[i as usize]);
                    (b - a).cross(&(c - a))
                };
                if before.len() != sp.pos.len() {
                    break;
                }
                let (n0, n1) = (normal(&before), normal(&sp.pos));
                if n0.dot(&n1) >= 0.0 {
                    continue;
                }
                println!(
                    "  flipped triangle {t} {tri:?}: area {:.2e} -> {:.2e} m² (rest {:.2e}), turned {:.0}°",
                    0.5 * n0.norm(),
                    0.5 * n1.norm(),
                    sp.tri_rest[t].area_m2,
                    n0.angle(&n1).to_degrees()
                );
                for &v in tri {
                    let v = v as usize;
                    let c = sim.contacts()[v];
                    let boundary = sp
                        .topo
                        .edges
                        .iter()
                        .any(|e| e.is_boundary() && e.v.contains(&(v as u32)));
                    println!(
                        "    vertex {v}: moved {:.2} mm, held {:?}, contact {} {:?}, boundary {boundary}, pos {:?}",
                        (sp.pos[v] - before[v]).norm() * 1e3,
                        sim.rig().hand_of(v as u32),
                        c.in_contact,
                        c.obstacle,
                        sp.pos[v].as_slice()
                    );
                }
            }
        }
        if std::env::var("STATS").is_ok() {
            println!("{s:?}");
        }
        if std::env::var("FASTEST").is_ok() {
            let sp = &sim.sheet().sp;
            let (v, speed) = sp
                .vel
                .iter()
                .enumerate()
                .map(|(i, v)| (i, v.norm()))
                .fold((0, 0.0), |a, b| if b.1 > a.1 { b } else { a });
            let c = sim.contacts()[v];
            let n = sp
                .triangles
                .iter()
                .enumerate()
                .filter(|(_, t)| t.contains(&(v as u32)))
                .fold(sim_core::math::V3::zeros(), |a, (t, _)| {
                    a + sp.tri_normal(t)
                });
            let normal_frac = if speed > 0.0 && n.norm() > 0.0 {
                (sp.vel[v].dot(&n) / n.norm() / speed).abs()
            } else {
                0.0
            };
            println!("  normal fraction {normal_frac:.2}");
            println!(
                "  fastest vertex {v} at {:.2} mm/s, pos {:?}, vel {:?}, held {:?}, contact {} {:?}, isometry {:.2e} m, asleep {}",
                speed * 1e3,
                sp.pos[v].as_slice(),
                sp.vel[v].as_slice(),
                sim.rig().hand_of(v as u32),
                c.in_contact,
                c.obstacle,
                sim.geometry().isometry.max_disp_m,
                s.asleep
            );
        }
        if std::env::var("STRAINEST").is_ok() {
            // STRAINEST=1: the most strained triangle, its vertices' hands and strains.
            let sp = &sim.sheet().sp;
            let (t, strain) = (0..sp.num_triangles())
                .map(|t| {
                    let x = sp.triangles[t].map(|i| sp.pos[i as usize]);
                    (t, sim_core::metrics::triangle_strain(sp, t, x))
                })
                .fold((0, 0.0), |a, b| if b.1 > a.1 { b } else { a });
            let held = sp.triangles[t].map(|v| sim.rig().hand_of(v));
            println!(
                "  most strained triangle {t} {:?} at {strain:.3}, hands {held:?}",
                sp.triangles[t]
            );
            for k in held.iter().flatten() {
                let d = sim.rig().hand_def(*k);
                println!(
                    "    hand {k}: handle vertices {:?}, ring {:?}, state {:?}",
                    &d.vertices[..d.num_mains as usize],
                    &d.vertices[d.num_mains as usize..d.num_vertices as usize],
                    sim.rig().state.hands[*k]
                );
            }
        }
        if std::env::var("HANDS").is_ok() {
            // HANDS=1: each active hand's travel this frame and whether it slipped.
            for (k, h) in sim.rig().state.hands.iter().enumerate() {
                if h.active {
                    let d = h.pose.pos() - h.prev_pose.pos();
                    println!(
                        "    hand {k}: moved {:.3} mm {:?}, slipping {}, sliding {}, slip gain {:.3}",
                        d.norm() * 1e3,
                        (d * 1e3).as_slice(),
                        h.slipping,
                        h.sliding,
                        h.slip_gain
                    );
                }
            }
        }
        if std::env::var("CROSSINGS").is_ok() {
            let sp = &sim.sheet().sp;
            let mut prox = sim_core::self_proximity::SelfProximity::new();
            let mut pairs = Vec::new();
            prox.for_each_crossing(sp, |a, b| pairs.push((a, b)));
            let closest = prox.closest_approach_m(sp, 0.01);
            let mut piece = vec![0usize; sp.num_triangles()];
            for (i, tris) in sp.topo.pieces().iter().enumerate() {
                for &t in tris {
                    piece[t as usize] = i;
                }
            }
            let across = pairs
                .iter()
                .filter(|(a, b)| piece[*a as usize] != piece[*b as usize])
                .count();
            println!(
                "  crossings {pairs:?} ({across} between pieces), closest {:.3} mm",
                closest * 1e3
            );
        }
        if std::env::var("PIECES").is_ok() && k == frames {
            let sp = &sim.sheet().sp;
            for (i, tris) in sp.topo.pieces().iter().enumerate() {
                let mut verts: Vec<u32> = tris
                    .iter()
                    .flat_map(|&t| sp.triangles[t as usize])
                    .collect();
                verts.sort_unstable();
                verts.dedup();
                let held: Vec<(u32, usize)> = verts
                    .iter()
                    .filter_map(|&v| sim.rig().hand_of(v).map(|h| (v, h)))
                    .collect();
                let vmax = verts
                    .iter()
                    .map(|&v| sp.vel[v as usize].norm())
                    .fold(0.0, f64::max);
                println!(
                    "  piece {i}: {} triangles, {} vertices, vmax {:.1} mm/s, held {held:?}",
                    tris.len(),
                    verts.len(),
                    vmax * 1e3
                );
            }
        }
        println!(
            "+{k}: strain {:.3}, halvings {}, iterations {}, pinned {}, held back {}, split {}, flipped {}",
            sim.metrics().max_strain,
            s.halvings,
            s.iterations,
            s.pinned_substeps,
            s.held_back_substeps,
            s.split_substeps,
            s.num_flipped
        );
    }
    Ok(())
}
