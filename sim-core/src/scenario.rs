//! # The seed scenario library
//!
//! The scenarios the seeds demonstrate (digest-tearing §4.2), as scripts in the format of
//! [`crate::script`], stored in `sim-core/scenarios/*.toml` and embedded in the binary. Tests,
//! benches, the benchmark report and `papier-render --scene NAME` all use the same files.
//!
//! | name | seed scenario |
//! |---|---|
//! | `c1_first_sharp_feature` | C1: two sides 10 % closer, then an orthogonal constraint (T 1132, Fig. 2.20) |
//! | `c2_moebius_twist` | C2: Möbius-like twist of a strip (T 1137, Fig. 2.21 top) |
//! | `c3_unload_after_singularity` | C3: load, then release: the sheet straightens (T 1143, Fig. 2.21 bottom) |
//! | `c4_double_bend` | C4: cylinder, then an orthogonal bend (T 1184, T 1209, TOG Fig. 1) |
//! | `c5_full_crumple` | C5: full crumpling (T 1204, Fig. 2.26) |
//! | `c6_four_corner_flip` | C6: four corners held, one lifted: the edge-flip case (T 818, Fig. 2.5) |
//! | `s1_slide_release_pinch` | S1: the 3.3 s curving sheet (S 38, T Fig. 4.4) |
//! | `s2_shake` | S2: shaking (T Fig. 4.21) |
//! | `s3_wiggle_near_wall` | S3: wiggle near a wall (T Fig. 4.19) |
//! | `s4_crumple` | S4: crumpling printer, tracing and bank-note paper (T Fig. 4.22) |
//! | `s5_fold_and_revert` | S5: fold and revert, a flap (T Fig. 4.17) |
//! | `s6_slide_on_table` | S6: sliding on a table (T Fig. 4.16) |

use thiserror::Error;

use crate::script::{Script, ScriptError};

macro_rules! scenarios {
    ($($name:literal),* $(,)?) => {
        /// Every scenario as (name, TOML text), in library order.
        const SCENARIOS: &[(&str, &str)] = &[
            $(($name, include_str!(concat!("../scenarios/", $name, ".toml")))),*
        ];
    };
}

scenarios!(
    "c1_first_sharp_feature",
    "c2_moebius_twist",
    "c3_unload_after_singularity",
    "c4_double_bend",
    "c5_full_crumple",
    "c6_four_corner_flip",
    "s1_slide_release_pinch",
    "s2_shake",
    "s3_wiggle_near_wall",
    "s4_crumple",
    "s5_fold_and_revert",
    "s6_slide_on_table",
);

/// Why a scenario could not be loaded.
#[derive(Debug, Error)]
pub enum ScenarioError {
    /// No scenario has this name.
    #[error("unknown scenario {0:?} (known: {known})", known = names().collect::<Vec<_>>().join(", "))]
    Unknown(String),
    /// The embedded file does not parse (a build defect, caught by the tests).
    #[error("scenario {0}: {1}")]
    Parse(String, ScriptError),
}

/// Names of all scenarios, in library order.
pub fn names() -> impl Iterator<Item = &'static str> {
    SCENARIOS.iter().map(|(n, _)| *n)
}

/// The TOML text of a scenario.
pub fn text(name: &str) -> Option<&'static str> {
    SCENARIOS.iter().find(|(n, _)| *n == name).map(|(_, t)| *t)
}

/// The parsed script of a scenario.
pub fn get(name: &str) -> Result<Script, ScenarioError> {
    let t = text(name).ok_or_else(|| ScenarioError::Unknown(name.to_string()))?;
    Script::parse(t).map_err(|e| ScenarioError::Parse(name.to_string(), e))
}

/// The first comment line of a scenario file (its title), without the `# `.
pub fn title(name: &str) -> Option<&'static str> {
    text(name)?.lines().next()?.strip_prefix("# ")
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::script_runner::{ScriptRunner, validate};

    #[test]
    fn every_scenario_parses_and_validates() {
        assert_eq!(names().count(), 12);
        for name in names() {
            let s = get(name).unwrap_or_else(|e| panic!("{e}"));
            validate(&s).unwrap_or_else(|e| panic!("{name}: {e}"));
            assert!(s.duration_s > 0.5 && s.duration_s <= 10.0, "{name}");
            assert!(
                title(name).is_some_and(|t| t.len() > 10),
                "{name} has a title line"
            );
            let r = ScriptRunner::new(&s, 200.0, crate::room::RoomConfig::default()).unwrap();
            assert!(r.num_frames() >= 100);
        }
        assert!(matches!(get("nope"), Err(ScenarioError::Unknown(_))));
        let s1 = get("s1_slide_release_pinch").unwrap();
        assert!((s1.duration_s - 3.3).abs() < 1e-12, "S1 lasts 3.3 s");
    }
}
