//! # The tear in the frame loop: `tear_amount` and `tear_steer` tear the sheet
//!
//! The seeds' procedural two-hand tear (MIG 2015 §3–4, `../shared/seeds/003_8cfb4a33a3603fcd.txt`
//! M:85–138; thesis §3.2, `../shared/seeds/000_cb4d91e46ec5927f.txt` T:1310–1419) driven by two
//! gesture values instead of a mouse:
//!
//! 1. **Start** (M:114, T:1361): when `tear_amount` first rises, the tear starts on the back
//!    edge (+y) at `tear_pos` across the width, moved by up to [`START_JITTER_M`] by the tear's
//!    own random stream (the seeds pick a random point between the index fingers; the sheet's
//!    stream is not touched, so singular points land where they did).
//! 2. **Macro tip** (eq. 3.1, M:118, T:1370; [`crate::tearing::tip`]): the rise Δθ of
//!    `tear_amount` (radians) is split between the hands as Δθ₁ = Δθ(1 − steer),
//!    Δθ₂ = Δθ(1 + steer); the thumbs sit [`THUMB_AHEAD_M`] ahead of the tip and as far either
//!    side (the hands re-grip as the tear runs), so a straight tear runs towards the front edge
//!    and steer ±1 turns it 45° towards a side; C = L/√2 makes a straight tear reach the front
//!    edge at `tear_amount` = 1, and at 1 a tear that has not reached an edge runs on along its
//!    heading to the border: **at 1 the sheet is in two pieces whatever the steer**.
//! 3. **A tear never closes** (M:116): the tip moves only when `tear_amount` rises past its
//!    highest value since the tear started (before it starts, the highest value follows the
//!    amount down, so a reset sheet tears again when the amount rises). The rig slews
//!    `tear_amount` at the rotation clamp (0.05 rad per 5 ms frame) and the hands follow it
//!    through a 40 ms low-pass ([`TEAR_SMOOTHING_S`]: a MIDI ramp's 1/127 steps become a
//!    steady rotation): the faster the ramp, the faster the tear, up to 10 rad/s.
//! 4. **The mesh follows** (tearing-plan §3.2): when the macro tip is [`MESH_STEP_FRAC`] of
//!    an edge ahead of the mesh's tip vertex, or has reached the border, a mesh step is
//!    *announced* ([`crate::Sim::refinement_pending`]) and made at the start of the next frame:
//!    [`crate::sheet::tear_step::advance_tear`] cuts S_P along the segment and unzips it into
//!    two lips, then the sim adopts the mesh (sim/remesh.rs). Batching the cut this way keeps
//!    the adoptions (~0.8 ms each) to about one per edge of tear.
//! 5. **Sound** (M:120, M:154, T:2042): the macro tip's speed ‖t‖/dt and its place on the
//!    surface fill [`crate::sound_input::TearState`]; the render path's tear noise reads them.
//!    Beyond the seeds (whose synthetic tear lacks the "specific tone" of a real one, T:2046,
//!    M §5): the flaps at the tip — the largest free vibration region touching the tip, else the
//!    largest — give the tear its resonator (l_r, l_c, disk), which colours the noise; and a tip
//!    that moves after standing still for [`TEAR_ONSET_STILL_FRAMES`] marks a tear onset.
//!
//! Decisions, one line each (not in the seeds):
//! - The macro tip moves continuously and drives the sound; the mesh's tip lags it by less than
//!   an edge, so the sound does not come in bursts of mesh steps.
//! - The tip's logic lives in the pattern, so an undone frame (sim.rs) needs no roll-back: the
//!   tear is a function of the gesture history, not of the sheet's positions.
//! - One tear front per sheet (Tearing I; the seeds' limitation too, M:171); once the sheet is
//!   in two pieces the tear gestures do nothing until a reset.
//! - A mesh step that crosses no edge yet waits for the tip to move on; one the cut refuses (a
//!   sliver it would make) is counted and tried again likewise; at the border the step aims a
//!   quarter edge beyond it.

use serde::{Deserialize, Serialize};

use crate::math::{V2, V3};
use crate::sheet::physical::PhysMesh;
use crate::tearing::tip;

use super::tear_hands::HAND_OFFSET_M;

/// Distance of the thumbs ahead of the tip and to either side of its axis, metres (the
/// seeds' hands hold the paper a few centimetres from the tear, Fig. 3.9; impl. choice).
pub const THUMB_AHEAD_M: f64 = 0.03;
/// Largest move of the start away from `tear_pos`, metres (the seeds' random start between
/// the index fingers, M:114; impl. choice).
pub const START_JITTER_M: f64 = 0.005;
/// A start keeps this fraction of the width from a side edge.
pub const START_MARGIN_FRAC: f64 = 0.05;
/// The mesh's tip follows the macro tip once it is this fraction of the mesh spacing behind.
pub const MESH_STEP_FRAC: f64 = 0.5;
/// `tear_amount` at which the tear is complete (reaches the border whatever its path).
pub const FULL_TEAR_RAD: f64 = 1.0 - 1e-9;
/// Time constant of the hands' rotation following `tear_amount`, seconds: a MIDI CC ramp is a
/// staircase of 1/127 steps, which the rig's slew alone would play as one-frame bursts of one
/// speed whatever the ramp's rate.
pub const TEAR_SMOOTHING_S: f64 = 0.04;
/// The rotation snaps to `tear_amount` within this, radians (so a held amount stops the tip).
pub const TEAR_SNAP_RAD: f64 = 1e-3;

/// Each pulling hand's force at `pull_sep` = 1, newtons (impl. choice: a firm two-finger pull).
pub const PULL_FORCE_N: f64 = 12.0;
/// Fracture energy E_f of Griffith's criterion (T:1438–1442) at the mean fibre resistance,
/// J/m; the fibres' resistance R ∈ \[0, 1\] scales it by 0.75 + 0.5·R (impl. choice: a pull
/// starts a tear on a whole edge from `pull_sep` ≈ 0.3–0.4, below the hands' grip).
pub const PULL_FRACTURE_N: f64 = 2.0;
/// V of the step V·E_r (T:1539–1541): the tip's speed per unit of released energy, m/s per
/// J/m (impl. choice: a full pull tears an A4 sheet in about a second).
pub const PULL_SPEED_M_PER_N_S: f64 = 0.015;
/// Distance of the nearer pulling hand from the tear's start, metres; `pull_asym` puts the
/// other one 1–3 times as far (tearing-plan §3.1).
pub const PULL_HAND_DIST_M: f64 = 0.04;
/// The pulling points (Roman's A and B) lie this far outside the back edge, metres: level with
/// a tip on the edge they would release nothing (θ = π, T:1446).
pub const PULL_FOCUS_OUT_M: f64 = 0.01;
/// A tip that moves after standing still for this many frames (50 ms) starts a tear onset: the
/// first fibres break at once, a louder burst than the running tear (impl. choice: a MIDI ramp's
/// steps, smoothed, never pause this long; a player's new push does).
pub const TEAR_ONSET_STILL_FRAMES: u64 = 10;
/// Largest move of the tip in one frame of a pull, metres (a frame's step of the seeds' V·E_r
/// stays below the mesh's edge; the excess is not carried: the pull is a rate).
pub const PULL_MAX_STEP_M: f64 = 0.005;

/// The tear's state: where it started, its macro tip, the mesh's tip vertex (saved with the
/// sheet).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct TearProgress {
    /// The tear has started.
    pub started: bool,
    /// Highest `tear_amount` since the tear started (the ratchet), radians.
    pub theta_max_rad: f64,
    /// Where the tear started on the border, pattern metres.
    pub start_m: [f64; 2],
    /// The macro tip, pattern metres.
    pub tip_m: [f64; 2],
    /// Direction of the last tip step (unit, pattern).
    pub heading: [f64; 2],
    /// The mesh's tip: an S_P vertex (`None` until the first mesh step).
    pub mesh_tip: Option<u32>,
    /// Pattern position of the mesh's tip (the start until the first mesh step).
    pub mesh_tip_m: [f64; 2],
    /// The macro tip has reached the border.
    pub reached_edge: bool,
    /// The sheet is in two pieces.
    pub separated: bool,
    /// A mesh step is announced for the start of the next frame.
    pub pending: bool,
    /// Length of the macro tip's path, pattern metres (never decreases).
    pub path_length_m: f64,
    /// Mesh steps made.
    pub mesh_steps: u32,
    /// Mesh steps the cut refused.
    pub refused_steps: u32,
    /// The hands' rotation, radians: `tear_amount` low-passed ([`TEAR_SMOOTHING_S`]).
    #[serde(default)]
    pub drive_rad: f64,
    /// The tearing hands (sim/tear_hands.rs).
    #[serde(default)]
    pub hands: super::tear_hands::TearHands,
    /// Macro path length at the last mesh step tried (a step that could not be made is tried
    /// again once the tip has moved on).
    pub tried_at_m: f64,
    /// The pulling hands hold the back edge (`pull_sep` > its floor).
    #[serde(default)]
    pub pulling: bool,
    /// Roman's pulling points A (left) and B (right), pattern metres.
    #[serde(default)]
    pub foci_m: [[f64; 2]; 2],
    /// The part of `pull_sep` below this pulls nothing: after a reset, a pull still held
    /// tears the whole sheet again only once it rises past its value then (as `tear_amount`
    /// does); before a pull starts a tear the floor follows `pull_sep` down.
    #[serde(default)]
    pub pull_floor: f64,
    /// Energy release rate E_r of the pull at the tip in the last frame, J/m (0: no pull).
    #[serde(default)]
    pub release_n: f64,
    /// The last frame in which the macro tip moved (`None`: it never has): a tip that moves
    /// after [`TEAR_ONSET_STILL_FRAMES`] still is a tear onset.
    #[serde(default)]
    pub last_moved_frame: Option<u64>,
}

/// The pull gestures the tear reads each frame (thesis §3.3).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PullInput {
    /// `pull_sep`, 0–1: the hands' force, × [`PULL_FORCE_N`].
    pub sep: f64,
    /// `pull_asym`, −1…1: the right (> 0) or left hand farther from the tear.
    pub asym: f64,
    /// `tear_pos`, 0 … 1 (where a pull starts the tear).
    pub pos: f64,
}

/// The gesture values the tear reads each frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TearInput {
    /// `tear_amount`, radians (0–1).
    pub amount_rad: f64,
    /// `tear_steer`, −1…1.
    pub steer: f64,
    /// `tear_pos`, 0 (left end of the back edge) … 1.
    pub pos: f64,
}

impl TearProgress {
    fn v(a: [f64; 2]) -> V2 {
        V2::new(a[0], a[1])
    }

    /// The macro tip (pattern).
    pub fn tip(&self) -> V2 {
        Self::v(self.tip_m)
    }

    /// Moves the hands' rotation towards `amount_rad` over a frame of `dt` seconds (a one-pole
    /// low-pass, snapped within [`TEAR_SNAP_RAD`]) and returns it.
    pub fn drive(&mut self, amount_rad: f64, dt: f64) -> f64 {
        if !amount_rad.is_finite() {
            return self.drive_rad;
        }
        let a = 1.0 - (-dt / TEAR_SMOOTHING_S).exp();
        self.drive_rad += (amount_rad - self.drive_rad) * a;
        if (amount_rad - self.drive_rad).abs() < TEAR_SNAP_RAD || !self.drive_rad.is_finite() {
            self.drive_rad = amount_rad;
        }
        self.drive_rad
    }

    /// Advances the macro tip for this frame's gesture values on a `w` × `l` sheet; `jitter`
    /// in \[−1, 1\] places the start (drawn from the tear's stream). Returns the tip's move,
    /// pattern metres (0 if it does not move).
    pub fn advance(&mut self, input: TearInput, w: f64, l: f64, jitter: f64) -> f64 {
        let TearInput {
            amount_rad: theta,
            steer,
            pos,
        } = input;
        if self.separated || !theta.is_finite() {
            return 0.0;
        }
        if !self.started {
            // Before the tear starts the ratchet follows the amount down.
            self.theta_max_rad = self.theta_max_rad.min(theta.max(0.0));
        }
        if theta <= self.theta_max_rad {
            return 0.0;
        }
        let dtheta = theta - self.theta_max_rad;
        self.theta_max_rad = theta;
        if !self.started {
            self.start_at(start_point(pos, w, l, jitter));
        }
        let s = if steer.is_finite() {
            steer.clamp(-1.0, 1.0)
        } else {
            0.0
        };
        let tip0 = self.tip();
        let thumbs = [
            tip0 + V2::new(-THUMB_AHEAD_M, -THUMB_AHEAD_M),
            tip0 + V2::new(THUMB_AHEAD_M, -THUMB_AHEAD_M),
        ];
        let c = l / std::f64::consts::SQRT_2;
        let t = tip::step(tip0, thumbs, [dtheta * (1.0 - s), dtheta * (1.0 + s)], c);
        let tn = t.norm();
        if tn > 0.0 {
            self.heading = [t.x / tn, t.y / tn];
        }
        let heading = Self::v(self.heading);
        let mut tip1 = tip0 + t;
        // The border stops the tip; at the full amount it runs on to the border.
        let exit = border_exit(tip0, heading, w, l);
        if (tip1 - tip0).norm() >= exit || theta >= FULL_TEAR_RAD {
            tip1 = tip0 + heading * exit;
            if !self.reached_edge {
                // The mesh follows to the border now, whatever a step found short before.
                self.tried_at_m = -1.0;
            }
            self.reached_edge = true;
        }
        let moved = (tip1 - tip0).norm();
        self.tip_m = [tip1.x, tip1.y];
        self.path_length_m += moved;
        moved
    }

    fn start_at(&mut self, p: V2) {
        self.started = true;
        self.start_m = [p.x, p.y];
        self.tip_m = self.start_m;
        self.mesh_tip_m = self.start_m;
        self.heading = [0.0, -1.0];
    }

    /// Moves the tip for this frame's pull (thesis §3.3, module doc "Pull") on a `w` × `l`
    /// sheet over `dt` seconds; `jitter` places the start as in [`Self::advance`],
    /// `fracture(p)` is E_f at pattern point `p`. Returns the tip's move, pattern metres.
    pub fn advance_pull(
        &mut self,
        input: PullInput,
        w: f64,
        l: f64,
        dt: f64,
        jitter: f64,
        fracture: impl Fn(V2) -> f64,
    ) -> f64 {
        let sep = if input.sep.is_finite() {
            input.sep.clamp(0.0, 1.0)
        } else {
            0.0
        };
        self.release_n = 0.0;
        if !self.started {
            self.pull_floor = self.pull_floor.min(sep);
        }
        let force_n = (sep - self.pull_floor).max(0.0) * PULL_FORCE_N;
        if force_n <= 0.0 || self.separated {
            self.pulling = false;
            return 0.0;
        }
        let at = if self.started {
            Self::v(self.start_m)
        } else {
            start_point(input.pos, w, l, jitter)
        };
        if !self.pulling {
            let asym = if input.asym.is_finite() {
                input.asym.clamp(-1.0, 1.0)
            } else {
                0.0
            };
            let far = PULL_HAND_DIST_M * (1.0 + 2.0 * asym.abs());
            let (da, db) = if asym > 0.0 {
                (PULL_HAND_DIST_M, far)
            } else {
                (far, PULL_HAND_DIST_M)
            };
            let y = 0.5 * l + PULL_FOCUS_OUT_M;
            self.foci_m = [[at.x - da, y], [at.x + db, y]];
            self.pulling = true;
        }
        let foci = [Self::v(self.foci_m[0]), Self::v(self.foci_m[1])];
        let tip0 = if self.started { self.tip() } else { at };
        let (release_n, d0) = roman(tip0, foci, force_n);
        self.release_n = release_n.max(0.0);
        if release_n < fracture(tip0) || d0.norm() == 0.0 {
            return 0.0;
        }
        if !self.started {
            self.start_at(at);
        }
        // V·E_r along the bisector, a midpoint step (the path is the hyperbola with foci A and
        // B, T:1448–1450; Euler steps drift off it where it curves).
        let len = (PULL_SPEED_M_PER_N_S * release_n * dt).min(PULL_MAX_STEP_M);
        let (_, d_mid) = roman(tip0 + d0 * (0.5 * len), foci, force_n);
        let d = if d_mid.norm() > 0.0 { d_mid } else { d0 };
        self.heading = [d.x, d.y];
        let exit = border_exit(tip0, d, w, l);
        let step = if len >= exit {
            if !self.reached_edge {
                self.tried_at_m = -1.0;
            }
            self.reached_edge = true;
            exit
        } else {
            len
        };
        let tip1 = tip0 + d * step;
        self.tip_m = [tip1.x, tip1.y];
        self.path_length_m += step;
        step
    }

    /// Whether the mesh should follow the macro tip now (`spacing_m`: the mesh's edge length).
    pub fn mesh_step_due(&self, spacing_m: f64) -> bool {
        if !self.started || self.separated || self.pending {
            return false;
        }
        let behind = (self.tip() - Self::v(self.mesh_tip_m)).norm();
        let moved_since_last_try = self.path_length_m > self.tried_at_m;
        moved_since_last_try && (self.reached_edge || behind >= MESH_STEP_FRAC * spacing_m)
    }

    /// The pattern point a mesh step aims at: the macro tip, or beyond the border once it is
    /// there.
    pub fn mesh_target(&self, spacing_m: f64) -> V2 {
        if self.reached_edge {
            self.tip() + Self::v(self.heading) * (0.25 * spacing_m)
        } else {
            self.tip()
        }
    }

    /// Checks a restored state against a mesh of `num_vertices` vertices.
    pub fn validate(&self, num_vertices: usize) -> Result<(), String> {
        let finite = [
            self.theta_max_rad,
            self.path_length_m,
            self.tried_at_m,
            self.drive_rad,
            self.start_m[0],
            self.start_m[1],
            self.tip_m[0],
            self.tip_m[1],
            self.heading[0],
            self.heading[1],
            self.mesh_tip_m[0],
            self.mesh_tip_m[1],
            self.foci_m[0][0],
            self.foci_m[0][1],
            self.foci_m[1][0],
            self.foci_m[1][1],
            self.pull_floor,
            self.release_n,
        ]
        .iter()
        .all(|x| x.is_finite());
        if !finite {
            return Err("the tear's state is not finite".into());
        }
        if self.mesh_tip.is_some_and(|v| v as usize >= num_vertices) {
            return Err("the tear's tip vertex is not in the mesh".into());
        }
        self.hands.validate(num_vertices)
    }
}

/// Stream constant of the tear's random draws (its start), apart from the sheet's stream.
const TEAR_STREAM: u64 = 0x7465_6172;

impl super::Sim {
    /// The tear's state.
    pub fn tear(&self) -> &TearProgress {
        &self.tear
    }

    /// The kinematic constraints at fraction `s` of the frame: the gesture hands', then the
    /// tearing hands' on the vertices the gesture hands leave (sim/tear_hands.rs).
    pub(super) fn fill_held(&mut self, s: f64) {
        self.rig
            .fill_kinematics(s, &mut self.fixed, &mut self.kin_target);
        self.tear
            .hands
            .fill(s, &mut self.fixed, &mut self.kin_target);
    }

    /// The tearing hands before the substeps: they let go when `tear_amount` is back at 0
    /// and lift as the tear grows. Returns whether they move this frame.
    pub(super) fn tear_hands_frame(&mut self) -> bool {
        let amount = self.rig.state.smoothed[crate::control::GestureParam::TearAmount.index()];
        // Back at 0 the hands let go; a gesture hand holding the sheet takes it over (two sets
        // of hard grips would fight over it).
        if self.tear.hands.active
            && ((amount <= 0.0 && !self.tear.pulling) || self.rig.num_active_hands() > 0)
        {
            self.tear.hands.release();
            return true;
        }
        self.tear.hands.advance(self.tear.path_length_m)
    }

    /// After the strain limit moved held vertices: the tearing hands slip with them.
    pub(super) fn tear_hands_regrip(&mut self) {
        let rig = &self.rig;
        self.tear
            .hands
            .regrip(&self.sheet.sp.pos, &self.strain_limit.moved, |v| {
                rig.hand_of(v).is_some()
            });
    }

    /// This frame's tear (after the rig moved the gestures): advances the macro tip, announces
    /// a mesh step if due, and writes the tear's sound input (module doc).
    /// Returns whether the tip moved.
    pub(super) fn tear_frame(
        &mut self,
        dt: f64,
        sound: &mut crate::sound_input::SoundFrame,
    ) -> bool {
        use crate::control::GestureParam as G;
        use rand::{RngExt, SeedableRng};
        let g = |p: G| self.rig.state.smoothed[p.index()];
        let amount_rad = self.tear.drive(g(G::TearAmount), dt);
        let input = TearInput {
            amount_rad,
            steer: g(G::TearSteer),
            pos: g(G::TearPosition),
        };
        let jitter = if self.tear.started {
            0.0
        } else {
            rand_pcg::Pcg32::seed_from_u64(self.cfg.seed ^ TEAR_STREAM).random_range(-1.0..=1.0)
        };
        let (w, l) = (self.sheet.width_m, self.sheet.length_m);
        let (was_started, was_pulling) = (self.tear.started, self.tear.pulling);
        let mut moved_m = self.tear.advance(input, w, l, jitter);
        let pull = PullInput {
            sep: g(G::PullSeparation),
            asym: g(G::PullAsymmetry),
            pos: g(G::TearPosition),
        };
        let fibres = &self.fibres;
        moved_m += self.tear.advance_pull(pull, w, l, dt, jitter, |p| {
            PULL_FRACTURE_N * (0.75 + 0.5 * fibres.resistance(crate::tearing::fibres::px_of(p)))
        });
        let free = self.rig.num_active_hands() == 0;
        if free && self.tear.pulling && !was_pulling && !self.tear.hands.active {
            // The pulling hands take the back edge either side of where the tear starts.
            let at = if self.tear.started {
                TearProgress::v(self.tear.start_m)
            } else {
                start_point(pull.pos, w, l, jitter)
            };
            let [a, b] = self.tear.foci_m;
            let rig = &self.rig;
            self.tear.hands.grab(
                at,
                [a[0] - at.x, b[0] - at.x],
                &self.sheet.sp.pattern,
                &self.sheet.sp.pos,
                |v| rig.hand_of(v).is_some(),
            );
        } else if free && self.tear.started && !was_started && !self.tear.hands.active {
            let rig = &self.rig;
            self.tear.hands.grab(
                TearProgress::v(self.tear.start_m),
                [-HAND_OFFSET_M, HAND_OFFSET_M],
                &self.sheet.sp.pattern,
                &self.sheet.sp.pos,
                |v| rig.hand_of(v).is_some(),
            );
        }
        let spacing_m = self.cfg.mesh.spacing_m(self.cfg.size);
        if self.tear.mesh_step_due(spacing_m) {
            self.tear.pending = true;
        }
        if moved_m > 0.0 {
            let (tip_tri, x) = locate(&self.sheet.sp, self.tear.tip()).unzip();
            let x = x.unwrap_or_else(V3::zeros);
            sound.tear.speed_m_s = (moved_m / dt) as f32;
            sound.tear.tip_m = [x.x as f32, x.y as f32, x.z as f32];
            sound.tear.onset = self
                .tear
                .last_moved_frame
                .is_none_or(|f| self.frame.saturating_sub(f) >= TEAR_ONSET_STILL_FRAMES);
            sound.tear.resonator = self
                .analysis
                .flap_resonator(
                    &crate::sound_analysis::AnalysisInput {
                        sp: &self.sheet.sp,
                        contacts: &self.contacts,
                        held: &self.fixed,
                        time_s: self.time_s(),
                        vel_start: &[],
                        dt_s: 0.0,
                        planes: &[],
                        pressed_m: 0.0,
                        layer_slip: &[],
                    },
                    self.tear.mesh_tip,
                    tip_tri,
                )
                .unwrap_or_default();
            self.tear.last_moved_frame = Some(self.frame);
        }
        sound.tear.length_m = self.tear.path_length_m as f32;
        moved_m > 0.0
    }

    /// Makes the mesh step announced last frame (module doc, step 4): cut and unzip S_P
    /// towards the macro tip and adopt the torn mesh.
    pub(super) fn apply_pending_tear(&mut self) {
        use crate::sheet::tear_step::{TearError, TearFrom, advance_tear};
        if !self.tear.pending {
            return;
        }
        self.tear.pending = false;
        self.tear.tried_at_m = self.tear.path_length_m;
        let spacing_m = self.cfg.mesh.spacing_m(self.cfg.size);
        let from = match self.tear.mesh_tip {
            Some(v) => TearFrom::Tip(v),
            None => TearFrom::Border(TearProgress::v(self.tear.start_m)),
        };
        let to = self.tear.mesh_target(spacing_m);
        let mut step = match advance_tear(&self.sheet.sp, from, to) {
            Ok(st) => st,
            // Too short to cross an edge yet (or, from the border, to make an edge of its
            // own): the tip goes on and the step is tried again a quarter edge further.
            Err(e)
                if !self.tear.reached_edge
                    && (e == TearError::TooShort || self.tear.mesh_tip.is_none()) =>
            {
                self.tear.tried_at_m += 0.25 * spacing_m;
                return;
            }
            Err(_) => {
                self.tear.refused_steps += 1;
                return;
            }
        };
        // A singular vertex the tear ran through is on a lip now: a tip of the border, no
        // longer an interior singular point (T:1489–1498 counts such points as boundary ones).
        let on_boundary = &step.mesh.topo.vertex_on_boundary;
        step.mesh.singular.retain(|&v| !on_boundary[v as usize]);
        self.geometry.start_events_early();
        self.wake();
        if self.adopt_mesh(step.mesh, &step.tri_parent, true).is_err() {
            self.tear.refused_steps += 1;
            return;
        }
        self.sheet.sg.pull_positions(&self.sheet.sp);
        self.tear.mesh_steps += 1;
        self.tear.mesh_tip = Some(step.tip);
        let q = self.sheet.sp.pattern[step.tip as usize];
        self.tear.mesh_tip_m = [q.x, q.y];
        self.tear.separated = self.sheet.sp.topo.pieces().len() > 1;
        if self.tear.reached_edge && !self.tear.separated {
            // The border not reached by this step: the next frame goes on from the new tip.
            self.tear.tried_at_m = -1.0;
            self.tear.pending = true;
        }
    }
}

/// Where a tear starts on the back edge of a `w` × `l` sheet: `tear_pos` across the width,
/// moved by up to [`START_JITTER_M`] × `jitter`, at least [`START_MARGIN_FRAC`] of the width
/// from a side.
fn start_point(pos: f64, w: f64, l: f64, jitter: f64) -> V2 {
    let margin = START_MARGIN_FRAC * w;
    let pos = if pos.is_finite() {
        pos.clamp(0.0, 1.0)
    } else {
        0.5
    };
    let jitter = if jitter.is_finite() {
        jitter.clamp(-1.0, 1.0)
    } else {
        0.0
    };
    let x =
        (-0.5 * w + pos * w + START_JITTER_M * jitter).clamp(-0.5 * w + margin, 0.5 * w - margin);
    V2::new(x, 0.5 * l)
}

/// Roman's two pulling points (eq. 3.4, T:1446–1448): the energy release rate
/// E_r = 2F cos(θ/2) at tip `s` pulled by a force `force_n` at each of `foci` (θ the angle
/// between AS and BS), and the direction the crack runs, the bisector of AS and BS (unit;
/// zero where they are opposite).
pub fn roman(s: V2, foci: [V2; 2], force_n: f64) -> (f64, V2) {
    let a = s - foci[0];
    let b = s - foci[1];
    let (na, nb) = (a.norm(), b.norm());
    if na == 0.0 || nb == 0.0 {
        return (0.0, V2::zeros());
    }
    let (ua, ub) = (a / na, b / nb);
    let cos_theta = ua.dot(&ub).clamp(-1.0, 1.0);
    // cos(θ/2) = √((1 + cos θ)/2), θ ∈ [0, π] between two vectors.
    let release_n = 2.0 * force_n * (0.5 * (1.0 + cos_theta)).sqrt();
    let bis = ua + ub;
    let nb2 = bis.norm();
    let d = if nb2 > 1e-9 { bis / nb2 } else { V2::zeros() };
    (release_n, d)
}

/// Distance from `p` along unit `d` to the border of the `w` × `l` rectangle centred at the
/// origin (0 if `d` is zero or points out from a point on the border).
fn border_exit(p: V2, d: V2, w: f64, l: f64) -> f64 {
    let mut t = f64::INFINITY;
    for (pc, dc, half) in [(p.x, d.x, 0.5 * w), (p.y, d.y, 0.5 * l)] {
        if dc > 0.0 {
            t = t.min((half - pc) / dc);
        } else if dc < 0.0 {
            t = t.min((-half - pc) / dc);
        }
    }
    if t.is_finite() { t.max(0.0) } else { 0.0 }
}

/// The point of the surface over pattern point `p`: barycentric in the triangle that contains
/// it (or comes closest to containing it).
pub fn surface_point(sp: &PhysMesh, p: V2) -> V3 {
    locate(sp, p).map_or(V3::zeros(), |(_, x)| x)
}

/// The triangle that contains pattern point `p` (or comes closest to containing it) and the
/// surface point over `p` in it; `None` on an empty mesh.
pub fn locate(sp: &PhysMesh, p: V2) -> Option<(u32, V3)> {
    let mut best: Option<(f64, u32, V3)> = None;
    for (t, tri) in sp.triangles.iter().enumerate() {
        let [a, b, c] = tri.map(|i| sp.pattern[i as usize]);
        let [l0, l1, l2] = crate::math::barycentric2(a, b, c, p);
        let inside = l0.min(l1).min(l2);
        if inside.is_finite() && best.is_none_or(|(m, _, _)| inside > m) {
            let [x0, x1, x2] = tri.map(|i| sp.pos[i as usize]);
            best = Some((inside, t as u32, x0 * l0 + x1 * l1 + x2 * l2));
        }
    }
    best.map(|(_, t, x)| (t, x))
}

#[cfg(test)]
mod tests {
    use super::*;

    const W: f64 = 0.21;
    const L: f64 = 0.297;

    fn input(amount_rad: f64, steer: f64) -> TearInput {
        TearInput {
            amount_rad,
            steer,
            pos: 0.5,
        }
    }

    /// Ramps the amount 0 → `to` in `n` frames at `steer`.
    fn ramp(to: f64, steer: f64, n: usize) -> TearProgress {
        let mut t = TearProgress::default();
        for k in 1..=n {
            t.advance(input(to * k as f64 / n as f64, steer), W, L, 0.0);
        }
        t
    }

    #[test]
    fn a_straight_tear_runs_to_the_front_edge_at_full_amount() {
        let half = ramp(0.5, 0.0, 50);
        assert!((half.tip_m[0]).abs() < 1e-12);
        assert!((half.tip_m[1] - 0.0).abs() < 1e-9, "{:?}", half.tip_m);
        assert!(!half.reached_edge);
        let full = ramp(1.0, 0.0, 100);
        assert!(full.reached_edge);
        assert!((full.tip_m[1] + 0.5 * L).abs() < 1e-9);
        assert!((full.path_length_m - L).abs() < 1e-9);
    }

    #[test]
    fn at_full_amount_every_steer_reaches_an_edge_and_steer_turns_the_tear() {
        let mut last_x = f64::NEG_INFINITY;
        for s in [-1.0, -0.5, 0.0, 0.5, 1.0] {
            let t = ramp(1.0, s, 40);
            assert!(t.reached_edge, "steer {s}");
            let [x, y] = t.tip_m;
            let on_border = (x.abs() - 0.5 * W).abs() < 1e-9 || (y.abs() - 0.5 * L).abs() < 1e-9;
            assert!(on_border, "steer {s}: tip {x}, {y}");
            // The end's lateral offset has the steer's sign and grows with it.
            assert!(x >= last_x, "steer {s}: {x} after {last_x}");
            assert_eq!(x.abs() < 1e-12, s == 0.0);
            assert_eq!(x > 0.0, s > 0.0);
            last_x = x;
        }
    }

    #[test]
    fn a_tear_never_closes_and_a_held_amount_stops_it() {
        let mut t = ramp(0.4, 0.0, 10);
        let tip = t.tip_m;
        assert_eq!(t.advance(input(0.4, 0.0), W, L, 0.0), 0.0);
        assert_eq!(t.advance(input(0.1, 0.0), W, L, 0.0), 0.0);
        assert_eq!(t.advance(input(0.35, 0.0), W, L, 0.0), 0.0);
        assert_eq!(t.tip_m, tip);
        assert!(t.advance(input(0.45, 0.0), W, L, 0.0) > 0.0);
        assert_eq!(t.advance(input(f64::NAN, 0.0), W, L, 0.0), 0.0);
    }

    #[test]
    fn twice_the_ramp_rate_tears_twice_as_fast() {
        let mut slow = TearProgress::default();
        let mut fast = TearProgress::default();
        slow.advance(input(0.1, 0.3), W, L, 0.0);
        fast.advance(input(0.1, 0.3), W, L, 0.0);
        let a = slow.advance(input(0.12, 0.3), W, L, 0.0);
        let b = fast.advance(input(0.14, 0.3), W, L, 0.0);
        assert!((b / a - 2.0).abs() < 1e-9, "{a} {b}");
    }

    #[test]
    fn before_the_tear_starts_the_ratchet_follows_the_amount_down() {
        let mut t = TearProgress {
            theta_max_rad: 1.0,
            ..TearProgress::default()
        };
        assert_eq!(t.advance(input(0.0, 0.0), W, L, 0.0), 0.0);
        assert!(t.advance(input(0.2, 0.0), W, L, 0.0) > 0.0);
        assert!(t.started);
    }

    #[test]
    fn the_start_is_on_the_back_edge_at_tear_pos_within_the_jitter() {
        for (pos, jitter) in [(0.5, 0.0), (0.25, 1.0), (0.0, -1.0), (1.0, 1.0)] {
            let mut t = TearProgress::default();
            t.advance(
                TearInput {
                    amount_rad: 0.01,
                    steer: 0.0,
                    pos,
                },
                W,
                L,
                jitter,
            );
            let [x, y] = t.start_m;
            assert_eq!(y, 0.5 * L);
            let want = (-0.5 * W + pos * W + START_JITTER_M * jitter).clamp(
                -0.5 * W + START_MARGIN_FRAC * W,
                0.5 * W - START_MARGIN_FRAC * W,
            );
            assert!((x - want).abs() < 1e-15);
        }
    }
}
