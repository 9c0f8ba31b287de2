//! # Stress driver: random, hostile command streams
//!
//! Drives a [`Sim`] with a seeded random stream of commands chosen to break it: maximal jumps
//! of every gesture (min ↔ max in one frame), non-finite and absurd values (NaN, ±∞, 10³⁰),
//! grab/release storms (several slots per frame, at random grips), crumple on/off, resets,
//! size/material/room switches (table and wall on/off, heights jumping across the sheet), and
//! quiet stretches in which the sheet may fall asleep. After every frame it checks the
//! invariants the physics must keep:
//!
//! - every position and velocity finite, inside the room box;
//! - no flipped triangle (orientation continuity, [`crate::metrics`], at the solver's own
//!   resolution: a frame solved as shorter substeps is continuous over each of them, sim.rs
//!   "A substep solved as shorter ones"), no degenerate triangle and no recovered substep;
//! - bounded speed (no explosion) and bounded strain;
//! - a valid mesh (topology and S_G consistency, checked periodically and at the end);
//! - exact continuation of a saved sheet (checked periodically): the sheet is saved
//!   ([`Sim::save`]) and restored ([`Sim::restore`]) with the session's present configuration,
//!   the restored sheet must save back to what was saved, the next frame's commands go to
//!   both, and after each of the next `restore_check_frames` frames both must save to the same
//!   state, bit for bit, and their frames must have made the same sound input (events,
//!   resonators, friction sources). This is what a project reopened in a DAW relies on,
//!   checked at states no scenario reaches (mid-storm, pinned, split or undone frames, pending
//!   insertions).
//!
//! **About the strain bound.** The hostile stream makes hands contradict each other (eight
//! crumple points squeezing while edge pinches pull, a table rising under held paper, …). The
//! grip-force limit of the hands ([`crate::gesture_rig`]) bounds the forces, but a frame of
//! contradiction can still stretch a triangle next to a hand far beyond anything paper survives
//! (paper tears at a few %); [`MAX_STRAIN`] = 1 (a triangle never stretched to twice its
//! length or squeezed to nothing) is the bound the physics must never exceed under this stream
//! (the worst seen in 10⁶ frames is reported by the long run). The library scenarios stay
//! far below (see the benchmark report).
//!
//! Used by the stress test (`tests/stress.rs`, 10⁵ frames) and the long run
//! (`cargo run --release -p papier-lab -- stress`, 10⁶ frames).

use rand::{RngExt, SeedableRng};

use crate::control::{Command, GestureParam, GrabSlot, Material, SheetSize};
use crate::room::RoomConfig;
use crate::sim::{FrameOutput, RestoreError, SavedSheet, Sim, SimConfig};
use crate::sound_input::SoundFrame;
use serde::{Deserialize, Serialize};

/// Largest vertex speed accepted, m/s (paper thrown hard moves at a few m/s).
pub const MAX_SPEED_M_S: f64 = 50.0;
/// Largest principal strain deviation |λ − 1| accepted under the hostile stream.
pub const MAX_STRAIN: f64 = 1.0;
/// Frames of a "hold still" phase: the shake stops and no other command comes.
pub const HOLD_FRAMES: u64 = 600;
/// In a hold, the sheet must be asleep this many frames after the rig (its gestures and its
/// hands' travel), the room and a tear running under a held pull stopped moving (2 s: the
/// hostile stream leaves sheets flung at metres per second or dropped from a raised table,
/// which take longer than the second a sheet held still by the user's gestures takes,
/// `tests/rest.rs`).
pub const HOLD_SETTLE_FRAMES: u64 = 400;
/// Largest strain of a sheet at rest in a hold.
pub const HOLD_MAX_STRAIN: f64 = 0.1;

/// What to run.
#[derive(Clone, Copy, Debug)]
pub struct StressConfig {
    /// Seed of the command stream.
    pub seed: u64,
    /// Frames to step.
    pub frames: u64,
    /// Initial sim configuration.
    pub sim: SimConfig,
    /// Allow size changes (they rebuild the sheet at another resolution).
    pub change_size: bool,
    /// Check the mesh validity every this many frames.
    pub validate_every: u64,
    /// Check every this many frames that a saved and restored sheet continues bit-identically
    /// (0: never).
    pub restore_check_every: u64,
    /// Frames the restored copy is stepped alongside and compared (at least 1): a state kept
    /// between frames and not saved may show only in a later frame.
    pub restore_check_frames: u64,
    /// Print every command and frame to stderr (debugging).
    pub trace: bool,
}

impl Default for StressConfig {
    fn default() -> Self {
        Self {
            seed: 1,
            frames: 10_000,
            sim: SimConfig::default(),
            change_size: true,
            validate_every: 1000,
            restore_check_every: 1000,
            restore_check_frames: 4,
            trace: false,
        }
    }
}

impl StressConfig {
    /// A session of the test suite's stress run (`sim-core/tests/stress.rs`): a coarser mesh
    /// than the default (spacing L_paper/5, ~40 triangles on A4) so that four sessions fit plain
    /// `cargo test`, size changes, the mesh checked every 500 frames and a save and restore
    /// every 250. The lab's `stress-fixture` replays these with `TEST_SESSION=1`.
    pub fn test_session(seed: u64, frames: u64) -> Self {
        Self {
            seed,
            frames,
            sim: SimConfig {
                mesh: crate::sheet::MeshConfig { spacing_frac: 0.2 },
                ..SimConfig::default()
            },
            change_size: true,
            validate_every: 500,
            restore_check_every: 250,
            restore_check_frames: 4,
            trace: false,
        }
    }
}

/// The outcome of a stress run.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct StressReport {
    /// Frames stepped.
    pub frames: u64,
    /// Frames in which the sheet slept.
    pub asleep_frames: u64,
    /// Commands applied.
    pub commands: u64,
    /// Largest vertex speed seen, m/s.
    pub max_speed_m_s: f64,
    /// Largest kinetic energy seen, J.
    pub max_kinetic_energy_j: f64,
    /// Largest strain deviation seen.
    pub max_strain: f64,
    /// Flipped triangles summed over frames.
    pub flips: u64,
    /// Recovered substeps summed over frames.
    pub recoveries: u64,
    /// Most interior singular vertices on one sheet.
    pub max_singular: usize,
    /// Largest c_mean of one frame, %.
    pub max_c_mean_pct: f64,
    /// Most S_P vertices on one sheet.
    pub max_vertices: usize,
    /// Frames stepped with a torn sheet (the mesh cut at least once).
    pub torn_frames: u64,
    /// Frames stepped with the sheet in two pieces.
    pub separated_frames: u64,
    /// "Hold still" phases played to their end.
    pub holds: u64,
    /// Longest wait from the rig's last motion to the sheet's sleep in a hold, frames.
    pub max_settle_frames: u64,
    /// First violation, if any (frame, description).
    pub failure: Option<(u64, String)>,
}

impl StressReport {
    /// True if no invariant was violated.
    pub fn ok(&self) -> bool {
        self.failure.is_none()
    }
}

fn wild_value(rng: &mut rand_pcg::Pcg32, g: GestureParam) -> f32 {
    let (lo, hi) = g.range();
    match rng.random_range(0..10u32) {
        0 => f32::NAN,
        1 => {
            if rng.random::<bool>() {
                f32::INFINITY
            } else {
                f32::NEG_INFINITY
            }
        }
        2 => {
            if rng.random::<bool>() {
                1e30
            } else {
                -1e30
            }
        }
        3 | 4 => lo,
        5 | 6 => hi,
        _ => rng.random_range(lo..=hi),
    }
}

fn random_command(rng: &mut rand_pcg::Pcg32, change_size: bool) -> Command {
    let slot = GrabSlot::ALL[rng.random_range(0..GrabSlot::ALL.len())];
    match rng.random_range(0..100u32) {
        0..=39 => {
            let g = GestureParam::ALL[rng.random_range(0..GestureParam::COUNT)];
            Command::Gesture {
                param: g,
                value: wild_value(rng, g),
            }
        }
        40..=59 => Command::Grab {
            slot,
            grip: match rng.random_range(0..6u32) {
                0 => f32::NAN,
                1 => 7.0,
                _ => rng.random_range(0.0..=1.0),
            },
        },
        60..=79 => Command::Release { slot },
        80..=83 => Command::ReleaseAll,
        84..=86 => Command::Reset,
        87..=89 if change_size => Command::Size(SheetSize::ALL[rng.random_range(0..4)]),
        87..=92 => Command::Material(Material::ALL[rng.random_range(0..3)]),
        93..=94 => Command::Seed(rng.random()),
        _ => Command::Room(RoomConfig {
            table: rng.random_range(0..4u32) != 0,
            table_height_cm: match rng.random_range(0..5u32) {
                0 => f32::NAN,
                1 => 1e9,
                _ => rng.random_range(30.0..130.0),
            },
            wall: rng.random::<bool>(),
            wall_dist_cm: match rng.random_range(0..5u32) {
                0 => f32::INFINITY,
                _ => rng.random_range(0.0..60.0),
            },
        }),
    }
}

/// Runs a stress session and reports the first violated invariant (if any).
pub fn run(cfg: &StressConfig) -> StressReport {
    run_with(cfg, |_, _| {})
}

/// [`run`], calling `inspect(frame, sim)` after every frame (debugging and tests).
pub fn run_with(cfg: &StressConfig, mut inspect: impl FnMut(u64, &Sim)) -> StressReport {
    let mut rng = rand_pcg::Pcg32::seed_from_u64(cfg.seed);
    let mut sim = Sim::new(cfg.sim);
    let mut out = FrameOutput::default();
    let mut rep = StressReport::default();
    // Bursts: a busy phase (commands nearly every frame), a calm phase (rare commands, long
    // enough for the sheet to settle and sleep), a storm (many commands per frame), and a
    // hold: the shake stops, nothing else changes, and the sheet must come to rest (asleep
    // within HOLD_SETTLE_FRAMES of the rig's last motion, silent and unstrained while asleep).
    let mut singular_pos: Vec<crate::math::V2> = Vec::new();
    let mut sheet_frame = 0u64;
    let mut tear_steps = 0u32;
    let mut phase_left = 0u64;
    let mut phase = 0u32;
    // The restored copy of the sheet, stepped alongside for `restore_check_frames` frames, and
    // how many of them are left.
    let mut twin: Option<(Sim, u64)> = None;
    let mut twin_out = FrameOutput::default();
    // In a hold: the frame at which the rig last moved, and since when the sheet sleeps.
    let mut hold_moved_at = 0u64;
    let mut hold_asleep_at: Option<u64> = None;
    for f in 0..cfg.frames {
        if phase_left == 0 {
            phase = rng.random_range(0..4);
            phase_left = if phase == 3 {
                HOLD_FRAMES
            } else {
                rng.random_range(20..400)
            };
            if phase == 3 {
                let c = Command::Gesture {
                    param: GestureParam::ShakeDepth,
                    value: 0.0,
                };
                sim.apply(c);
                if let Some((t, _)) = twin.as_mut() {
                    t.apply(c);
                }
                rep.commands += 1;
                hold_moved_at = f;
                hold_asleep_at = None;
            }
        }
        phase_left -= 1;
        let n_cmds = match phase {
            0 => u32::from(rng.random_range(0..3u32) == 0),
            1 => u32::from(rng.random_range(0..200u32) == 0),
            2 => rng.random_range(0..6u32),
            _ => 0,
        };
        for _ in 0..n_cmds {
            let c = random_command(&mut rng, cfg.change_size);
            if cfg.trace {
                eprintln!("  {c:?}");
            }
            sim.apply(c);
            if let Some((t, _)) = twin.as_mut() {
                t.apply(c);
            }
            rep.commands += 1;
        }
        sim.step(&mut out);
        if let Some((mut t, left)) = twin.take() {
            t.step(&mut twin_out);
            let after = cfg.restore_check_frames.max(1) - left + 1;
            let (a, b) = (sim.save(), t.save());
            if a != b {
                rep.failure = Some((
                    f,
                    format!(
                        "the sheet saved and restored {after} frame(s) before does not \
                         continue bit-identically: {} differ",
                        saved_differences(&a, &b).join(", ")
                    ),
                ));
                return rep;
            }
            if let Some(what) = sound_difference(&out.sound, &twin_out.sound) {
                rep.failure = Some((
                    f,
                    format!(
                        "the sheet saved and restored {after} frame(s) before does not sound \
                         the same: {what} differ"
                    ),
                ));
                return rep;
            }
            if left > 1 {
                twin = Some((t, left - 1));
            }
        }
        inspect(f, &sim);
        let st = out.stats;
        if cfg.trace {
            eprintln!(
                "frame {f}: asleep {} held {} strain {:.3} vmax {:.3} flips {} it {} halvings {}",
                st.asleep,
                st.num_held,
                st.max_strain,
                st.max_speed_m_s,
                st.num_flipped,
                st.iterations,
                st.halvings
            );
        }
        rep.frames += 1;
        rep.asleep_frames += u64::from(st.asleep);
        rep.flips += u64::from(st.num_flipped);
        rep.recoveries += u64::from(st.recoveries);
        let m = sim.metrics();
        rep.max_speed_m_s = rep.max_speed_m_s.max(m.max_speed_m_s);
        rep.max_kinetic_energy_j = rep.max_kinetic_energy_j.max(m.kinetic_energy_j);
        rep.max_strain = rep.max_strain.max(m.max_strain);
        if let Some(msg) = check(&sim, &out) {
            rep.failure = Some((f, msg));
            return rep;
        }
        if phase == 3 {
            // A table or wall still easing to where a room command put it is a change in
            // progress too, and so is a hand still travelling to its target (a hand crosses
            // 35 cm at 0.4 m/s on a 10 cm square: the travel clamp is 2 % of its length a
            // frame). So is a tear running on under a held pull (the pull is a force: the tip
            // runs while the criterion holds, sim/tear.rs) and the mesh step it announces.
            let tearing = out.sound.tear.speed_m_s > 0.0 || sim.tear().pending;
            if sim.rig().is_moving()
                || sim.rig().hands_travelling()
                || sim.obstacles().is_moving()
                || tearing
            {
                hold_moved_at = f;
            }
            if st.asleep {
                hold_asleep_at.get_or_insert(f);
            } else {
                hold_asleep_at = None;
            }
            let since = f - hold_moved_at;
            if since > HOLD_SETTLE_FRAMES {
                let a = sim.analysis_stats();
                let problem = if !st.asleep {
                    Some(format!(
                        "held still, the sheet is awake {since} frames after the rig stopped \
                         (vmax {:.4} m/s, strain {:.3})",
                        m.max_speed_m_s, m.max_strain
                    ))
                } else if a.crumple_events + a.clac_events + a.impact_events > 0 {
                    Some("held still and asleep, the sheet made a crumple event".into())
                } else if m.max_strain > HOLD_MAX_STRAIN {
                    Some(format!(
                        "held still, the sheet rests at strain {:.3}",
                        m.max_strain
                    ))
                } else {
                    None
                };
                if let Some(msg) = problem {
                    rep.failure = Some((f, msg));
                    return rep;
                }
            }
            if phase_left == 0 {
                rep.holds += 1;
                if let Some(a) = hold_asleep_at {
                    rep.max_settle_frames =
                        rep.max_settle_frames.max(a.saturating_sub(hold_moved_at));
                }
            }
        }
        // Geometry layer: the singular count never decreases on one sheet (a reset or size
        // change starts a new sheet, frame counter back to 0; a tear step may take the
        // singular vertices it runs through into its lips), singular points never move in
        // 2D, c_mean stays bounded.
        let g = sim.geometry();
        let n = g.singular.len();
        let torn_on = sim.tear().mesh_steps != tear_steps;
        tear_steps = sim.tear().mesh_steps;
        if sim.frame() > sheet_frame && !torn_on {
            if n < singular_pos.len() {
                rep.failure = Some((f, format!("singular count {} → {n}", singular_pos.len())));
                return rep;
            }
            for (k, p) in singular_pos.iter().enumerate() {
                if g.singular[k].pos2 != *p {
                    rep.failure = Some((f, format!("singular point {k} moved in 2D")));
                    return rep;
                }
            }
        } else {
            singular_pos.clear();
        }
        sheet_frame = sim.frame();
        for s in &g.singular[singular_pos.len()..] {
            singular_pos.push(s.pos2);
        }
        rep.max_singular = rep.max_singular.max(n);
        rep.max_vertices = rep.max_vertices.max(sim.sheet().sp.num_vertices());
        rep.torn_frames += u64::from(sim.tear().mesh_steps > 0);
        rep.separated_frames += u64::from(sim.tear().separated);
        rep.max_c_mean_pct = rep.max_c_mean_pct.max(m.c_mean_pct);
        if m.c_mean_pct.is_nan() || m.c_mean_pct >= MAX_C_MEAN_PCT {
            rep.failure = Some((f, format!("c_mean {} %", m.c_mean_pct)));
            return rep;
        }
        if cfg.validate_every > 0
            && (f + 1) % cfg.validate_every == 0
            && let Err(e) = validate_mesh(&sim)
        {
            rep.failure = Some((f, e));
            return rep;
        }
        if cfg.restore_check_every > 0 && (f + 1) % cfg.restore_check_every == 0 {
            let saved = sim.save();
            match Sim::restore(*sim.config(), &saved) {
                Ok(t) => {
                    // Restoring must take every field as saved (nothing recomputed from the
                    // sheet differently from the frame that saved it).
                    let back = t.save();
                    if back != saved {
                        rep.failure = Some((
                            f,
                            format!(
                                "the restored sheet saves differently from what it was saved \
                                 as: {} differ",
                                saved_differences(&saved, &back).join(", ")
                            ),
                        ));
                        return rep;
                    }
                    twin = Some((t, cfg.restore_check_frames.max(1)));
                }
                Err(e) => {
                    rep.failure = Some((f, format!("the saved sheet does not restore: {e}")));
                    return rep;
                }
            }
        }
    }
    if let Err(e) = validate_mesh(&sim) {
        rep.failure = Some((cfg.frames, e));
    }
    rep
}

/// A sheet saved from a stress session with the room the session had put it in: a regression
/// fixture (`tests/fixtures/`, written by `cargo run --release -p papier-lab -- stress-fixture`).
///
/// [`Sim::restore`] takes the room from the configuration it is given, and the stream's `Room`
/// commands move the table, the wall and the hands' home height; a sheet restored into the
/// default room does not continue the session's frame bit-identically; restored into the
/// session's room, it does.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct StressFixture {
    /// The session's room when the sheet was saved.
    pub room: RoomConfig,
    /// The sheet.
    pub sheet: SavedSheet,
}

impl StressFixture {
    /// Saves `sim` with its room.
    pub fn of(sim: &Sim) -> Self {
        Self {
            room: sim.config().room,
            sheet: sim.save(),
        }
    }

    /// Restores the sheet with `base`'s settings in the fixture's room.
    pub fn restore(&self, base: SimConfig) -> Result<Sim, RestoreError> {
        Sim::restore(
            SimConfig {
                room: self.room,
                ..base
            },
            &self.sheet,
        )
    }
}

/// Largest accepted per-frame c_mean, % (the seeds' heavy crumple averages 1.47 %).
pub const MAX_C_MEAN_PCT: f64 = 5.0;

/// The fields in which two saved sheets differ.
fn saved_differences(a: &SavedSheet, b: &SavedSheet) -> Vec<&'static str> {
    let mut d = Vec::new();
    macro_rules! field {
        ($($f:ident),*) => {
            $(if a.$f != b.$f {
                d.push(stringify!($f));
            })*
        };
    }
    field!(
        version,
        size,
        material,
        seed,
        frame,
        pattern_m,
        triangles,
        positions_m,
        velocities_m_s,
        edge_rest_angle_rad,
        edge_damage,
        singular_vertices,
        rng,
        rig,
        rig_ownership,
        rig_suppressed,
        rig_ownership_pending,
        obstacle_offsets_m,
        obstacle_active,
        asleep,
        quiet_frames,
        geometry,
        contact_boosts,
        fibre_seed,
        hand_defs,
        sound_history,
        tear
    );
    if let (Some(ga), Some(gb)) = (&a.geometry, &b.geometry) {
        macro_rules! geometry_field {
            ($($f:ident),*) => {
                $(if ga.$f != gb.$f {
                    d.push(concat!("geometry.", stringify!($f)));
                })*
            };
        }
        geometry_field!(
            curved,
            refractory_until,
            singular,
            rng,
            iso_undriven_compression,
            pending_singular,
            pending_flip
        );
    }
    d
}

/// What differs between the sound input of two frames (their events and sources, not the
/// unused slots of their fixed-size arrays), if anything.
fn sound_difference(a: &SoundFrame, b: &SoundFrame) -> Option<&'static str> {
    if a.crumple() != b.crumple() {
        Some("crumple events")
    } else if a.friction() != b.friction() {
        Some("friction sources")
    } else if a.tear != b.tear {
        Some("tear states")
    } else if (a.frame, a.time_s) != (b.frame, b.time_s) {
        Some("frame clocks")
    } else if (a.dropped_crumple, a.dropped_friction) != (b.dropped_crumple, b.dropped_friction) {
        Some("dropped-event counts")
    } else {
        None
    }
}

/// Per-frame invariants.
fn check(sim: &Sim, out: &FrameOutput) -> Option<String> {
    let sp = &sim.sheet().sp;
    for (i, (p, v)) in sp.pos.iter().zip(&sp.vel).enumerate() {
        if !(crate::math::finite3(p) && crate::math::finite3(v)) {
            return Some(format!("vertex {i} is not finite"));
        }
        if p.x.abs() > 50.0 || p.y.abs() > 50.0 || p.z < -0.5 || p.z > 50.0 {
            return Some(format!("vertex {i} left the room: {p:?}"));
        }
    }
    let st = &out.stats;
    if st.num_flipped > 0 {
        return Some(format!("{} flipped triangles", st.num_flipped));
    }
    if st.recoveries > 0 {
        return Some(format!("{} recovered substeps", st.recoveries));
    }
    let m = sim.metrics();
    if m.max_speed_m_s.is_nan() || m.max_speed_m_s > MAX_SPEED_M_S {
        return Some(format!("speed {} m/s", m.max_speed_m_s));
    }
    if m.max_strain.is_nan() || m.max_strain > MAX_STRAIN {
        return Some(format!("strain {}", m.max_strain));
    }
    if m.num_degenerate > 0 {
        return Some(format!("{} degenerate triangles", m.num_degenerate));
    }
    None
}

/// Structural validity of the sheet.
pub fn validate_mesh(sim: &Sim) -> Result<(), String> {
    let sheet = sim.sheet();
    sheet.sp.topo.validate()?;
    // Each piece a disc (one until a tear separates the sheet).
    sheet.sp.topo.validate_pieces()?;
    sheet.sg.validate(&sheet.sp)?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn short_stress_run_is_clean() {
        let cfg = StressConfig {
            frames: 300,
            sim: SimConfig {
                size: SheetSize::A6,
                mesh: crate::sheet::MeshConfig { spacing_frac: 0.25 },
                ..SimConfig::default()
            },
            validate_every: 50,
            restore_check_every: 7,
            ..StressConfig::default()
        };
        let r = run(&cfg);
        assert!(r.ok(), "{:?}", r.failure);
        assert!(r.commands > 30);
    }
}
