//! # The gesture rig: gesture values → hand targets
//!
//! The seeds drive the sheet by handles, hard constraints with a controlled tangent plane
//! (thesis `000_cb4d91e46ec5927f.txt` T 714/730, TOG 2015 `001_44bc28f7c5e9f81f.txt`
//! P 388–394, 450; digest-tearing §4.1), moved by a user. A plugin is driven by notes and
//! automation instead, so the rig maps *absolute* gesture values (digest-tearing §4.3 design
//! rule (a)) to handle target poses; notes grab and release groups of handles. A name in quotes
//! below is the section of `docs/decisions.md` with the figures behind a choice.
//!
//! ## Slots (grab/release)
//!
//! | slot | handles (pattern position) |
//! |---|---|
//! | back / front | 2 on the back (+y) / front (−y) edge at 25 % and 75 % of the width (a pinch) |
//! | left / right | 2 on the left (−x) / right (+x) edge at 25 % and 75 % of the length |
//! | corners | the 4 corners |
//!
//! Each handle holds its vertex and 2–4 tangent-plane neighbours ([`crate::handles`]); the two
//! handles of an edge slot are one **hand** (one rigid grip, like thumb and finger of a pinch),
//! each corner a hand of its own. A grab takes hold where the sheet is; the hand then travels to
//! its target at `0.05 + 1.95·grip` m/s (grip = note velocity 0–1), at most
//! [`TRAVEL_CLAMP_FRAC`] × L_paper per frame. Release frees the vertices with their velocity. A
//! vertex two hands contest stays with the earlier grab, and no edge joins two hands' grips.
//!
//! ## Target pose of a hand
//!
//! From the home pose (the centroid of the hand's handle vertices at table height, flat frame):
//! - **slide** s ∈ \[0, 1\]: inwards along the normal of the hand's edge by s·span/4 (span: the
//!   sheet's extent across that edge; corners by (W/4, L/4)·s). Back + front: the edges approach
//!   (S1, C1); front alone pushes the sheet along the table (S6) to the wall at +y (S3). The
//!   patches tilt up by 0.7 × the angle a free arc leaves its ends at ([`arc_half_angle`]): a
//!   flat sheet pressed on the table is an equilibrium the implicit solver would keep.
//! - **lift** ℓ ∈ \[0, 1\]: the front group (front hand, front corners) rises by ℓ·L/2; the left
//!   and right hands pivot about their back finger (angle asin ℓ), since raising one finger of a
//!   rigid pinch and not the other would stretch the paper between them.
//! - **twist** τ ∈ \[−1, 1\]: the front group turns by τ·π about the sheet's long axis, +τ
//!   raising the right (+x) side (C2, S5, C6); the left and right hands, spanning both halves,
//!   do not twist.
//! - **shake** d, f: every active handle moves vertically by `d·A·sin(φ)`, φ advancing by
//!   2π·f·dt a frame (a continuous phase, so rate changes do not jump). A =
//!   [`SHAKE_AMPLITUDE_M`] ≈ 5.9 cm whatever the sheet: the hand moves, not the paper, and depth
//!   1 is a vigorous shake (at 3 Hz the free part then flips on every swing: a shake whose peak
//!   acceleration stays under g only bends the sheet's sag, docs/decisions.md, "Shake depth").
//! - **crumple** c ∈ \[0, 1\]: 8 boundary points (corners, edge midpoints) become point handles
//!   moving to `centre + (1 − c·k)(p − centre)`, k = [`CRUMPLE_CAP`], with a seeded jitter, a
//!   lift of ≈ c·0.1·L and a tilt of c·[`CRUMPLE_TILT_RAD`]; they take precedence over slot
//!   handles (a slot hand with a handle vertex on or next to theirs stands aside: two rigid
//!   grips one edge apart tear the paper between them as they move) and go when c is back
//!   at 0. Point handles, because rigid patches of neighbouring
//!   hands would collide as the ring shrinks ("Hands, grip and obstacles"); but a hand alone
//!   on a piece torn off (or sharing it with one or two others) holds its 1-ring as a pinch,
//!   else the piece swings on it as a pendulum nothing stops (docs/decisions.md, "Shake
//!   depth"), or flaps about the lines between three points.
//!
//! **Pieces held on one line.** A piece whose held vertices are fewer than three or on one
//! line hangs as a pendulum or a hinge; once the hands are still, a hand holding a handle
//! vertex on it takes back its ring there, where the paper is relaxed, and a piece held only by
//! ring neighbours is let go ([`GestureRig::hold_hinged_pieces`]; docs/decisions.md, "A piece
//! held on one line is held again"). At a tear step every hand takes the torn mesh's rings.
//!
//! Gesture values follow slew-rate limits derived from the travel clamp (a jump becomes a sweep:
//! a twist jump turns the hands along arcs instead of through each other), then each pose is
//! clamped again. Tear and pull move the sheet through the tear (sim/tear.rs) and its hands
//! (sim/tear_hands.rs), not through this rig.
//!
//! ## Grip and obstacles
//!
//! - **Grip force.** A finger holds at most `1 + 4·grip` N ([`grip_force_n`]); pulled harder, a
//!   hand gives way along the pull by [`HAND_COMPLIANCE_M_N`] per newton of excess and stays
//!   there while its target stays ([`crate::handles::HandState::advance`]). Contradictory hard
//!   constraints would otherwise crush or tear the sheet; gravity and bending pull with
//!   millinewtons, so only such gestures are affected ("Hands, grip and obstacles").
//! - **Paper does not stretch.** A hand also gives way where its vertices' triangles are
//!   strained beyond [`STRAIN_GIVE`] (4 %) while it moves or slides, beyond
//!   [`STRAIN_GIVE_STILL`] (6 %) while it is still (static friction holds more than kinetic:
//!   a sheet sagging in still hands stops instead of creeping through them), by the excess
//!   times the edge length; a held neighbour strained beyond [`STRAIN_RELEASE`] slides out of
//!   the grip. What a frame still leaves strained beyond 8 % the strain limit projects
//!   ([`crate::physics::strain_limit`]); where it moves held vertices, their hand slips with
//!   its handle vertices and lets go of its neighbours ([`GestureRig::regrip`]) ("A held sheet
//!   comes to rest").
//! - **Settling.** A give against the last one's direction is halved (it overshot the balance;
//!   the hands would otherwise swing over it frame after frame), one the same way grows back by
//!   [`SLIP_GAIN_GROWTH`]; the direction is the move's once kept out of tables and walls, and a
//!   regrip's slip counts as the last one (a hand pulled into the table, or between the strain
//!   limit and its grip, swings sideways). A give under [`SLIP_MIN_M`], or into a table or a
//!   wall, is none: a hand at its balance holds, so a held sheet comes to rest and sleeps.
//! - **Obstacles.** Targets are moved out of the table, wall and floor; a hand never gives way
//!   into one, a hand holding paper inside one comes out at its travel speed, and a moving one
//!   carries every hand by the largest push any needs, as they hold one sheet (`obstacles`).
//!
//! ## Crumple cap
//!
//! Sheet–sheet contact ([`crate::physics::sheet_contact`]) holds layers within 1.5 mm, but a
//! fold snapping through a coarse mesh moves ~1 cm a frame, faster than a contact skin can
//! catch, so the squeeze must stop before the sheet passes through itself. The seeds, with no
//! self-collision, capped their crumpling (T 1245, T 2014, T 2076; digest-tearing §4.3: 0.6).
//! Here k = 0.6 bounds the squeeze, and each frame of a squeeze the sim also measures the sheet's
//! closest approach to itself ([`crate::self_proximity`]) for [`GestureRig::limit_squeeze`]:
//!
//! ```text
//! closest approach                   the squeeze
//! > SQUEEZE_SLOW_M (2 cm)            at the hands' speed
//! SQUEEZE_STOP_M … SQUEEZE_SLOW_M    slowed linearly, down to SQUEEZE_SLOWEST of it
//! ≤ SQUEEZE_STOP_M (1 mm)            stopped, until the command falls below the limit
//! < SQUEEZE_BACK_OFF_M (0.5 mm)      backing off by one frame's travel per frame, by at most
//!                                    SQUEEZE_MAX_BACK_OFF (0.1) of the value until the
//!                                    sheet has room again (≥ 1 mm), then stopped;
//! 0 (crossing itself)                backing off as far as it takes
//! ```
//!
//! The crumple value slews no faster than the hands follow, so stopping the value stops them. A
//! frame that still passes the sheet through itself is undone (`Sim`'s module doc, "The
//! pass-through guard"). A fixed bound alone let the point hands buckle the sheet into folds
//! that crossed; the stop lies inside the contact skin, so the squeeze goes on until layers
//! touch and the contact holds them ("The crumple cap follows the sheet; the squeeze stops at
//! 1 mm").
//!
//! **Pressing.** While the squeeze is held at its limit the crumple value may go on rising or
//! falling above it; the hands cannot follow, and what they would have travelled is kept
//! (`crumple_pressed`) and handed to the sound analysis frame by frame at no more than the
//! hands' speed ([`GestureRig::take_press_m`]): the crackle of a ball pressed harder or let go
//! (sound_analysis/crackle.rs "Pressing"). It keeps the sheet awake while it lasts.
//!
//! Moving targets out of obstacles and carrying the hands along with a moving one is
//! `obstacles`; the hands' part of a saved sheet is `saved` ([`SavedHandDef`]).

mod obstacles;
mod saved;

pub use saved::SavedHandDef;

use serde::{Deserialize, Serialize};

use crate::collision::{Obstacles, PlaneObstacle};
use crate::control::DEFAULT_FRAME_RATE_HZ;
use crate::control::{GestureParam, GrabSlot};
use crate::handles::{HandDef, HandState, HandleDef, MAX_HAND_VERTICES, Pose};
use crate::math::{Rot, V2, V3};
use crate::sheet::Sheet;

/// Slot hands: back, front, left, right, and the four corners.
pub const NUM_SLOT_HANDS: usize = 8;
/// Crumple hands: 4 corners + 4 edge midpoints.
pub const NUM_CRUMPLE_HANDS: usize = 8;
/// All hands.
pub const NUM_HANDS: usize = NUM_SLOT_HANDS + NUM_CRUMPLE_HANDS;
/// Crumple squeeze cap k: at c = 1 the hands are at (1 − k) of their home distance.
pub const CRUMPLE_CAP: f64 = 0.6;
/// Closest approach of the sheet to itself at which the squeeze stops, metres.
pub const SQUEEZE_STOP_M: f64 = 0.001;
/// Closest approach of the sheet to itself below which the squeeze slows down, metres.
pub const SQUEEZE_SLOW_M: f64 = 0.02;
/// Slowest squeeze near the stop, as a fraction of the hands' speed.
pub const SQUEEZE_SLOWEST: f64 = 0.1;
/// Closest approach below which the crumple hands back off, metres.
pub const SQUEEZE_BACK_OFF_M: f64 = 0.0005;
/// Largest back-off of the squeeze (crumple value) while the sheet stays closer to itself than
/// [`SQUEEZE_BACK_OFF_M`]: layers the hands' backing off does not part were not pressed together
/// by the squeeze (a twist, a lift, contact), and backing off further only unfolds the crumple
/// after the gestures stopped. A sheet crossing itself (closest approach 0) backs off without
/// this bound, until it no longer crosses ("Crumple cap" in the module doc).
pub const SQUEEZE_MAX_BACK_OFF: f64 = 0.1;
/// Reach of the closest-approach query, metres (pairs farther apart are not measured).
pub const SQUEEZE_REACH_M: f64 = SQUEEZE_SLOW_M;
/// Tilt of a crumple hand's frame at c = 1, radians.
pub const CRUMPLE_TILT_RAD: f64 = 0.6;
/// Per-frame hand travel clamp as a fraction of L_paper, at the default frame rate (it is a
/// speed: 4 L_paper/s; at other frame rates the per-frame clamp scales accordingly).
pub const TRAVEL_CLAMP_FRAC: f64 = 0.02;
/// Per-frame rotation clamp of a hand frame at the default frame rate, radians
/// (digest-tearing §4.3 (d)).
pub const ROTATION_CLAMP_RAD: f64 = 0.05;
/// Shake amplitude at depth 1 as a fraction of [`SHAKE_REFERENCE_LENGTH_M`].
pub const SHAKE_AMPLITUDE_FRAC: f64 = 0.2;
/// The length the shake amplitude is a fraction of: an A4's (the same for every sheet size).
/// Written as `depth × 0.2 × A4 length` so that a depth of d/4 now moves an A4 exactly as d moved
/// it when the amplitude was 5 % of the sheet's own length (the seed scenes keep their bits).
pub const SHAKE_REFERENCE_LENGTH_M: f64 = 29.7 * 0.01;
/// Shake amplitude at depth 1, metres ([`SHAKE_AMPLITUDE_FRAC`] × [`SHAKE_REFERENCE_LENGTH_M`]).
pub const SHAKE_AMPLITUDE_M: f64 = SHAKE_AMPLITUDE_FRAC * SHAKE_REFERENCE_LENGTH_M;
/// Fraction of the free-arc edge angle by which sliding hands tilt their held patch.
pub const SLIDE_TILT_GAIN: f64 = 0.7;
/// Largest force a finger holds at grip 0, N.
pub const GRIP_FORCE_MIN_N: f64 = 1.0;
/// Extra holding force of a finger at grip 1, N.
pub const GRIP_FORCE_RANGE_N: f64 = 4.0;
/// How far a hand gives way per newton of excess pull, m/N (a hand stiffness of 100 N/m).
pub const HAND_COMPLIANCE_M_N: f64 = 0.01;
/// Strain (|λ − 1| of a held vertex's triangles) beyond which a hand gives way as if pulled
/// beyond its grip, by the excess times the mesh's edge length per frame: paper does not
/// stretch by more than a few percent, the fingers slide.
pub const STRAIN_GIVE: f64 = 0.04;
/// Strain a still hand's fingers hold before they give way (static friction: more than
/// [`STRAIN_GIVE`], which sliding or moving fingers hold).
pub const STRAIN_GIVE_STILL: f64 = 0.06;
/// Smallest give that moves a hand, metres (below it the hand holds: it is at its balance).
pub const SLIP_MIN_M: f64 = 2e-5;
/// Strain of a held neighbour vertex's triangles beyond which it slides out of the grip (the
/// hand keeps its handle vertex).
pub const STRAIN_RELEASE: f64 = 0.08;
/// A hand's slip that goes on the way the last one went gives this much more than the last
/// (up to the whole give); one against it gives half ([`GestureRig::apply_slip`]).
pub const SLIP_GAIN_GROWTH: f64 = 1.25;
/// Speed of the crumple hands, m/s (grip 0.5).
const CRUMPLE_SPEED_M_S: f64 = 1.025;

/// Half-angle α of a circular arc whose chord is `1 − f` of its length (`sin α / α = 1 − f`,
/// f ∈ [0, 0.9]): the angle at which a free sheet whose ends approach by a fraction f leaves
/// its ends. Newton's method from the small-angle guess √(6f).
pub fn arc_half_angle(f: f64) -> f64 {
    let f = f.clamp(0.0, 0.9);
    if f == 0.0 {
        return 0.0;
    }
    let mut a = (6.0 * f).sqrt().min(3.0);
    for _ in 0..30 {
        let r = a.sin() / a - (1.0 - f);
        let dr = (a * a.cos() - a.sin()) / (a * a);
        if dr == 0.0 {
            break;
        }
        let next = (a - r / dr).clamp(1e-9, std::f64::consts::PI);
        if (next - a).abs() < 1e-14 {
            a = next;
            break;
        }
        a = next;
    }
    a
}

/// Largest force one finger moving at `speed_m_s` (its grip) holds, N.
pub fn grip_force_n(speed_m_s: f64) -> f64 {
    let grip = ((speed_m_s - 0.05) / 1.95).clamp(0.0, 1.0);
    GRIP_FORCE_MIN_N + GRIP_FORCE_RANGE_N * grip
}

/// Grip speed of a slot hand for a grip (velocity) 0–1, m/s.
pub fn grip_speed_m_s(grip: f32) -> f64 {
    0.05 + 1.95 * f64::from(grip.clamp(0.0, 1.0))
}

/// What kind of hand, for the target pose.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum HandKind {
    /// Back or front edge pinch.
    FrontBack,
    /// Left or right edge pinch.
    Side,
    /// A corner.
    Corner,
    /// A crumple point.
    Crumple,
}

/// Geometry of one hand on the current sheet.
#[derive(Clone, Copy, Debug, PartialEq)]
struct HandInfo {
    def: HandDef,
    kind: HandKind,
    /// Displacement of the reference point per unit of slide (pattern), metres.
    slide: V2,
}

/// Slot of each slot hand.
const SLOT_OF: [GrabSlot; NUM_SLOT_HANDS] = [
    GrabSlot::Back,
    GrabSlot::Front,
    GrabSlot::Left,
    GrabSlot::Right,
    GrabSlot::Corners,
    GrabSlot::Corners,
    GrabSlot::Corners,
    GrabSlot::Corners,
];

/// Serializable state of the rig (part of a saved sheet).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RigState {
    /// Commanded gesture values (plain units), in [`GestureParam::ALL`] order.
    pub commanded: [f32; GestureParam::COUNT],
    /// Rate-limited gesture values the targets follow.
    pub smoothed: [f64; GestureParam::COUNT],
    /// Grip of each held slot, in [`GrabSlot::ALL`] order (`None` = not held).
    pub held: [Option<f32>; 5],
    /// Hand states: 8 slot hands (back, front, left, right, 4 corners), then 8 crumple hands.
    pub hands: [HandState; NUM_HANDS],
    /// Crumple hands are active.
    pub crumple_active: bool,
    /// Crumple jitter per crumple hand: (dx, dy) as fractions of L_paper, lift factor.
    pub crumple_jitter: [[f64; 3]; NUM_CRUMPLE_HANDS],
    /// Shake phase, radians.
    pub shake_phase_rad: f64,
    /// Grab sequence number of each hand (earlier grabs keep contested vertices).
    pub grab_seq: [u64; NUM_HANDS],
    /// Next grab sequence number.
    pub next_seq: u64,
    /// Squeeze limit: the crumple value at which the sheet came close to itself (1 = none
    /// found; see "Crumple cap" in the module doc).
    #[serde(default = "no_squeeze_limit")]
    pub crumple_limit: f64,
    /// Speed of the squeeze as a fraction of the hands' speed (it slows down as the sheet
    /// approaches itself).
    #[serde(default = "no_squeeze_limit")]
    pub crumple_speed: f64,
    /// Frames in a row whose motion was undone because it passed the sheet through itself
    /// (`Sim::undo_pass_through`).
    #[serde(default)]
    pub undo_streak: u32,
    /// The crumple value's travel the hands have not followed because the squeeze is held at
    /// its limit, waiting to be pressed ("Pressing" in the module doc).
    #[serde(default)]
    pub crumple_pressed: f64,
    /// How far the squeeze has backed off (crumple value) since the sheet last had room
    /// ([`SQUEEZE_MAX_BACK_OFF`]). Saves from before it load with 0.
    #[serde(default)]
    pub crumple_backed_off: f64,
}

fn no_squeeze_limit() -> f64 {
    1.0
}

impl Default for RigState {
    fn default() -> Self {
        let mut commanded = [0.0; GestureParam::COUNT];
        let mut smoothed = [0.0; GestureParam::COUNT];
        for g in GestureParam::ALL {
            commanded[g.index()] = g.default_value();
            smoothed[g.index()] = f64::from(g.default_value());
        }
        Self {
            commanded,
            smoothed,
            held: [None; 5],
            hands: [HandState::default(); NUM_HANDS],
            crumple_active: false,
            crumple_jitter: [[0.0, 0.0, 1.0]; NUM_CRUMPLE_HANDS],
            shake_phase_rad: 0.0,
            grab_seq: [0; NUM_HANDS],
            next_seq: 0,
            crumple_limit: no_squeeze_limit(),
            crumple_speed: no_squeeze_limit(),
            undo_streak: 0,
            crumple_pressed: 0.0,
            crumple_backed_off: 0.0,
        }
    }
}

/// The rig: hand geometry on the current sheet plus its state.
#[derive(Clone, Debug)]
pub struct GestureRig {
    info: [HandInfo; NUM_HANDS],
    /// The state (gestures, grabs, hand poses).
    pub state: RigState,
    /// Suppressed slot hands (one of their handle vertices is held by a crumple hand or next to
    /// one of its handle vertices).
    suppressed: [bool; NUM_HANDS],
    /// Held vertices: (vertex, hand, index of the vertex in the hand).
    ownership: Vec<(u32, u8, u8)>,
    /// Per-vertex claim while computing the ownership (hand index or `u8::MAX`).
    claim: Vec<u8>,
    /// The claims of the previous ownership (to detect vertices changing hands).
    prev_claim: Vec<u8>,
    ownership_dirty: bool,
    /// Vertex adjacency of the sheet (CSR offsets and neighbours), to keep hands apart.
    adj_offsets: Vec<u32>,
    adj: Vec<u32>,
    /// Scratch: held neighbours to let go because they touch another hand's vertex.
    drop: Vec<bool>,
    home_z_m: f64,
    width_m: f64,
    length_m: f64,
    /// A hand travelled towards its target in the last frame ([`Self::hands_travelling`]).
    travelled: bool,
    /// Per vertex, the piece of the sheet it is on (index into the pieces of its S_P; all 0
    /// on a whole sheet), set when the mesh changes ([`Self::fit_grips_to_pieces`]).
    piece: Vec<u32>,
    /// Number of pieces labelled in `piece`.
    num_pieces: u32,
}

impl GestureRig {
    /// A rig for `sheet` whose home height is `home_z_m`.
    pub fn new(sheet: &Sheet, home_z_m: f64) -> Self {
        let h0 = HandleDef::at_vertex(sheet, 0);
        let mut rig = Self {
            info: [HandInfo {
                def: HandDef::new(sheet, &[h0]),
                kind: HandKind::Crumple,
                slide: V2::zeros(),
            }; NUM_HANDS],
            state: RigState::default(),
            suppressed: [false; NUM_HANDS],
            ownership: Vec::with_capacity(NUM_HANDS * MAX_HAND_VERTICES),
            claim: Vec::new(),
            prev_claim: Vec::new(),
            ownership_dirty: true,
            adj_offsets: Vec::new(),
            adj: Vec::new(),
            drop: Vec::new(),
            home_z_m,
            width_m: sheet.width_m,
            length_m: sheet.length_m,
            travelled: false,
            piece: Vec::new(),
            num_pieces: 0,
        };
        rig.rebuild_geometry(sheet, home_z_m);
        rig
    }

    /// Recomputes the hand geometry for a (new) sheet and re-anchors every active hand where
    /// the sheet is. Allocates only if the sheet has more vertices than before.
    pub fn rebuild_geometry(&mut self, sheet: &Sheet, home_z_m: f64) {
        let (w, l) = (sheet.width_m, sheet.length_m);
        self.width_m = w;
        self.length_m = l;
        self.home_z_m = home_z_m;
        let (hw, hl) = (0.5 * w, 0.5 * l);
        let at = |p: V2| HandleDef::at_vertex(sheet, sheet.nearest_vertex(p, true));
        let pinch = |a: V2, b: V2| HandDef::new(sheet, &[at(a), at(b)]);
        let fb = |y: f64| pinch(V2::new(-hw + 0.25 * w, y), V2::new(-hw + 0.75 * w, y));
        let side = |x: f64| pinch(V2::new(x, -hl + 0.25 * l), V2::new(x, -hl + 0.75 * l));
        self.info[0] = HandInfo {
            def: fb(hl),
            kind: HandKind::FrontBack,
            slide: V2::new(0.0, -l / 4.0),
        };
        self.info[1] = HandInfo {
            def: fb(-hl),
            kind: HandKind::FrontBack,
            slide: V2::new(0.0, l / 4.0),
        };
        self.info[2] = HandInfo {
            def: side(-hw),
            kind: HandKind::Side,
            slide: V2::new(w / 4.0, 0.0),
        };
        self.info[3] = HandInfo {
            def: side(hw),
            kind: HandKind::Side,
            slide: V2::new(-w / 4.0, 0.0),
        };
        let corners = [
            V2::new(-hw, -hl),
            V2::new(hw, -hl),
            V2::new(hw, hl),
            V2::new(-hw, hl),
        ];
        for (k, c) in corners.iter().enumerate() {
            self.info[4 + k] = HandInfo {
                def: HandDef::new(sheet, &[at(*c)]),
                kind: HandKind::Corner,
                slide: V2::new(-c.x.signum() * w / 4.0, -c.y.signum() * l / 4.0),
            };
            let v = sheet.nearest_vertex(*c, true);
            self.info[8 + k] = HandInfo {
                def: HandDef::new(sheet, &[HandleDef::point(sheet, v)]),
                kind: HandKind::Crumple,
                slide: V2::zeros(),
            };
        }
        let mids = [
            V2::new(0.0, -hl),
            V2::new(hw, 0.0),
            V2::new(0.0, hl),
            V2::new(-hw, 0.0),
        ];
        for (k, m) in mids.iter().enumerate() {
            let v = sheet.nearest_vertex(*m, true);
            self.info[12 + k] = HandInfo {
                def: HandDef::new(sheet, &[HandleDef::point(sheet, v)]),
                kind: HandKind::Crumple,
                slide: V2::zeros(),
            };
        }
        self.fit_grips_to_pieces(sheet);
        if self.claim.len() != sheet.sp.num_vertices() {
            self.claim = vec![u8::MAX; sheet.sp.num_vertices()];
            self.prev_claim = vec![u8::MAX; sheet.sp.num_vertices()];
        }
        self.ownership.clear();
        for c in &mut self.claim {
            *c = u8::MAX;
        }
        self.adj_offsets
            .clone_from(&sheet.sp.topo.adjacency_offsets);
        self.adj.clone_from(&sheet.sp.topo.adjacency);
        self.drop.clear();
        self.drop.resize(NUM_HANDS * MAX_HAND_VERTICES, false);
        for k in 0..NUM_HANDS {
            if self.state.hands[k].active {
                let def = self.info[k].def;
                self.state.hands[k].reanchor(&def, &sheet.sp.pos);
            }
        }
        self.ownership_dirty = true;
    }

    /// Fits the hands' grips to the pieces of the sheet: labels each vertex with its piece
    /// ([`Self::hold_hinged_pieces`]); on a torn sheet, every slot hand takes the torn mesh's
    /// rings around its handle vertices, and a crumple hand that shares its piece with at most
    /// two other crumple hands holds its handle's 1-ring as a pinch instead of the bare point:
    /// a piece hanging from one point is a pendulum, one hanging from two points swings about
    /// the line through them (a hinge), and one held at three points flaps about the lines
    /// between them (a torn half held at three crumple points swung for 2 s in the stress
    /// sessions); point handles hold no rotation, while fingers pinching paper hold its tangent
    /// plane. On a whole sheet every
    /// crumple hand shares the piece with seven others and stays a point (the ring shrinks
    /// without neighbouring hands' patches colliding). The ring is the torn mesh's (one taken
    /// before the tear may reach across a lip); active hands whose grip changes re-anchor
    /// where the sheet is. Allocates (the pieces): called only when the mesh changes.
    pub fn fit_grips_to_pieces(&mut self, sheet: &Sheet) {
        let (piece, num_pieces) = sheet.sp.topo.vertex_pieces();
        self.piece = piece;
        self.num_pieces = num_pieces as u32;
        if num_pieces < 2 {
            return;
        }
        // Slot hands keep their handle vertices and take the torn mesh's rings around them.
        for k in 0..NUM_SLOT_HANDS {
            let d = self.info[k].def;
            let nm = usize::from(d.num_mains).clamp(1, 2);
            let handles = [0, nm - 1].map(|j| HandleDef::at_vertex(sheet, d.vertices[j]));
            let def = HandDef::new(sheet, &handles[..nm]);
            if def == d {
                continue;
            }
            self.info[k].def = def;
            if self.state.hands[k].active {
                self.state.hands[k].reanchor(&def, &sheet.sp.pos);
            }
            self.ownership_dirty = true;
        }
        let label = &self.piece;
        let piece_of = |i: &HandInfo| label[i.def.vertices()[0] as usize];
        for k in NUM_SLOT_HANDS..NUM_HANDS {
            let own = piece_of(&self.info[k]);
            let others = (NUM_SLOT_HANDS..NUM_HANDS)
                .filter(|&j| j != k && piece_of(&self.info[j]) == own)
                .count();
            if others > 2 {
                continue;
            }
            // The ring of the torn mesh (a ring taken before the tear may reach across a lip).
            let v = self.info[k].def.vertices()[0];
            let def = HandDef::new(sheet, &[HandleDef::at_vertex(sheet, v)]);
            if def == self.info[k].def {
                continue;
            }
            self.info[k].def = def;
            if self.state.hands[k].active {
                self.state.hands[k].reanchor(&def, &sheet.sp.pos);
            }
            self.ownership_dirty = true;
        }
    }

    /// A piece the hands hold at fewer than three points, or at points on one line, hangs
    /// from them as a pendulum or swings about the line as a hinge, and a still hand does not
    /// stop it (point holds carry no rotation). Once every hand is still, such a piece is held
    /// as fingers hold paper: a hand holding one of its handle vertices on the piece takes back
    /// the tangent-plane neighbours on the piece it let go of (misfit at the grab, strain
    /// release, regrip), where they are now and only where the paper is relaxed (below half
    /// the release strain, so a ring let go under strain is not taken back and let go again);
    /// a piece held only by neighbour vertices (a fragment torn off next to a grip) is let go
    /// and falls. `pattern` are the sheet's pattern positions, `vertex_strain` the largest
    /// strain of each vertex's triangles, `spacing_m` the mesh's edge length (points within a
    /// quarter of it of one line count as on it). Returns true if a grip changed. Allocates
    /// nothing.
    pub fn hold_hinged_pieces(
        &mut self,
        pattern: &[V2],
        vertex_strain: &[f64],
        spacing_m: f64,
    ) -> bool {
        let n = pattern.len();
        if self.ownership_dirty
            || self.travelled
            || self.piece.len() != n
            || vertex_strain.len() != n
            || self.state.hands.iter().any(|h| h.active && h.slipping)
        {
            return false;
        }
        let mut changed = false;
        for p in 0..self.num_pieces {
            let mut pts = [V2::zeros(); NUM_HANDS * MAX_HAND_VERTICES];
            let (mut m, mut main_held) = (0, false);
            for &(v, k, j) in &self.ownership {
                if self.piece[v as usize] == p && m < pts.len() {
                    pts[m] = pattern[v as usize];
                    m += 1;
                    main_held |= j < self.info[k as usize].def.num_mains;
                }
            }
            if m == 0 || !on_one_line(&pts[..m], 0.25 * spacing_m) {
                continue;
            }
            for k in 0..NUM_HANDS {
                let h = &self.state.hands[k];
                if !h.active || self.suppressed[k] {
                    continue;
                }
                let def = self.info[k].def;
                let nm = def.num_mains as usize;
                let holds_main_here = (0..nm).any(|j| {
                    let v = def.vertices[j] as usize;
                    self.piece[v] == p && self.claim[v] == k as u8
                });
                let h = &mut self.state.hands[k];
                for j in 0..def.num_vertices as usize {
                    let v = def.vertices[j] as usize;
                    if self.piece[v] != p {
                        continue;
                    }
                    if main_held {
                        if holds_main_here
                            && j >= nm
                            && !h.holds(j)
                            && self.claim[v] == u8::MAX
                            && vertex_strain[v] <= 0.5 * STRAIN_RELEASE
                        {
                            h.mask |= 1 << j;
                            changed = true;
                        }
                    } else if self.claim[v] == k as u8 && h.holds(j) {
                        h.mask &= !(1u16 << j);
                        changed = true;
                    }
                }
            }
        }
        self.ownership_dirty |= changed;
        changed
    }

    /// Sets the home height (the table top) the targets are measured from.
    pub fn set_home_height(&mut self, home_z_m: f64) {
        self.home_z_m = home_z_m;
    }

    /// L_paper, metres.
    /// Per-frame hand travel clamp at this frame rate (`frame_scale` = default rate / rate), m.
    fn travel_clamp_m(&self, frame_scale: f64) -> f64 {
        TRAVEL_CLAMP_FRAC * self.l_paper() * frame_scale
    }

    fn l_paper(&self) -> f64 {
        self.width_m.max(self.length_m)
    }

    /// A hand takes hold of a slot (a second grab of a held slot only changes the grip).
    pub fn grab(&mut self, slot: GrabSlot, grip: f32, pos: &[V3]) {
        let grip = if grip.is_finite() {
            grip.clamp(0.0, 1.0)
        } else {
            0.5
        };
        let speed = grip_speed_m_s(grip);
        let was = self.state.held[slot.index()].is_some();
        self.state.held[slot.index()] = Some(grip);
        if !was {
            self.state.next_seq = self.state.next_seq.saturating_add(1);
        }
        for (k, &s) in SLOT_OF.iter().enumerate() {
            if s == slot {
                if was {
                    self.state.hands[k].speed_m_s = speed;
                } else {
                    let def = self.info[k].def;
                    self.state.hands[k] = HandState::grab(&def, pos, speed);
                    self.state.grab_seq[k] = self.state.next_seq;
                }
            }
        }
        self.ownership_dirty = true;
    }

    /// The hand holding `slot` lets go.
    pub fn release(&mut self, slot: GrabSlot) {
        self.state.held[slot.index()] = None;
        for (k, &s) in SLOT_OF.iter().enumerate() {
            if s == slot {
                self.state.hands[k].active = false;
            }
        }
        self.ownership_dirty = true;
    }

    /// Every hand lets go (crumple hands stay while crumple > 0).
    pub fn release_all(&mut self) {
        for s in GrabSlot::ALL {
            self.release(s);
        }
    }

    /// Sets a gesture value (already sanitized by the caller).
    pub fn set_gesture(&mut self, g: GestureParam, value: f32) {
        let i = g.index();
        let limit = self.state.crumple_limit;
        if g == GestureParam::Crumple && limit < 1.0 {
            // The part of the change above the squeeze limit, which the hands cannot follow.
            let (old, new) = (f64::from(self.state.commanded[i]), f64::from(value));
            let pressed = (new.max(limit) - old.max(limit)).abs();
            if pressed.is_finite() {
                self.state.crumple_pressed += pressed;
            }
        }
        self.state.commanded[i] = value;
    }

    /// This frame's press ("Pressing" in the module doc): how far the crumple hands would have
    /// closed or opened this frame, metres summed over the hands, had the squeeze not been held
    /// at its limit. At most one frame of the hands' travel; the rest is pressed in the next
    /// frames (so a jump of the value presses at the hands' speed, not in one frame).
    pub fn take_press_m(&mut self, frame_scale: f64) -> f64 {
        let pressed = self.state.crumple_pressed;
        if pressed.is_nan() || pressed <= 0.0 || !self.state.crumple_active {
            self.state.crumple_pressed = 0.0;
            return 0.0;
        }
        let step = pressed.min(self.crumple_rate_at(self.travel_clamp_m(frame_scale), 1.0));
        self.state.crumple_pressed = pressed - step;
        let hands_m: f64 = (0..NUM_CRUMPLE_HANDS)
            .map(|j| self.info[NUM_SLOT_HANDS + j].def.home_ref.norm())
            .sum();
        step * CRUMPLE_CAP * hands_m
    }

    /// True if the rig will move something in the next frame.
    pub fn is_moving(&self) -> bool {
        let any_active = self.state.hands.iter().any(|h| h.active);
        let shaking = any_active && self.state.smoothed[GestureParam::ShakeDepth.index()] > 0.0;
        let settling = GestureParam::ALL
            .iter()
            .any(|&g| self.slew_target(g) != self.state.smoothed[g.index()]);
        let crumple_pending = (self.state.commanded[GestureParam::Crumple.index()] > 0.0)
            != self.state.crumple_active;
        let pressing = self.state.crumple_pressed > 0.0;
        shaking || settling || crumple_pending || pressing || self.ownership_dirty
    }

    /// True if an active hand travelled towards its target in the last frame: it is still on
    /// its way (at most its travel clamp a frame), though every gesture has settled. A hand
    /// giving way to the sheet's pull does not count.
    pub fn hands_travelling(&self) -> bool {
        self.travelled
    }

    /// Number of active hands (crumple hands included, suppressed ones excluded).
    pub fn num_active_hands(&self) -> usize {
        (0..NUM_HANDS)
            .filter(|&k| self.state.hands[k].active && !self.suppressed[k])
            .count()
    }

    /// Advances the rig by one frame: gesture slew, crumple on/off, target poses, hand poses.
    /// Returns true if any hand moved.
    pub fn advance_frame(
        &mut self,
        dt_s: f64,
        frame_scale: f64,
        pos: &[V3],
        obstacles: &Obstacles,
        rng: &mut rand_pcg::Pcg32,
    ) -> bool {
        let clamp_m = self.travel_clamp_m(frame_scale);
        let max_angle = ROTATION_CLAMP_RAD * frame_scale;
        self.slew_gestures(clamp_m, max_angle);
        let crumple_smoothed = self.state.smoothed[GestureParam::Crumple.index()];
        let rate = self.state.smoothed[GestureParam::ShakeRateHz.index()];

        // Crumple hands on/off.
        let c_cmd = self.state.commanded[GestureParam::Crumple.index()];
        if c_cmd > 0.0 && !self.state.crumple_active {
            self.state.crumple_active = true;
            use rand::RngExt;
            for k in 0..NUM_CRUMPLE_HANDS {
                self.state.crumple_jitter[k] = [
                    rng.random_range(-0.03..0.03),
                    rng.random_range(-0.03..0.03),
                    rng.random_range(0.6..1.4),
                ];
                let def = self.info[NUM_SLOT_HANDS + k].def;
                self.state.hands[NUM_SLOT_HANDS + k] =
                    HandState::grab(&def, pos, CRUMPLE_SPEED_M_S);
            }
            self.ownership_dirty = true;
        } else if self.state.crumple_active && c_cmd <= 0.0 && crumple_smoothed <= 0.0 {
            self.state.crumple_active = false;
            for k in NUM_SLOT_HANDS..NUM_HANDS {
                self.state.hands[k].active = false;
            }
            self.ownership_dirty = true;
        }
        if self.ownership_dirty {
            self.recompute_ownership(pos);
        }

        self.state.shake_phase_rad = (self.state.shake_phase_rad
            + std::f64::consts::TAU * rate * dt_s)
            .rem_euclid(std::f64::consts::TAU);
        let mut moved = false;
        self.travelled = false;
        for k in 0..NUM_HANDS {
            if !self.state.hands[k].active || self.suppressed[k] {
                continue;
            }
            let target = self.pushed_out(k, self.target_pose(k), obstacles);
            moved |= self.state.hands[k].advance(&target, dt_s, clamp_m, max_angle);
            // Travel, not a slip (a slip moves the pose after this, `apply_slip`).
            self.travelled |= !self.state.hands[k].is_still();
        }
        moved |= self.carried_by_obstacles(obstacles, dt_s);
        moved
    }

    /// The value a gesture slews towards: the commanded one, the crumple squeeze no further
    /// than its limit.
    fn slew_target(&self, g: GestureParam) -> f64 {
        let v = f64::from(self.state.commanded[g.index()]);
        if g == GestureParam::Crumple {
            v.min(self.state.crumple_limit)
        } else {
            v
        }
    }

    /// Largest change of a gesture value per frame (its slew rate) for the per-frame travel
    /// and rotation clamps.
    fn slew_rate(&self, g: GestureParam, clamp_m: f64, max_angle: f64) -> f64 {
        let (w, l) = (self.width_m, self.length_m);
        match g {
            GestureParam::Slide => 4.0 * clamp_m / self.l_paper(),
            GestureParam::Lift => 2.0 * clamp_m / l,
            GestureParam::Twist => {
                (max_angle / std::f64::consts::PI).min(clamp_m / (std::f64::consts::PI * 0.5 * w))
            }
            GestureParam::Crumple => self.crumple_rate(clamp_m),
            GestureParam::ShakeDepth => clamp_m / (SHAKE_AMPLITUDE_FRAC * SHAKE_REFERENCE_LENGTH_M),
            // The hands' rotation (radians) that tears (sim/tear.rs).
            GestureParam::TearAmount => max_angle,
            // The pulling hands' force rises over at least 0.2 s (a jump is a firm pull, not
            // an impulse).
            GestureParam::PullSeparation => 0.025 * max_angle / ROTATION_CLAMP_RAD,
            _ => f64::INFINITY,
        }
    }

    /// Slew rate of the crumple value: the fastest crumple hand's target moves no faster than
    /// the hands travel (their speed, within the travel clamp), so the hands keep up with the
    /// value and stopping the value stops them (see "Crumple cap" in the module doc).
    fn crumple_rate(&self, clamp_m: f64) -> f64 {
        self.crumple_rate_at(clamp_m, self.state.crumple_speed)
    }

    /// [`Self::crumple_rate`] at a squeeze speed (1: before it slows near the sheet).
    fn crumple_rate_at(&self, clamp_m: f64, speed: f64) -> f64 {
        let frame_s = clamp_m / (TRAVEL_CLAMP_FRAC * self.l_paper() * DEFAULT_FRAME_RATE_HZ);
        let step_m = clamp_m.min(CRUMPLE_SPEED_M_S * frame_s);
        let lp = self.l_paper();
        // |∂target/∂c| of each crumple hand (see `target_pose`).
        let reach_m = (0..NUM_CRUMPLE_HANDS)
            .map(|j| {
                let home = self.info[NUM_SLOT_HANDS + j].def.home_ref;
                let jit = self.state.crumple_jitter[j];
                CRUMPLE_CAP * home.norm()
                    + lp * jit[0].hypot(jit[1])
                    + 0.1 * self.length_m * jit[2].abs()
            })
            .fold(0.0, f64::max);
        if reach_m > 0.0 {
            speed * step_m / reach_m
        } else {
            f64::INFINITY
        }
    }

    /// True while the crumple hands squeeze or are about to (the sim then measures the
    /// sheet's closest approach to itself for [`Self::limit_squeeze`]).
    pub fn is_squeezing(&self) -> bool {
        self.state.crumple_active || self.state.commanded[GestureParam::Crumple.index()] > 0.0
    }

    /// Caps the squeeze where the sheet comes close to itself (see "Crumple cap" in the module
    /// doc): `closest_m` is the sheet's closest approach to itself this frame
    /// ([`crate::self_proximity`]). Below [`SQUEEZE_BACK_OFF_M`] the hands back off by one
    /// frame's travel, by at most [`SQUEEZE_MAX_BACK_OFF`] until the sheet has room again, below
    /// [`SQUEEZE_STOP_M`] they stop; a commanded value below the limit
    /// releases it (the next squeeze goes on until the sheet comes close again).
    pub fn limit_squeeze(&mut self, closest_m: f64, frame_scale: f64) {
        let i = GestureParam::Crumple.index();
        let c = self.state.smoothed[i];
        self.state.crumple_speed = ((closest_m - SQUEEZE_STOP_M)
            / (SQUEEZE_SLOW_M - SQUEEZE_STOP_M))
            .clamp(SQUEEZE_SLOWEST, 1.0);
        if f64::from(self.state.commanded[i]) < self.state.crumple_limit
            && closest_m >= SQUEEZE_STOP_M
        {
            self.state.crumple_limit = 1.0;
        }
        if closest_m >= SQUEEZE_STOP_M {
            self.state.crumple_backed_off = 0.0;
        }
        // A sheet crossing itself (0) backs off as far as it takes.
        let bounded = closest_m > 0.0;
        if closest_m < SQUEEZE_BACK_OFF_M
            && (!bounded || self.state.crumple_backed_off < SQUEEZE_MAX_BACK_OFF)
        {
            let clamp_m = self.travel_clamp_m(frame_scale);
            let rate = self.slew_rate(GestureParam::Crumple, clamp_m, 0.0);
            let rate = if bounded {
                rate.min(SQUEEZE_MAX_BACK_OFF - self.state.crumple_backed_off)
            } else {
                rate
            };
            let to = (c - rate).max(0.0);
            self.state.crumple_backed_off += c - to;
            self.state.crumple_limit = to;
        } else if closest_m < SQUEEZE_STOP_M {
            self.state.crumple_limit = self.state.crumple_limit.min(c);
        }
    }

    fn slew_gestures(&mut self, clamp_m: f64, max_angle: f64) {
        for gp in GestureParam::ALL {
            let i = gp.index();
            let target = self.slew_target(gp);
            let rate = self.slew_rate(gp, clamp_m, max_angle);
            let cur = self.state.smoothed[i];
            let d = target - cur;
            self.state.smoothed[i] = if d.abs() <= rate {
                target
            } else {
                cur + rate * d.signum()
            };
        }
    }

    /// Target pose of hand `k` from the smoothed gestures.
    fn target_pose(&self, k: usize) -> Pose {
        let g = |p: GestureParam| self.state.smoothed[p.index()];
        let info = &self.info[k];
        let home = info.def.home_ref;
        let l = self.length_m;
        let lp = self.l_paper();
        let z0 = self.home_z_m;
        let shake = g(GestureParam::ShakeDepth)
            * SHAKE_AMPLITUDE_FRAC
            * SHAKE_REFERENCE_LENGTH_M
            * self.state.shake_phase_rad.sin();
        if info.kind == HandKind::Crumple {
            let j = k - NUM_SLOT_HANDS;
            let c = g(GestureParam::Crumple);
            let jit = self.state.crumple_jitter[j];
            let p = home * (1.0 - c * CRUMPLE_CAP) + V2::new(jit[0], jit[1]) * (c * lp);
            let lift = c * 0.1 * l * jit[2];
            let inward = -home.normalize();
            let axis = V3::new(inward.x, inward.y, 0.0).cross(&V3::z());
            let rot = nalgebra::Unit::try_new(axis, 1e-12)
                .map(|a| Rot::from_axis_angle(&a, c * CRUMPLE_TILT_RAD))
                .unwrap_or_else(Rot::identity);
            return Pose::new(V3::new(p.x, p.y, z0 + lift + shake), rot);
        }
        let slide = g(GestureParam::Slide);
        let p = home + info.slide * slide;
        let mut pos = V3::new(p.x, p.y, z0 + shake);
        // Tilt the held patch with the slide (inner side up), so the approaching edges bow
        // the sheet upwards instead of compressing it flat.
        let mut rot = Rot::identity();
        if slide > 0.0 {
            let u = info.slide.normalize();
            let axis = V3::new(u.x, u.y, 0.0).cross(&V3::z());
            if let Some(a) = nalgebra::Unit::try_new(axis, 1e-12) {
                rot = Rot::from_axis_angle(&a, SLIDE_TILT_GAIN * arc_half_angle(0.5 * slide));
            }
        }
        let lift = g(GestureParam::Lift);
        if info.kind == HandKind::Side {
            // Pivot about the back finger (x-parallel axis) until the front finger has risen
            // by lift·L/2 (or stands straight above the back finger).
            if lift > 0.0 {
                let d = &info.def;
                let (o0, o1) = (d.home_offsets[0], d.home_offsets[1]);
                let (front_o, back_o) = if o0.y < o1.y { (o0, o1) } else { (o1, o0) };
                let span = (back_o - front_o).norm();
                let theta = (lift * 0.5 * l / span).clamp(0.0, 1.0).asin();
                let r = Rot::from_axis_angle(&-V3::x_axis(), theta);
                let back = pos + rot * back_o;
                pos = back + r * (pos - back);
                rot = r * rot;
            }
        } else if home.y < 0.0 {
            pos.z += lift * 0.5 * l;
            let phi = g(GestureParam::Twist) * std::f64::consts::PI;
            if phi != 0.0 {
                // Rotation about −y by φ raises the +x side.
                let r = Rot::from_axis_angle(&-V3::y_axis(), phi);
                let axis_pt = V3::new(0.0, pos.y, pos.z);
                pos = axis_pt + r * (pos - axis_pt);
                rot = r * rot;
            }
        }
        Pose::new(pos, rot)
    }

    /// Recomputes which hand holds which vertex. A neighbour vertex that changes hands (its
    /// previous holder let go, or a new hand took it) is taken where it is now: its offset in
    /// the new holder is refitted to its current position, so it never jumps to a stale offset.
    fn recompute_ownership(&mut self, pos: &[V3]) {
        self.ownership.clear();
        self.prev_claim.copy_from_slice(&self.claim);
        for c in &mut self.claim {
            *c = u8::MAX;
        }
        let was_suppressed = self.suppressed;
        self.suppressed = [false; NUM_HANDS];
        // Crumple hands first (fixed order), then slot hands by grab order (earlier grabs
        // keep contested vertices), ties in slot order.
        let mut order = [0usize; NUM_HANDS];
        for (i, o) in order.iter_mut().enumerate() {
            *o = i;
        }
        let seq = self.state.grab_seq;
        order[..NUM_SLOT_HANDS].sort_unstable_by_key(|&k| (seq[k], k));
        let groups = [&order[NUM_SLOT_HANDS..], &order[..NUM_SLOT_HANDS]];
        for group in groups {
            // Handle vertices first, then neighbours.
            for &k in group {
                if !self.state.hands[k].active {
                    continue;
                }
                let def = &self.info[k].def;
                let nm = def.num_mains as usize;
                // A handle vertex another hand holds, or next to one of its handle vertices:
                // two rigid grips one edge apart would tear the paper between them as they
                // move, so the later hand stands aside.
                let taken = |v: u32| {
                    let (a, b) = (
                        self.adj_offsets[v as usize] as usize,
                        self.adj_offsets[v as usize + 1] as usize,
                    );
                    self.claim[v as usize] != u8::MAX
                        || self.adj[a..b]
                            .iter()
                            .any(|&u| self.claim[u as usize] != u8::MAX)
                };
                if def.vertices[..nm].iter().any(|&v| taken(v)) {
                    self.suppressed[k] = true;
                    continue;
                }
                for (j, &v) in def.vertices[..nm].iter().enumerate() {
                    self.claim[v as usize] = k as u8;
                    self.ownership.push((v, k as u8, j as u8));
                }
            }
            for &k in group {
                if !self.state.hands[k].active || self.suppressed[k] {
                    continue;
                }
                let def = self.info[k].def;
                for j in def.num_mains as usize..def.num_vertices as usize {
                    let v = def.vertices[j];
                    if self.state.hands[k].holds(j) && self.claim[v as usize] == u8::MAX {
                        self.claim[v as usize] = k as u8;
                        self.ownership.push((v, k as u8, j as u8));
                    }
                }
            }
        }
        // Hands do not touch: a held neighbour next to a vertex of another hand is let go (two
        // rigid grips joined by one short edge would fight over it; the free vertex between
        // them lets the paper fold instead).
        for (i, &(v, k, j)) in self.ownership.iter().enumerate() {
            let neighbour = (j as usize) >= self.info[k as usize].def.num_mains as usize;
            let (a, b) = (
                self.adj_offsets[v as usize] as usize,
                self.adj_offsets[v as usize + 1] as usize,
            );
            self.drop[i] = neighbour
                && self.adj[a..b].iter().any(|&u| {
                    let c = self.claim[u as usize];
                    c != u8::MAX && c != k
                });
        }
        let mut i = 0;
        self.ownership.retain(|&(v, _, _)| {
            let keep = !self.drop[i];
            if !keep {
                self.claim[v as usize] = u8::MAX;
            }
            i += 1;
            keep
        });
        // A hand that gets its vertices back starts again from where the sheet is, with the
        // grip of a new grab: its neighbours are claimed at the next recomputation (the claims
        // above were made with its old grip).
        let mut reanchored = false;
        for (k, &was) in was_suppressed.iter().enumerate() {
            if was && !self.suppressed[k] && self.state.hands[k].active {
                let def = self.info[k].def;
                self.state.hands[k].reanchor(&def, pos);
                reanchored = true;
            }
        }
        for &(v, k, j) in &self.ownership {
            if self.prev_claim[v as usize] != k {
                let h = &mut self.state.hands[k as usize];
                let o = h.pose.rotation().inverse() * (pos[v as usize] - h.pose.pos());
                h.offsets_m[j as usize] = [o.x, o.y, o.z];
            }
        }
        self.ownership_dirty = reanchored;
    }

    /// Writes the kinematic constraints at fraction `s` ∈ [0, 1] of the current frame:
    /// `fixed[v]` for held vertices and their positions in `target`.
    pub fn fill_kinematics(&self, s: f64, fixed: &mut [bool], target: &mut [V3]) {
        for f in fixed.iter_mut() {
            *f = false;
        }
        for &(v, k, j) in &self.ownership {
            fixed[v as usize] = true;
            target[v as usize] = self.state.hands[k as usize].held_position(j as usize, s);
        }
    }

    /// Takes back this frame's hand motion (the sim undid the frame: see
    /// `Sim::undo_pass_through`): every hand returns to its pose at the start of the frame.
    pub fn undo_frame_motion(&mut self) {
        for h in &mut self.state.hands {
            h.pose = h.prev_pose;
        }
    }

    /// Lets hands give way where the sheet pulls harder than their grip or is strained beyond
    /// what paper takes, never deeper into an obstacle (module doc, "Grip and obstacles").
    /// `forces` are the elastic forces on the vertices, `vertex_strain` the largest strain of
    /// each vertex's triangles ([`crate::metrics::vertex_strains`]), `spacing_m` the mesh's
    /// edge length. Returns true if any hand slipped or let go of a vertex.
    pub fn apply_slip(
        &mut self,
        forces: &[V3],
        vertex_strain: &[f64],
        spacing_m: f64,
        frame_scale: f64,
        obstacles: &Obstacles,
    ) -> bool {
        let clamp_m = self.travel_clamp_m(frame_scale);
        let mut f = [V3::zeros(); NUM_HANDS];
        let mut strain = [0.0f64; NUM_HANDS];
        let mut any = false;
        for &(v, k, j) in &self.ownership {
            f[k as usize] += forces[v as usize];
            let s = vertex_strain.get(v as usize).copied().unwrap_or(0.0);
            strain[k as usize] = strain[k as usize].max(s);
            // A finger does not hold paper torn apart under it: a held neighbour (not the
            // handle vertex itself) whose triangles are strained beyond the release strain
            // slides out of the grip.
            let h = &mut self.state.hands[k as usize];
            if s > STRAIN_RELEASE && j >= self.info[k as usize].def.num_mains && h.holds(j as usize)
            {
                h.mask &= !(1u16 << j);
                self.ownership_dirty = true;
                any = true;
            }
        }
        for (k, fk) in f.iter().enumerate() {
            let h = &mut self.state.hands[k];
            // Fingers that slid in the last frame or move now hold to STRAIN_GIVE; still ones
            // to STRAIN_GIVE_STILL (static friction holds more than kinetic), so a sheet that
            // sags in still hands stops instead of creeping through them at a strain just
            // over the give.
            let give_strain = if h.sliding || !h.is_still() {
                STRAIN_GIVE
            } else {
                STRAIN_GIVE_STILL
            };
            h.sliding = false;
            if !h.active || self.suppressed[k] {
                continue;
            }
            let h = &self.state.hands[k];
            let n = fk.norm();
            let fmax = grip_force_n(h.speed_m_s) * f64::from(self.info[k].def.num_mains);
            // The give: the pull beyond the grip, and the strain beyond a few percent (paper
            // does not stretch; the hand's fingers slide instead).
            let give_m = (n - fmax).max(0.0) * HAND_COMPLIANCE_M_N
                + (strain[k] - give_strain).max(0.0) * spacing_m;
            // A give below SLIP_MIN_M is a hand at its balance (or a rounding error), not a
            // slip: it would keep a held sheet awake forever for nothing.
            if give_m > SLIP_MIN_M && n > 0.0 && n.is_finite() && give_m.is_finite() {
                let dir = fk / n;
                let r = h.pose.rotation();
                let p0 = h.pose.pos();
                let mut p = p0 + dir * give_m.min(clamp_m);
                for pl in obstacles.planes.iter().filter(|pl| pl.active) {
                    let excess =
                        self.held_depth_m(k, p, &r, pl) - self.held_depth_m(k, p0, &r, pl).max(0.0);
                    if excess > 0.0 {
                        p += pl.normal * excess;
                    }
                }
                // A slip against the last one's direction overshot the balance: halve the
                // give, so a hand the sheet pulls back and forth settles instead of swinging.
                // The direction is the move's, out of the obstacles (a pull into the table
                // swinging sideways is still a swing).
                let step = p - p0;
                let len = step.norm();
                let gain = if step.dot(&V3::from(h.slip_dir)) < 0.0 {
                    0.5 * h.slip_gain
                } else {
                    (SLIP_GAIN_GROWTH * h.slip_gain).min(1.0)
                };
                // The segment from p0 stays out of the obstacles (depth is linear along it).
                let p = p0 + step * gain;
                // Given way into a table or a wall, the hand goes nowhere: it holds.
                if (p - p0).norm() <= SLIP_MIN_M {
                    continue;
                }
                let dir = step / len;
                let h = &mut self.state.hands[k];
                h.pose = Pose::new(p, r);
                h.slipping = true;
                h.slip_dir = [dir.x, dir.y, dir.z];
                h.slip_gain = gain;
                h.sliding = true;
                any = true;
            }
        }
        any
    }

    /// Gives way where the strain limit moved held vertices (`moved[v]`,
    /// [`crate::physics::strain_limit`]; module doc, "Paper does not stretch"): a hand whose
    /// handle vertices moved slips by their mean move, rigidly (its grip keeps its shape), and
    /// a moved held neighbour slides out of the grip. The slip counts as the hand's last one
    /// for [`GestureRig::apply_slip`]'s swing damping. Returns true if any held vertex moved.
    pub fn regrip(&mut self, pos: &[V3], moved: &[bool]) -> bool {
        let mut shift = [V3::zeros(); NUM_HANDS];
        let mut count = [0u32; NUM_HANDS];
        let mut any = false;
        for &(v, k, j) in &self.ownership {
            if !moved.get(v as usize).copied().unwrap_or(false) {
                continue;
            }
            any = true;
            let h = &mut self.state.hands[k as usize];
            if j < self.info[k as usize].def.num_mains {
                shift[k as usize] += pos[v as usize] - h.held_position(j as usize, 1.0);
                count[k as usize] += 1;
            } else {
                h.mask &= !(1u16 << j);
                self.ownership_dirty = true;
            }
        }
        for (k, h) in self.state.hands.iter_mut().enumerate() {
            if count[k] > 0 {
                let d = shift[k] / f64::from(count[k]);
                let n = d.norm();
                if n > 0.0 && n.is_finite() {
                    h.pose = Pose::new(h.pose.pos() + d, h.pose.rotation());
                    h.slipping = true;
                    // A give of the grip against this slip is a swing between the two.
                    h.slip_dir = (d / n).into();
                }
            }
        }
        any
    }

    /// Vertices currently held (for tags and stats).
    pub fn held_vertices(&self) -> impl Iterator<Item = u32> + '_ {
        self.ownership.iter().map(|o| o.0)
    }

    /// The hand holding vertex `v`, if any (tests and diagnostics).
    pub fn hand_of(&self, v: u32) -> Option<usize> {
        self.ownership
            .iter()
            .find(|o| o.0 == v)
            .map(|o| usize::from(o.1))
    }

    /// The definition of hand `k` (tests and diagnostics).
    pub fn hand_def(&self, k: usize) -> &HandDef {
        &self.info[k].def
    }
}

/// True if `pts` are fewer than three or all within `tol_m` of the line through the two of
/// them farthest apart.
fn on_one_line(pts: &[V2], tol_m: f64) -> bool {
    let (mut a, mut b, mut far) = (0, 0, 0.0);
    for i in 0..pts.len() {
        for j in i + 1..pts.len() {
            let d = (pts[j] - pts[i]).norm_squared();
            if d > far {
                (a, b, far) = (i, j, d);
            }
        }
    }
    if far <= tol_m * tol_m {
        return true;
    }
    let dir = (pts[b] - pts[a]) / far.sqrt();
    pts.iter().all(|q| {
        let r = q - pts[a];
        (r.x * dir.y - r.y * dir.x).abs() <= tol_m
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::control::SheetSize;
    use crate::room::RoomConfig;
    use crate::sheet::MeshConfig;
    use rand::SeedableRng;

    /// A crumple hand left alone on a piece torn off the sheet holds its 1-ring; the others,
    /// sharing the rest of the sheet, stay points, and a whole sheet has only points.
    #[test]
    fn a_crumple_hand_on_a_piece_held_at_one_two_or_three_points_holds_its_ring() {
        use crate::sheet::geometric::GeomStructure;
        use crate::sheet::tear_step::{TearFrom, advance_tear};
        let whole = Sheet::new_flat(SheetSize::A6, MeshConfig::default(), 0.75, 0.1);
        let rig = GestureRig::new(&whole, 0.75);
        assert!((NUM_SLOT_HANDS..NUM_HANDS).all(|k| rig.info[k].def.num_vertices == 1));
        let (hw, hl) = (0.5 * whole.width_m, 0.5 * whole.length_m);
        // Tears `whole` along a polyline from the border until it is in two pieces.
        let tear_off = |path: &[V2]| {
            let mut sp = whole.sp.clone();
            let mut from = TearFrom::Border(path[0]);
            'legs: for leg in path.windows(2) {
                let steps = ((leg[1] - leg[0]).norm() / 0.01).ceil() as usize;
                for k in 1..=steps {
                    let to = leg[0] + (leg[1] - leg[0]) * (k as f64 / steps as f64);
                    // A step that crosses no edge yet waits for the next (as the sim's tear).
                    let Ok(st) = advance_tear(&sp, from, to) else {
                        continue;
                    };
                    from = TearFrom::Tip(st.tip);
                    sp = st.mesh;
                    if sp.topo.pieces().len() == 2 {
                        break 'legs;
                    }
                }
            }
            assert_eq!(sp.topo.pieces().len(), 2);
            let sg = GeomStructure::initial(&sp);
            Sheet {
                sp,
                sg,
                ..whole.clone()
            }
        };
        let handle =
            |rig: &GestureRig, k: usize| whole.sp.pattern[rig.info[k].def.vertices()[0] as usize];
        // The back-left corner torn off, 4 cm from it: one crumple hand on it.
        let torn = tear_off(&[V2::new(-hw, -hl + 0.04), V2::new(-hw + 0.04, -hl - 0.01)]);
        let rig = GestureRig::new(&torn, 0.75);
        let corner = torn.nearest_vertex(V2::new(-hw, -hl), true);
        for k in NUM_SLOT_HANDS..NUM_HANDS {
            let def = &rig.info[k].def;
            if def.vertices()[0] == corner {
                assert!(def.num_vertices >= 3, "the lone corner holds its ring");
            } else {
                assert_eq!(def.num_vertices, 1, "hand {k} shares its piece: a point");
            }
        }
        // The back-left quarter torn off around the corner hand and the left edge's hand: two
        // crumple hands on it (a hinge), both pinch; the six on the rest stay points.
        let on_quarter = |p: V2| p.x < -0.01 && p.y < 0.012;
        let path = [
            V2::new(-hw, 0.012),
            V2::new(-0.01, 0.012),
            V2::new(-0.01, -hl - 0.01),
        ];
        let torn = tear_off(&path);
        let rig = GestureRig::new(&torn, 0.75);
        let mut pinched = 0;
        let whole_rig = GestureRig::new(&whole, 0.75);
        for k in NUM_SLOT_HANDS..NUM_HANDS {
            let p = handle(&whole_rig, k);
            let def = &rig.info[k].def;
            if on_quarter(p) {
                assert!(
                    def.num_vertices >= 3,
                    "hand {k} on the hinged quarter pinches"
                );
                pinched += 1;
            } else {
                assert_eq!(
                    def.num_vertices, 1,
                    "hand {k} shares its piece with 5: a point"
                );
            }
        }
        assert_eq!(pinched, 2);
        // The back strip torn off across the sheet: three crumple hands on it (the back
        // corners and the back edge's middle), whose piece still flaps about the lines between
        // them: all three pinch; the five on the rest stay points.
        let y_cut = -0.5 * hl + 0.002;
        let torn = tear_off(&[V2::new(-hw, y_cut), V2::new(hw, y_cut)]);
        let rig = GestureRig::new(&torn, 0.75);
        let mut pinched = 0;
        for k in NUM_SLOT_HANDS..NUM_HANDS {
            let def = &rig.info[k].def;
            if handle(&whole_rig, k).y < y_cut {
                assert!(def.num_vertices >= 3, "hand {k} on the strip pinches");
                pinched += 1;
            } else {
                assert_eq!(
                    def.num_vertices, 1,
                    "hand {k} shares its piece with 4: a point"
                );
            }
        }
        assert_eq!(pinched, 3);
    }

    fn setup() -> (Sheet, GestureRig, Obstacles, rand_pcg::Pcg32) {
        let sheet = Sheet::new_flat(SheetSize::A4, MeshConfig::default(), 0.75, 0.1);
        let rig = GestureRig::new(&sheet, 0.75);
        (
            sheet,
            rig,
            Obstacles::new(&RoomConfig::default()),
            rand_pcg::Pcg32::seed_from_u64(1),
        )
    }

    /// The default room without its table.
    fn no_table() -> Obstacles {
        Obstacles::new(&RoomConfig {
            table: false,
            ..RoomConfig::default()
        })
    }

    fn run(
        rig: &mut GestureRig,
        sheet: &Sheet,
        obs: &Obstacles,
        rng: &mut rand_pcg::Pcg32,
        frames: usize,
    ) {
        for _ in 0..frames {
            rig.advance_frame(0.005, 1.0, &sheet.sp.pos, obs, rng);
        }
    }

    fn targets(rig: &GestureRig, sheet: &Sheet) -> (Vec<bool>, Vec<V3>) {
        let n = sheet.sp.num_vertices();
        let (mut fixed, mut target) = (vec![false; n], vec![V3::zeros(); n]);
        rig.fill_kinematics(1.0, &mut fixed, &mut target);
        (fixed, target)
    }

    #[test]
    fn slide_brings_back_and_front_together() {
        let (sheet, mut rig, obs, mut rng) = setup();
        rig.grab(GrabSlot::Back, 1.0, &sheet.sp.pos);
        rig.grab(GrabSlot::Front, 1.0, &sheet.sp.pos);
        rig.set_gesture(GestureParam::Slide, 1.0);
        run(&mut rig, &sheet, &obs, &mut rng, 200);
        let (fixed, target) = targets(&rig, &sheet);
        let back = rig.info[0].def.vertices[0] as usize;
        let front = rig.info[1].def.vertices[0] as usize;
        let l = sheet.length_m;
        // Home gap L, each edge moved L/4 inwards (the pinches also tilt, so compare the
        // reference points of the hands).
        let gap = rig.state.hands[0].pose.pos().y - rig.state.hands[1].pose.pos().y;
        assert!((gap - 0.5 * l).abs() < 1e-9, "gap {gap}");
        assert!(target[back].y - target[front].y < 0.6 * l);
        assert!(fixed.iter().filter(|&&f| f).count() >= 4 * 4);
    }

    /// A hand still on its way to its target is travelling though every gesture has settled
    /// (the home height dropped by a room change: no gesture moves), and stops travelling
    /// when it arrives.
    #[test]
    fn a_hand_on_its_way_is_travelling_until_it_arrives() {
        let (sheet, mut rig, _, mut rng) = setup();
        // No table: the hand's target is not pushed back up to a table top.
        let obs = no_table();
        rig.grab(GrabSlot::Front, 1.0, &sheet.sp.pos);
        run(&mut rig, &sheet, &obs, &mut rng, 20);
        assert!(!rig.is_moving() && !rig.hands_travelling(), "held still");
        rig.set_home_height(0.45);
        let mut frames = 0;
        while rig.hands_travelling() || frames == 0 {
            assert!(!rig.is_moving(), "no gesture moves");
            run(&mut rig, &sheet, &obs, &mut rng, 1);
            frames += 1;
            assert!(frames < 1000, "the hand never arrives");
        }
        // 30 cm at the travel clamp (2 % of the A4's length a frame, 5.9 mm) and no faster.
        assert!(frames >= 50, "arrived in {frames} frames");
        let hand = rig.state.hands.iter().find(|h| h.active).unwrap();
        let z = hand.pose.pos().z;
        assert!((z - 0.45).abs() < 0.02, "the hand at {z} m");
    }

    /// A hand pulled down and sideways beyond its grip slips sideways along the table but not
    /// into it; with no table it slips down too (so the test can fail).
    #[test]
    fn a_slipping_hand_slides_along_the_table_not_into_it() {
        let (sheet, _, table, mut rng) = setup();
        let no_table = no_table();
        for (obs, on_table) in [(&table, true), (&no_table, false)] {
            let mut rig = GestureRig::new(&sheet, 0.75);
            rig.grab(GrabSlot::Back, 0.0, &sheet.sp.pos);
            run(&mut rig, &sheet, obs, &mut rng, 5);
            let (fixed, before) = targets(&rig, &sheet);
            let mut forces = vec![V3::zeros(); sheet.sp.num_vertices()];
            for (f, &held) in forces.iter_mut().zip(&fixed) {
                if held {
                    *f = V3::new(30.0, 0.0, -30.0);
                }
            }
            let no_strain = vec![0.0; forces.len()];
            assert!(rig.apply_slip(&forces, &no_strain, 0.033, 1.0, obs));
            let (_, after) = targets(&rig, &sheet);
            let held: Vec<usize> = (0..fixed.len()).filter(|&i| fixed[i]).collect();
            let dx = held.iter().map(|&i| after[i].x - before[i].x).sum::<f64>();
            let z_min = held
                .iter()
                .map(|&i| after[i].z)
                .fold(f64::INFINITY, f64::min);
            assert!(dx > 1e-4 * held.len() as f64, "slid {dx}");
            if on_table {
                assert!(z_min >= 0.75 - 1e-12, "into the table: {z_min}");
            } else {
                assert!(z_min < 0.75 - 1e-4, "slipped down: {z_min}");
            }
        }
    }

    /// The held vertices' mean displacement between two target sets.
    fn mean_shift(before: &[V3], after: &[V3], fixed: &[bool]) -> V3 {
        let held: Vec<usize> = (0..fixed.len()).filter(|&i| fixed[i]).collect();
        held.iter().map(|&i| after[i] - before[i]).sum::<V3>() / held.len() as f64
    }

    /// A hand pulled back and forth beyond its grip gives less each time the pull reverses
    /// (halved), so it settles at its balance instead of swinging over it frame after frame.
    #[test]
    fn a_hand_pulled_back_and_forth_gives_less_each_time() {
        let (sheet, mut rig, _, mut rng) = setup();
        let obs = no_table();
        rig.grab(GrabSlot::Back, 0.0, &sheet.sp.pos);
        run(&mut rig, &sheet, &obs, &mut rng, 5);
        let no_strain = vec![0.0; sheet.sp.num_vertices()];
        let mut gives = Vec::new();
        for k in 0..6 {
            let (fixed, before) = targets(&rig, &sheet);
            let pull = if k % 2 == 0 { 30.0 } else { -30.0 };
            let forces: Vec<V3> = fixed
                .iter()
                .map(|&h| {
                    if h {
                        V3::new(pull, 0.0, 0.0)
                    } else {
                        V3::zeros()
                    }
                })
                .collect();
            assert!(rig.apply_slip(&forces, &no_strain, 0.033, 1.0, &obs));
            let (_, after) = targets(&rig, &sheet);
            gives.push(mean_shift(&before, &after, &fixed).x.abs());
        }
        for w in gives.windows(2) {
            assert!(
                (w[1] - 0.5 * w[0]).abs() < 1e-9 * w[0],
                "gives {gives:?}: each reversal halves the give"
            );
        }
    }

    /// A still hand whose held vertices' triangles are strained beyond STRAIN_GIVE_STILL gives
    /// way along the sheet's pull even when the pull is within its grip, and goes on giving
    /// beyond STRAIN_GIVE while it slides; a held neighbour strained beyond STRAIN_RELEASE
    /// slides out of the grip; below these the hand holds.
    #[test]
    fn a_strained_grip_gives_way_and_lets_go_of_the_torn_vertex() {
        let (sheet, mut rig, obs, mut rng) = setup();
        rig.grab(GrabSlot::Back, 1.0, &sheet.sp.pos);
        run(&mut rig, &sheet, &obs, &mut rng, 5);
        let n = sheet.sp.num_vertices();
        let (fixed, before) = targets(&rig, &sheet);
        // A gentle pull along +y, well within the grip.
        let forces: Vec<V3> = fixed
            .iter()
            .map(|&h| {
                if h {
                    V3::new(0.0, 0.01, 0.0)
                } else {
                    V3::zeros()
                }
            })
            .collect();
        let mut strain = vec![0.0; n];
        assert!(
            !rig.apply_slip(&forces, &strain, 0.033, 1.0, &obs),
            "holds unstrained"
        );
        let held = rig.hand_def(0).vertices[..rig.hand_def(0).num_vertices as usize].to_vec();
        let strain_all = |strain: &mut Vec<f64>, s: f64| {
            for &v in &held {
                strain[v as usize] = s;
            }
        };
        // Still fingers hold beyond STRAIN_GIVE, up to STRAIN_GIVE_STILL.
        strain_all(&mut strain, 0.05);
        assert!(
            !rig.apply_slip(&forces, &strain, 0.033, 1.0, &obs),
            "a still hand holds at 5 %"
        );
        strain_all(&mut strain, 0.08);
        assert!(rig.apply_slip(&forces, &strain, 0.033, 1.0, &obs));
        let (_, after) = targets(&rig, &sheet);
        let shift = mean_shift(&before, &after, &fixed);
        assert!(
            (shift.y - (0.08 - STRAIN_GIVE_STILL) * 0.033).abs() < 1e-9 && shift.x.abs() < 1e-12,
            "gave {shift:?} along the pull"
        );
        // Sliding, they hold to STRAIN_GIVE only.
        run(&mut rig, &sheet, &obs, &mut rng, 1);
        strain_all(&mut strain, 0.05);
        assert!(
            rig.apply_slip(&forces, &strain, 0.033, 1.0, &obs),
            "a sliding hand gives at 5 %"
        );
        // A neighbour (not a handle vertex) torn beyond STRAIN_RELEASE slides out.
        let nm = rig.hand_def(0).num_mains as usize;
        let torn = held[nm];
        strain[torn as usize] = 0.09;
        rig.apply_slip(&forces, &strain, 0.033, 1.0, &obs);
        run(&mut rig, &sheet, &obs, &mut rng, 1);
        assert_eq!(rig.hand_of(torn), None, "the torn neighbour is let go");
        assert_eq!(rig.hand_of(held[0]), Some(0), "the handle vertex is kept");
    }

    #[test]
    fn lift_and_twist_move_only_the_front_group() {
        let (sheet, mut rig, obs, mut rng) = setup();
        rig.grab(GrabSlot::Corners, 1.0, &sheet.sp.pos);
        rig.set_gesture(GestureParam::Lift, 0.5);
        rig.set_gesture(GestureParam::Twist, 0.25);
        run(&mut rig, &sheet, &obs, &mut rng, 300);
        let (_, target) = targets(&rig, &sheet);
        let l = sheet.length_m;
        let fl = rig.info[4].def.vertices[0] as usize; // front-left
        let fr = rig.info[5].def.vertices[0] as usize; // front-right
        let br = rig.info[6].def.vertices[0] as usize;
        assert!((target[br].z - 0.75).abs() < 1e-9, "back corner stays");
        // Front corners rotated by π/4 about the axis at height 0.75 + L/4: right side up.
        let zc = 0.75 + 0.25 * l;
        let hw = 0.5 * sheet.width_m;
        let s = (std::f64::consts::PI / 4.0).sin() * hw;
        assert!((target[fr].z - (zc + s)).abs() < 1e-9, "{}", target[fr].z);
        assert!((target[fl].z - (zc - s)).abs() < 1e-9);
    }

    #[test]
    fn side_hands_pivot_rigidly_with_lift() {
        // No table: the part of the patch behind the back finger dips as the hand pivots, and
        // a table would push the whole hand up.
        let (sheet, mut rig, _, mut rng) = setup();
        let obs = no_table();
        rig.grab(GrabSlot::Left, 1.0, &sheet.sp.pos);
        rig.set_gesture(GestureParam::Lift, 0.5);
        run(&mut rig, &sheet, &obs, &mut rng, 300);
        let (_, target) = targets(&rig, &sheet);
        let d = &rig.info[2].def;
        let (front, back) = (d.vertices[0] as usize, d.vertices[1] as usize);
        let l = sheet.length_m;
        assert!(sheet.sp.pattern[front].y < sheet.sp.pattern[back].y);
        assert!(
            (target[front].z - (0.75 + 0.25 * l)).abs() < 1e-9,
            "front finger up by L/4: {}",
            target[front].z
        );
        assert!((target[back].z - 0.75).abs() < 1e-9, "back finger stays");
        // Rigid: the fingers keep their pattern distance.
        let dp = (sheet.sp.pattern[front] - sheet.sp.pattern[back]).norm();
        assert!(((target[front] - target[back]).norm() - dp).abs() < 1e-9);
    }

    #[test]
    fn a_hand_back_from_standing_aside_holds_its_whole_grip() {
        // The corner hands stand aside while the crumple hands hold their corners, and take
        // them back with a new grab's grip when the crumple ends: every vertex of that grip is
        // held (not only those of the grip they had when they stood aside).
        let (sheet, mut rig, obs, mut rng) = setup();
        rig.grab(GrabSlot::Corners, 1.0, &sheet.sp.pos);
        run(&mut rig, &sheet, &obs, &mut rng, 2);
        // The corners' rings let go (as the strain release does).
        for k in 4..8 {
            let nm = rig.info[k].def.num_mains;
            rig.state.hands[k].mask &= (1u16 << nm) - 1;
        }
        rig.ownership_dirty = true;
        rig.set_gesture(GestureParam::Crumple, 1.0);
        run(&mut rig, &sheet, &obs, &mut rng, 5);
        rig.set_gesture(GestureParam::Crumple, 0.0);
        for _ in 0..400 {
            run(&mut rig, &sheet, &obs, &mut rng, 1);
            if !rig.state.crumple_active {
                break;
            }
        }
        assert!(!rig.state.crumple_active);
        run(&mut rig, &sheet, &obs, &mut rng, 2);
        for k in 4..8 {
            assert!(!rig.suppressed[k]);
            let (h, def) = (&rig.state.hands[k], &rig.info[k].def);
            assert!(
                def.num_vertices > def.num_mains,
                "corner hand {k} has a ring"
            );
            for j in 0..def.num_vertices as usize {
                if h.holds(j) {
                    let v = def.vertices[j];
                    assert!(
                        rig.ownership.contains(&(v, k as u8, j as u8)),
                        "hand {k} grips vertex {v} but does not hold it"
                    );
                }
            }
        }
    }

    #[test]
    fn crumple_takes_precedence_and_releases() {
        let (sheet, mut rig, obs, mut rng) = setup();
        rig.grab(GrabSlot::Corners, 1.0, &sheet.sp.pos);
        rig.set_gesture(GestureParam::Crumple, 1.0);
        run(&mut rig, &sheet, &obs, &mut rng, 5);
        assert!(rig.state.crumple_active);
        for k in 4..8 {
            assert!(rig.suppressed[k], "corner hand {k} suppressed");
        }
        assert_eq!(rig.num_active_hands(), 8);
        run(&mut rig, &sheet, &obs, &mut rng, 400);
        let (_, target) = targets(&rig, &sheet);
        let c0 = rig.info[8].def.vertices[0] as usize;
        let r = V2::new(target[c0].x, target[c0].y).norm();
        let r0 = sheet.sp.pattern[c0].norm();
        assert!(
            r < 0.5 * r0,
            "corner squeezed towards the centre: {r} vs {r0}"
        );
        rig.set_gesture(GestureParam::Crumple, 0.0);
        run(&mut rig, &sheet, &obs, &mut rng, 400);
        assert!(!rig.state.crumple_active);
        assert_eq!(rig.num_active_hands(), 4, "corner hands back");
        assert!(!rig.is_moving());
    }

    #[test]
    fn points_on_one_line_are_told_from_a_triangle() {
        let p = |x: f64, y: f64| V2::new(x, y);
        assert!(on_one_line(&[], 0.01));
        assert!(on_one_line(&[p(0.0, 0.0)], 0.01));
        assert!(on_one_line(&[p(0.0, 0.0), p(0.3, 0.1)], 0.01));
        assert!(on_one_line(
            &[p(0.0, 0.0), p(0.1, 0.005), p(0.2, 0.0)],
            0.01
        ));
        assert!(!on_one_line(
            &[p(0.0, 0.0), p(0.1, 0.02), p(0.2, 0.0)],
            0.01
        ));
        assert!(!on_one_line(&[p(0.0, 0.0), p(0.0, 0.1), p(0.1, 0.0)], 0.01));
    }

    /// A sheet one hand holds at its two handle vertices only (its ring let go) swings about
    /// the edge between them: once the hand is still it takes its ring back, where the paper
    /// is relaxed; a sheet also held elsewhere is not touched.
    #[test]
    fn a_still_hand_holding_a_piece_on_one_line_takes_its_ring_back() {
        let (sheet, mut rig, obs, mut rng) = setup();
        let n = sheet.sp.num_vertices();
        let spacing = MeshConfig::default().spacing_m(SheetSize::A4);
        rig.grab(GrabSlot::Front, 1.0, &sheet.sp.pos);
        run(&mut rig, &sheet, &obs, &mut rng, 3);
        assert!(!rig.is_moving());
        let front = 1;
        let full = rig.state.hands[front].mask;
        let mains = (1u16 << rig.info[front].def.num_mains) - 1;
        assert!(full != mains, "the front edge's hand holds a ring");
        let let_go = |rig: &mut GestureRig, rng: &mut rand_pcg::Pcg32| {
            for h in &mut rig.state.hands {
                if h.active {
                    h.mask &= (1u16 << rig.info[0].def.num_mains.max(2)) - 1;
                }
            }
            rig.ownership_dirty = true;
            run(rig, &sheet, &obs, rng, 1);
        };
        let_go(&mut rig, &mut rng);
        assert_eq!(rig.state.hands[front].mask, mains);
        // Strained paper is not taken back.
        let strained = vec![0.05; n];
        assert!(!rig.hold_hinged_pieces(&sheet.sp.pattern, &strained, spacing));
        assert_eq!(rig.state.hands[front].mask, mains);
        let relaxed = vec![0.0; n];
        assert!(rig.hold_hinged_pieces(&sheet.sp.pattern, &relaxed, spacing));
        assert_eq!(rig.state.hands[front].mask, full, "the ring is held again");
        run(&mut rig, &sheet, &obs, &mut rng, 1);
        assert!(!rig.hold_hinged_pieces(&sheet.sp.pattern, &relaxed, spacing));
        // The back edge held too: four handle vertices, not on one line.
        rig.grab(GrabSlot::Back, 1.0, &sheet.sp.pos);
        run(&mut rig, &sheet, &obs, &mut rng, 3);
        let_go(&mut rig, &mut rng);
        assert_eq!(rig.state.hands[front].mask, mains);
        assert!(!rig.hold_hinged_pieces(&sheet.sp.pattern, &relaxed, spacing));
        assert_eq!(rig.state.hands[front].mask, mains);
    }

    #[test]
    fn arc_half_angle_solves_the_chord_equation() {
        assert_eq!(arc_half_angle(0.0), 0.0);
        for f in [0.01, 0.1, 0.5, 0.8] {
            let a = arc_half_angle(f);
            assert!((a.sin() / a - (1.0 - f)).abs() < 1e-10, "{f}");
        }
    }

    #[test]
    fn jumps_are_rate_limited() {
        let (sheet, mut rig, obs, mut rng) = setup();
        rig.grab(GrabSlot::Front, 1.0, &sheet.sp.pos);
        rig.set_gesture(GestureParam::Twist, 1.0);
        rig.advance_frame(0.005, 1.0, &sheet.sp.pos, &obs, &mut rng);
        assert!(
            rig.state.smoothed[GestureParam::Twist.index()]
                <= ROTATION_CLAMP_RAD / std::f64::consts::PI + 1e-12
        );
        let h = &rig.state.hands[1];
        assert!(
            (h.pose.pos() - h.prev_pose.pos()).norm() <= TRAVEL_CLAMP_FRAC * sheet.length_m + 1e-12
        );
    }

    /// The squeeze limit: far from itself the squeeze runs at full speed; within
    /// [`SQUEEZE_SLOW_M`] it slows; below [`SQUEEZE_STOP_M`] it stops where it is (is_moving
    /// turns false: the sheet may sleep); below [`SQUEEZE_BACK_OFF_M`] it backs off; a
    /// commanded value under the limit releases it once the sheet is clear again.
    #[test]
    fn the_squeeze_slows_stops_backs_off_and_is_released() {
        let (sheet, mut rig, obs, mut rng) = setup();
        let c = |rig: &GestureRig| rig.state.smoothed[GestureParam::Crumple.index()];
        rig.set_gesture(GestureParam::Crumple, 1.0);
        let step = |rig: &mut GestureRig, rng: &mut rand_pcg::Pcg32, closest_m: f64| {
            rig.limit_squeeze(closest_m, 1.0);
            let before = rig.state.smoothed[GestureParam::Crumple.index()];
            rig.advance_frame(0.005, 1.0, &sheet.sp.pos, &obs, rng);
            rig.state.smoothed[GestureParam::Crumple.index()] - before
        };
        let full = step(&mut rig, &mut rng, f64::INFINITY);
        assert!(full > 0.0);
        let full = step(&mut rig, &mut rng, f64::INFINITY);
        let mid = 0.5 * (SQUEEZE_SLOW_M + SQUEEZE_STOP_M);
        let slow = step(&mut rig, &mut rng, mid);
        assert!((slow / full - 0.5).abs() < 1e-9, "{slow} vs {full}");
        let near = step(&mut rig, &mut rng, SQUEEZE_STOP_M + 1e-4);
        assert!(
            (near / full - SQUEEZE_SLOWEST).abs() < 1e-9,
            "{near} vs {full}"
        );
        let held = c(&rig);
        assert_eq!(
            step(
                &mut rig,
                &mut rng,
                0.5 * (SQUEEZE_STOP_M + SQUEEZE_BACK_OFF_M)
            ),
            0.0
        );
        assert_eq!(rig.state.crumple_limit, held);
        assert!(
            !GestureParam::ALL
                .iter()
                .any(|&g| rig.slew_target(g) != rig.state.smoothed[g.index()])
        );
        // Clear again but still commanded 1: the limit stays (no restart against the fold).
        assert_eq!(step(&mut rig, &mut rng, f64::INFINITY), 0.0);
        let back = step(&mut rig, &mut rng, 0.0);
        assert!(back < 0.0 && c(&rig) < held, "{back}");
        // Lowering the command under the limit releases it; raising it squeezes again.
        let lowered = (0.5 * rig.state.crumple_limit) as f32;
        rig.set_gesture(GestureParam::Crumple, lowered);
        for _ in 0..100 {
            step(&mut rig, &mut rng, f64::INFINITY);
        }
        assert_eq!(rig.state.crumple_limit, 1.0);
        assert_eq!(c(&rig), f64::from(lowered));
        rig.set_gesture(GestureParam::Crumple, 1.0);
        assert!(step(&mut rig, &mut rng, f64::INFINITY) > 0.0);
    }

    /// A squeeze whose backing off does not part the layers stops backing off after
    /// SQUEEZE_MAX_BACK_OFF (rest family seed 5: an A6 twisted and crumpled kept unfolding for
    /// 0.5 s after the last change, down to 0); once the sheet has room it may back off again.
    #[test]
    fn the_squeeze_backs_off_a_tenth_at_most_while_the_layers_stay_close() {
        let (sheet, mut rig, obs, mut rng) = setup();
        let g = GestureParam::Crumple;
        rig.set_gesture(g, 0.8);
        run(&mut rig, &sheet, &obs, &mut rng, 400);
        let c0 = rig.state.smoothed[g.index()];
        assert!((c0 - 0.8).abs() < 1e-6, "{c0}");
        for _ in 0..400 {
            rig.limit_squeeze(1e-4, 1.0);
            run(&mut rig, &sheet, &obs, &mut rng, 1);
        }
        let held = rig.state.smoothed[g.index()];
        assert!((held - (c0 - 0.1)).abs() < 1e-9, "{held}");
        assert!((rig.state.crumple_limit - (c0 - 0.1)).abs() < 1e-9);
        // Room again, then close again: another back-off of at most a tenth.
        rig.limit_squeeze(SQUEEZE_STOP_M, 1.0);
        for _ in 0..400 {
            rig.limit_squeeze(1e-4, 1.0);
            run(&mut rig, &sheet, &obs, &mut rng, 1);
        }
        let held = rig.state.smoothed[g.index()];
        assert!((held - (c0 - 0.2)).abs() < 1e-9, "{held}");
        // A sheet crossing itself backs off as far as it takes.
        for _ in 0..2000 {
            rig.limit_squeeze(0.0, 1.0);
            run(&mut rig, &sheet, &obs, &mut rng, 1);
        }
        assert_eq!(rig.state.smoothed[g.index()], 0.0);
    }

    /// Pressing: with the squeeze held at its limit, the command's travel above the limit (up
    /// or down) is pressed, at most one frame of the hands' travel per frame, in metres summed
    /// over the hands; the part under the limit, and any travel with no limit, is not.
    #[test]
    fn a_held_squeeze_presses_what_the_hands_cannot_follow() {
        let (sheet, mut rig, obs, mut rng) = setup();
        let g = GestureParam::Crumple;
        rig.set_gesture(g, 0.5);
        assert_eq!(rig.state.crumple_pressed, 0.0, "no limit, no press");
        run(&mut rig, &sheet, &obs, &mut rng, 400);
        assert_eq!(rig.state.smoothed[g.index()], 0.5);
        rig.limit_squeeze(0.5 * (SQUEEZE_STOP_M + SQUEEZE_BACK_OFF_M), 1.0);
        assert_eq!(rig.state.crumple_limit, 0.5);
        assert_eq!(rig.take_press_m(1.0), 0.0);
        let hands_m: f64 = (0..NUM_CRUMPLE_HANDS)
            .map(|j| rig.info[NUM_SLOT_HANDS + j].def.home_ref.norm())
            .sum::<f64>()
            * CRUMPLE_CAP;
        let frame_m = rig.crumple_rate_at(rig.travel_clamp_m(1.0), 1.0) * hands_m;
        let drain = |rig: &mut GestureRig| {
            let (mut sum, mut frames) = (0.0, 0);
            while rig.state.crumple_pressed > 0.0 {
                assert!(rig.is_moving(), "a press keeps the sheet awake");
                let p = rig.take_press_m(1.0);
                assert!(p > 0.0 && p <= frame_m * (1.0 + 1e-12), "{p} vs {frame_m}");
                sum += p;
                frames += 1;
                assert!(frames < 10_000);
            }
            (sum, frames)
        };
        // Up by 0.3 in one jump: pressed over several frames, at the hands' speed.
        rig.set_gesture(g, 0.8);
        let (sum, frames) = drain(&mut rig);
        assert!((sum - 0.3 * hands_m).abs() < 1e-6 * hands_m, "{sum}");
        assert!(frames > 1, "{frames}");
        // Down to 0.3: only the travel above the limit (0.8 → 0.5) is pressed.
        rig.set_gesture(g, 0.3);
        let (sum, _) = drain(&mut rig);
        assert!((sum - 0.3 * hands_m).abs() < 1e-6 * hands_m, "{sum}");
        // Under the limit the hands follow: released, and nothing pressed.
        rig.limit_squeeze(f64::INFINITY, 1.0);
        assert_eq!(rig.state.crumple_limit, 1.0);
        rig.set_gesture(g, 0.9);
        assert_eq!(rig.state.crumple_pressed, 0.0);
        assert_eq!(rig.take_press_m(1.0), 0.0);
    }

    /// The crumple value moves no faster than the hands can follow: the fastest crumple
    /// hand's target moves at most its speed per frame, so every hand keeps up.
    #[test]
    fn crumple_hands_keep_up_with_the_squeeze() {
        let (sheet, mut rig, obs, mut rng) = setup();
        rig.set_gesture(GestureParam::Crumple, 1.0);
        let mut prev: Option<Vec<V3>> = None;
        for _ in 0..150 {
            rig.advance_frame(0.005, 1.0, &sheet.sp.pos, &obs, &mut rng);
            let now: Vec<V3> = (NUM_SLOT_HANDS..NUM_HANDS)
                .map(|k| rig.target_pose(k).pos())
                .collect();
            if let Some(prev) = &prev {
                for (a, b) in prev.iter().zip(&now) {
                    assert!((a - b).norm() <= CRUMPLE_SPEED_M_S * 0.005 + 1e-9);
                }
            }
            for k in NUM_SLOT_HANDS..NUM_HANDS {
                let lag = (rig.target_pose(k).pos() - rig.state.hands[k].pose.pos()).norm();
                assert!(lag < 1e-9, "hand {k} lags {lag} m");
            }
            prev = Some(now);
        }
        assert_eq!(rig.state.smoothed[GestureParam::Crumple.index()], 1.0);
    }
}
