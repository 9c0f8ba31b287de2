//! # Playing a script: frame-by-frame commands for the simulation
//!
//! A [`Script`] (automation lanes, grabs, resets; [`crate::script`]) becomes a stream of
//! [`Command`]s, frame by frame, exactly as the plugin would send them from a DAW track:
//!
//! - the `[set]` values apply before frame 0 ([`ScriptRunner::config`] folds the sheet and room
//!   values into a [`SimConfig`]; [`ScriptRunner::initial_commands`] has them all as commands);
//! - frame k covers simulated time `[k/f, (k+1)/f)`; it first applies the discrete inputs
//!   (resets, then releases, then grabs at equal times) with time `< (k+1)/f` not yet applied,
//!   then, for every lane, the lane's value at `k/f` if it changed since the last frame;
//! - gesture ids become [`Command::Gesture`], `size` / `material` / `seed` become
//!   [`Command::Size`] / [`Command::Material`] / [`Command::Seed`], the room ids (`table`,
//!   `table_height_cm`, `wall`, `wall_dist_cm`) one [`Command::Room`] per frame with the
//!   changed room; listener, mix and output ids are valid but not simulation inputs, so the
//!   runner skips them.
//!
//! [`validate`] checks every id against this vocabulary and every value against its type
//! (an id unknown to everyone is an error, with the place it occurs).

use thiserror::Error;

use crate::control::{Command, GestureParam, Material, SheetSize};
use crate::room::RoomConfig;
use crate::script::{DiscreteInput, Lane, Script, ScriptValue};
use crate::sim::{FrameOutput, Sim, SimConfig};

/// Ids that are valid script parameters but not simulation inputs (the plugin's listener,
/// mix and output parameters).
pub const NON_SIM_IDS: [&str; 6] = [
    "listener_az_deg",
    "listener_dist_m",
    "mix_crumple_db",
    "mix_friction_db",
    "mix_tear_db",
    "gain_db",
];

/// What a script parameter id drives.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ParamTarget {
    /// A gesture.
    Gesture(GestureParam),
    /// The sheet size (text id).
    Size,
    /// The paper grade (text id).
    Material,
    /// The random seed (non-negative integer).
    Seed,
    /// Table on/off.
    Table,
    /// Table height, cm.
    TableHeight,
    /// Wall on/off.
    Wall,
    /// Wall distance, cm.
    WallDist,
    /// Valid, but not a simulation input (listener, mix, gain): numeric.
    NotSim,
}

impl ParamTarget {
    /// Classifies an id; `None` if no one knows it.
    pub fn of(id: &str) -> Option<Self> {
        if let Some(g) = GestureParam::from_id(id) {
            return Some(Self::Gesture(g));
        }
        Some(match id {
            "size" => Self::Size,
            "material" => Self::Material,
            "seed" => Self::Seed,
            "table" => Self::Table,
            "table_height_cm" => Self::TableHeight,
            "wall" => Self::Wall,
            "wall_dist_cm" => Self::WallDist,
            _ if NON_SIM_IDS.contains(&id) => Self::NotSim,
            _ => return None,
        })
    }
}

/// Why a script cannot drive the simulation.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum RunnerError {
    /// An id nobody knows.
    #[error("{place}: unknown parameter id {id:?}")]
    UnknownParam {
        /// The id.
        id: String,
        /// Where it occurs (`[set]` or `lane N`).
        place: String,
    },
    /// A value of the wrong type or out of its domain.
    #[error("{place}: {id} = {value} is not valid ({expected})")]
    BadValue {
        /// The id.
        id: String,
        /// The value as written.
        value: String,
        /// What was expected.
        expected: &'static str,
        /// Where it occurs.
        place: String,
    },
}

fn check_value(
    target: ParamTarget,
    id: &str,
    v: &ScriptValue,
    place: &str,
) -> Result<(), RunnerError> {
    let bad = |expected: &'static str| RunnerError::BadValue {
        id: id.to_string(),
        value: v.to_string(),
        expected,
        place: place.to_string(),
    };
    match target {
        ParamTarget::Gesture(_)
        | ParamTarget::TableHeight
        | ParamTarget::WallDist
        | ParamTarget::NotSim => v
            .as_f64()
            .filter(|x| x.is_finite())
            .map(|_| ())
            .ok_or_else(|| bad("a number")),
        ParamTarget::Seed => match v {
            ScriptValue::Number(x)
                if x.is_finite() && *x >= 0.0 && x.fract() == 0.0 && *x < 2f64.powi(53) =>
            {
                Ok(())
            }
            _ => Err(bad("a non-negative integer")),
        },
        ParamTarget::Table | ParamTarget::Wall => match v {
            ScriptValue::Bool(_) => Ok(()),
            _ => Err(bad("true or false")),
        },
        ParamTarget::Size => match v {
            ScriptValue::Text(s) if SheetSize::from_id(s).is_some() => Ok(()),
            _ => Err(bad("one of \"a4\", \"a5\", \"a6\", \"sq10\"")),
        },
        ParamTarget::Material => match v {
            ScriptValue::Text(s) if Material::from_id(s).is_some() => Ok(()),
            _ => Err(bad("one of \"printer\", \"tracing\", \"banknote\"")),
        },
    }
}

/// Checks every parameter id and value of a script.
pub fn validate(script: &Script) -> Result<(), RunnerError> {
    for (id, v) in &script.set {
        let target = ParamTarget::of(id).ok_or_else(|| RunnerError::UnknownParam {
            id: id.clone(),
            place: "[set]".into(),
        })?;
        check_value(target, id, v, "[set]")?;
    }
    for (i, lane) in script.lanes.iter().enumerate() {
        let place = format!("lane {} ({})", i + 1, lane.id);
        let target = ParamTarget::of(&lane.id).ok_or_else(|| RunnerError::UnknownParam {
            id: lane.id.clone(),
            place: place.clone(),
        })?;
        for (_, v) in &lane.points {
            check_value(target, &lane.id, v, &place)?;
        }
    }
    Ok(())
}

/// Applies one (validated) value to a room; returns true if it is a room id.
fn apply_room(room: &mut RoomConfig, target: ParamTarget, v: &ScriptValue) -> bool {
    match (target, v) {
        (ParamTarget::Table, ScriptValue::Bool(b)) => room.table = *b,
        (ParamTarget::Wall, ScriptValue::Bool(b)) => room.wall = *b,
        (ParamTarget::TableHeight, ScriptValue::Number(x)) => room.table_height_cm = *x as f32,
        (ParamTarget::WallDist, ScriptValue::Number(x)) => room.wall_dist_cm = *x as f32,
        _ => return false,
    }
    true
}

/// The command for a (validated) non-room value, if it is a simulation input.
fn command_for(target: ParamTarget, v: &ScriptValue) -> Option<Command> {
    match (target, v) {
        (ParamTarget::Gesture(g), ScriptValue::Number(x)) => Some(Command::Gesture {
            param: g,
            value: *x as f32,
        }),
        (ParamTarget::Size, ScriptValue::Text(s)) => SheetSize::from_id(s).map(Command::Size),
        (ParamTarget::Material, ScriptValue::Text(s)) => {
            Material::from_id(s).map(Command::Material)
        }
        (ParamTarget::Seed, ScriptValue::Number(x)) => Some(Command::Seed(*x as u64)),
        _ => None,
    }
}

/// Plays a script as per-frame commands.
#[derive(Clone, Debug)]
pub struct ScriptRunner {
    frame_rate_hz: f64,
    num_frames: u64,
    discrete: Vec<(f64, DiscreteInput)>,
    next_discrete: usize,
    lanes: Vec<(Lane, ParamTarget)>,
    last: Vec<Option<ScriptValue>>,
    initial: Vec<Command>,
    set_values: Vec<(ParamTarget, ScriptValue)>,
    room: RoomConfig,
    frame: u64,
    buf: Vec<Command>,
}

impl ScriptRunner {
    /// A runner for `script` at `frame_rate_hz`, starting from the room `base_room` (overridden
    /// by the script's `[set]` room values).
    pub fn new(
        script: &Script,
        frame_rate_hz: f64,
        base_room: RoomConfig,
    ) -> Result<Self, RunnerError> {
        validate(script)?;
        let frame_rate_hz = if frame_rate_hz.is_finite() && frame_rate_hz >= 1.0 {
            frame_rate_hz
        } else {
            crate::sim::DEFAULT_FRAME_RATE_HZ
        };
        let mut room = base_room.sanitized();
        let mut set_values = Vec::new();
        let (mut seed, mut material, mut size, mut gestures) =
            (Vec::new(), Vec::new(), Vec::new(), Vec::new());
        for (id, v) in &script.set {
            let t = ParamTarget::of(id).expect("validated");
            set_values.push((t, v.clone()));
            if apply_room(&mut room, t, v) {
                continue;
            }
            if let Some(c) = command_for(t, v) {
                match t {
                    ParamTarget::Seed => seed.push(c),
                    ParamTarget::Material => material.push(c),
                    ParamTarget::Size => size.push(c),
                    _ => gestures.push(c),
                }
            }
        }
        // Seed before size (a size change rebuilds the sheet with the current seed).
        let mut initial = Vec::new();
        initial.extend(seed);
        initial.extend(material);
        initial.extend(size);
        initial.push(Command::Room(room));
        initial.extend(gestures);
        let lanes: Vec<(Lane, ParamTarget)> = script
            .lanes
            .iter()
            .map(|l| (l.clone(), ParamTarget::of(&l.id).expect("validated")))
            .collect();
        // A lane whose first value equals the `[set]` value does not resend it.
        let last = lanes
            .iter()
            .map(|(l, _)| {
                script
                    .set
                    .iter()
                    .rev()
                    .find(|(k, _)| *k == l.id)
                    .map(|(_, v)| v.clone())
            })
            .collect();
        Ok(Self {
            frame_rate_hz,
            num_frames: (script.duration_s * frame_rate_hz).ceil() as u64,
            discrete: script.discrete_inputs(),
            next_discrete: 0,
            lanes,
            last,
            initial,
            set_values,
            room,
            frame: 0,
            buf: Vec::with_capacity(64),
        })
    }

    /// `base` with the script's `[set]` size, material, seed and room applied, and the
    /// runner's frame rate.
    pub fn config(&self, base: SimConfig) -> SimConfig {
        let mut c = base;
        c.frame_rate_hz = self.frame_rate_hz;
        c.room = self.room;
        for (t, v) in &self.set_values {
            match command_for(*t, v) {
                Some(Command::Size(s)) => c.size = s,
                Some(Command::Material(m)) => c.material = m,
                Some(Command::Seed(s)) => c.seed = s,
                _ => {}
            }
        }
        c
    }

    /// The `[set]` values as commands (seed, material, size, room, gestures), to apply before
    /// frame 0. Applying them to a sim created from [`Self::config`] only sets the gestures.
    pub fn initial_commands(&self) -> &[Command] {
        &self.initial
    }

    /// Number of frames the script lasts (`⌈duration × frame rate⌉`).
    pub fn num_frames(&self) -> u64 {
        self.num_frames
    }

    /// Index of the next frame.
    pub fn frame(&self) -> u64 {
        self.frame
    }

    /// Frame rate, Hz.
    pub fn frame_rate_hz(&self) -> f64 {
        self.frame_rate_hz
    }

    /// Appends the commands of the next frame to `out` and advances. Returns false (and adds
    /// nothing) once the script is over.
    pub fn next_frame(&mut self, out: &mut Vec<Command>) -> bool {
        if self.frame >= self.num_frames {
            return false;
        }
        let k = self.frame as f64;
        let t_end = (k + 1.0) / self.frame_rate_hz;
        let t = k / self.frame_rate_hz;
        while self.next_discrete < self.discrete.len()
            && self.discrete[self.next_discrete].0 < t_end
        {
            out.push(match &self.discrete[self.next_discrete].1 {
                DiscreteInput::Reset => Command::Reset,
                DiscreteInput::Grab { slot, velocity } => Command::Grab {
                    slot: *slot,
                    grip: *velocity,
                },
                DiscreteInput::Release { slot } => Command::Release { slot: *slot },
            });
            self.next_discrete += 1;
        }
        let mut room_changed = false;
        for (i, (lane, target)) in self.lanes.iter().enumerate() {
            let v = lane.value_at(t);
            if self.last[i].as_ref() == Some(&v) {
                continue;
            }
            if apply_room(&mut self.room, *target, &v) {
                room_changed = true;
            } else if let Some(c) = command_for(*target, &v) {
                out.push(c);
            }
            self.last[i] = Some(v);
        }
        if room_changed {
            out.push(Command::Room(self.room));
        }
        self.frame += 1;
        true
    }

    /// Applies the next frame's commands to `sim` and steps it. Returns false once the
    /// script is over (nothing applied or stepped).
    pub fn drive(&mut self, sim: &mut Sim, out: &mut FrameOutput) -> bool {
        let mut buf = std::mem::take(&mut self.buf);
        buf.clear();
        let more = self.next_frame(&mut buf);
        if more {
            for c in buf.drain(..) {
                sim.apply(c);
            }
            sim.step(out);
        }
        self.buf = buf;
        more
    }

    /// A sim set up for the script (config from `base` + `[set]`, initial commands applied).
    pub fn start(&self, base: SimConfig) -> Sim {
        let mut sim = Sim::new(self.config(base));
        for c in &self.initial {
            sim.apply(*c);
        }
        sim
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::control::GrabSlot;

    const S: &str = r#"
version = 1
duration_s = 0.05
[set]
size = "a6"
seed = 7
table_height_cm = 70
slide = 0.25
gain_db = -6
[[lane]]
id = "slide"
interp = "step"
points = [[0.0, 0.25], [0.02, 0.5]]
[[lane]]
id = "wall"
interp = "step"
points = [[0.0, false], [0.011, true]]
[[lane]]
id = "listener_az_deg"
points = [[0.0, 0.0], [0.05, 90.0]]
[[grab]]
slot = "front"
on_s = 0.004
off_s = 0.031
velocity = 0.5
[[reset]]
at_s = 0.004
"#;

    #[test]
    fn frames_follow_the_timing_rules() {
        let s = Script::parse(S).unwrap();
        let mut r = ScriptRunner::new(&s, 200.0, RoomConfig::default()).unwrap();
        assert_eq!(r.num_frames(), 10);
        let cfg = r.config(SimConfig::default());
        assert_eq!(cfg.size, SheetSize::A6);
        assert_eq!(cfg.seed, 7);
        assert_eq!(cfg.room.table_height_cm, 70.0);
        // [set]: seed, size, room, gesture (gain ignored).
        let init = r.initial_commands();
        assert_eq!(init[0], Command::Seed(7));
        assert_eq!(init[1], Command::Size(SheetSize::A6));
        assert!(matches!(init[2], Command::Room(room) if room.table_height_cm == 70.0));
        assert_eq!(init.len(), 4);
        let mut frames: Vec<Vec<Command>> = Vec::new();
        loop {
            let mut v = Vec::new();
            if !r.next_frame(&mut v) {
                break;
            }
            frames.push(v);
        }
        assert_eq!(frames.len(), 10);
        // Frame 0 = [0, 5 ms): reset and grab at 4 ms (reset first); the slide lane starts
        // at the [set] value, so it is not resent; the wall lane starts (false = no change of
        // the room, but it is the first value) → one Room command.
        assert_eq!(frames[0][0], Command::Reset);
        assert!(matches!(
            frames[0][1],
            Command::Grab {
                slot: GrabSlot::Front,
                ..
            }
        ));
        assert!(
            frames[0]
                .iter()
                .all(|c| !matches!(c, Command::Gesture { .. }))
        );
        // Frame 2 (t = 10 ms): the wall lane is still false at 10 ms; frame 3 (15 ms): true.
        assert!(
            frames[2]
                .iter()
                .all(|c| !matches!(c, Command::Room(r) if r.wall))
        );
        assert!(
            frames[3]
                .iter()
                .any(|c| matches!(c, Command::Room(r) if r.wall))
        );
        // Frame 4 (20 ms): slide steps to 0.5.
        assert!(frames[4].contains(&Command::Gesture {
            param: GestureParam::Slide,
            value: 0.5
        }));
        // Release at 31 ms → frame 6 ([30, 35) ms).
        assert!(frames[6].contains(&Command::Release {
            slot: GrabSlot::Front
        }));
        // Listener lane never produces commands.
        assert!(frames.iter().flatten().all(|c| !matches!(
            c,
            Command::Gesture {
                param: GestureParam::Twist,
                ..
            }
        )));
    }

    #[test]
    fn unknown_ids_and_bad_values_are_errors() {
        let bad_id = Script::parse("version = 1\n[set]\nwobble = 1\n").unwrap();
        let e = validate(&bad_id).unwrap_err();
        assert!(
            e.to_string().contains("wobble") && e.to_string().contains("[set]"),
            "{e}"
        );
        let bad_lane =
            Script::parse("version = 1\n[[lane]]\nid = \"crumple_amount\"\npoints = [[0, 1]]\n")
                .unwrap();
        assert!(matches!(
            validate(&bad_lane),
            Err(RunnerError::UnknownParam { .. })
        ));
        let bad_size = Script::parse("version = 1\n[set]\nsize = \"a3\"\n").unwrap();
        assert!(validate(&bad_size).unwrap_err().to_string().contains("a4"));
        let bad_seed = Script::parse("version = 1\n[set]\nseed = 1.5\n").unwrap();
        assert!(validate(&bad_seed).is_err());
        let bad_table = Script::parse("version = 1\n[set]\ntable = 1\n").unwrap();
        assert!(validate(&bad_table).is_err());
        let ok =
            Script::parse("version = 1\n[set]\nmix_tear_db = -3\nlistener_dist_m = 2\n").unwrap();
        validate(&ok).unwrap();
    }
}
