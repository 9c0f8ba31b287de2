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
//! | `t1_two_hand_tear` | T1: two hands tear a sheet on the table in two (M §3–4, T Fig. 3.9) |
//! | `t2_steered_tear` | T2: the hands' balance steers the tear left and right (T Fig. 3.10) |
//! | `t3_pull_equal` | T3: an equal pull tears straight along the mediator (T Fig. 3.28) |
//! | `t4_pull_unequal` | T4: an unequal pull tears along a hyperbola (T Fig. 3.29) |

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
    "t1_two_hand_tear",
    "t2_steered_tear",
    "t3_pull_equal",
    "t4_pull_unequal",
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
    /// The seed after `@` is not a number.
    #[error("scenario {0}: seed {1:?} is not a number")]
    Seed(String, String),
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

/// The parsed script of `NAME` or `NAME@SEED`: with a seed, the script's own `seed` setting is
/// replaced (the probes replay one scene with several seeds).
pub fn get_seeded(arg: &str) -> Result<Script, ScenarioError> {
    let Some((name, seed)) = arg.split_once('@') else {
        return get(arg);
    };
    let seed = seed
        .parse::<f64>()
        .ok()
        .filter(|s| s.is_finite())
        .ok_or_else(|| ScenarioError::Seed(name.to_string(), seed.to_string()))?;
    let mut script = get(name)?;
    script.set.retain(|(k, _)| k != "seed");
    script
        .set
        .push(("seed".into(), crate::script::ScriptValue::Number(seed)));
    Ok(script)
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
    fn a_seed_after_the_name_replaces_the_scripts_seed() {
        let seeded = get_seeded("c5_full_crumple@7").unwrap();
        let seeds: Vec<_> = seeded.set.iter().filter(|(k, _)| k == "seed").collect();
        assert_eq!(seeds.len(), 1);
        assert!(matches!(seeds[0].1, crate::script::ScriptValue::Number(s) if s == 7.0));
        assert_eq!(
            get_seeded("c5_full_crumple").unwrap(),
            get("c5_full_crumple").unwrap()
        );
        assert!(matches!(
            get_seeded("c5_full_crumple@x"),
            Err(ScenarioError::Seed(..))
        ));
        assert!(matches!(
            get_seeded("nope@1"),
            Err(ScenarioError::Unknown(_))
        ));
    }

    #[test]
    fn every_scenario_parses_and_validates() {
        assert_eq!(names().count(), 16);
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
