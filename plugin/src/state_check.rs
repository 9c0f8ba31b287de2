//! # Checking a saved state before it is loaded
//!
//! A host hands the plugin a saved project's state; nice-plug parses its JSON and then calls
//! [`nice_plug::prelude::Plugin::filter_state`], which lands here before any value is applied.
//! The framework itself skips unknown ids and mistyped values silently in release builds, so
//! this check does it first and says why:
//!
//! - **state layout version** (`state_version`, [`crate::params::STATE_VERSION`]): a missing or
//!   unreadable one is reported and layout 1 is assumed; a newer one (a project saved by a later
//!   Papier) is reported and only the parameters and fields this version knows are loaded;
//! - **every parameter** is validated exactly like `papier-render --set` and scripts
//!   ([`crate::engine::ParamValues::set`]): an unknown id, a value of the wrong kind, a
//!   non-finite or out-of-range number or an unknown choice is **removed** from the state, so
//!   that parameter keeps its current value (the default in a fresh instance) instead of being
//!   clamped or guessed;
//! - **unknown persisted fields** are reported (nice-plug ignores them).
//!
//! The persisted sheet and the sound database folder are checked where they are parsed
//! ([`crate::state`], [`crate::db_loader`]). A state that is not JSON at all never reaches this
//! point: nice-plug rejects it and the host is told the load failed (its log line exists only
//! in debug builds of the framework; the README lists this).

use nice_plug::plugin::{ParamValue, PluginState};
use sim_core::script::ScriptValue;

use crate::engine::ParamValues;
use crate::params::STATE_VERSION;

/// Persisted fields this version reads.
pub const KNOWN_FIELDS: [&str; 4] = ["state_version", "sheet", "db_path", "editor_size"];

/// Checks and cleans `state` in place; returns one line per problem found (empty when the
/// state is clean).
pub fn check(state: &mut PluginState) -> Vec<String> {
    let mut problems = Vec::new();
    match state.fields.get("state_version") {
        None => problems.push(format!(
            "saved state has no state_version; reading it as layout {STATE_VERSION}"
        )),
        Some(text) => match text.trim().parse::<u32>() {
            Ok(v) if v > STATE_VERSION => problems.push(format!(
                "saved state has layout {v}, newer than this Papier's {STATE_VERSION} (saved by \
                 a later version?); loading only the parameters and fields this version knows"
            )),
            Ok(_) => {}
            Err(_) => problems.push(format!(
                "saved state_version {text:?} is not a number; reading it as layout \
                 {STATE_VERSION}"
            )),
        },
    }
    let mut probe = ParamValues::default();
    state.params.retain(|id, value| {
        let script_value = match value {
            ParamValue::F32(x) => ScriptValue::Number(f64::from(*x)),
            ParamValue::I32(i) => ScriptValue::Number(f64::from(*i)),
            ParamValue::Bool(b) => ScriptValue::Bool(*b),
            ParamValue::String(s) => ScriptValue::Text(s.clone()),
        };
        match probe.set(id, &script_value) {
            Ok(()) => true,
            Err(e) => {
                problems.push(format!(
                    "saved state: {e}; that parameter keeps its current value"
                ));
                false
            }
        }
    });
    for key in state.fields.keys() {
        if !KNOWN_FIELDS.contains(&key.as_str()) {
            problems.push(format!(
                "saved state has an unknown field `{key}`; it is ignored"
            ));
        }
    }
    problems
}

#[cfg(test)]
mod tests {
    use std::collections::BTreeMap;

    use super::*;

    fn clean_state() -> PluginState {
        let mut params = BTreeMap::new();
        params.insert("crumple".to_string(), ParamValue::F32(0.4));
        params.insert("seed".to_string(), ParamValue::I32(7));
        params.insert("table".to_string(), ParamValue::Bool(true));
        params.insert("size".to_string(), ParamValue::String("a6".into()));
        params.insert("gain_db".to_string(), ParamValue::F32(-6.0));
        let mut fields = BTreeMap::new();
        fields.insert("state_version".to_string(), STATE_VERSION.to_string());
        fields.insert("db_path".to_string(), "null".to_string());
        PluginState {
            version: "0.1.0".into(),
            params,
            fields,
        }
    }

    #[test]
    fn a_clean_state_passes_unchanged() {
        let mut s = clean_state();
        let before: Vec<String> = s.params.keys().cloned().collect();
        assert!(check(&mut s).is_empty());
        assert!(s.params.keys().eq(before.iter()));
    }

    /// Every value a parameter can hold (both ends of its range, its default) passes the check
    /// in the form nice-plug saves it, so a valid project never loses a value.
    #[test]
    fn every_value_a_parameter_can_hold_passes() {
        use nice_plug::prelude::{ParamPtr, Params};
        let params = crate::params::PapierParams::default();
        let mut n = 0;
        for (id, ptr, _) in params.param_map() {
            for normalized in [0.0, 1.0, f32::NAN] {
                // SAFETY: `ptr` points into `params`, alive for the whole loop.
                let normalized = if normalized.is_nan() {
                    unsafe { ptr.default_normalized_value() }
                } else {
                    normalized
                };
                let plain = unsafe { ptr.preview_plain(normalized) };
                let value = match ptr {
                    ParamPtr::FloatParam(_) => ParamValue::F32(plain),
                    ParamPtr::IntParam(_) => ParamValue::I32(plain.round() as i32),
                    ParamPtr::BoolParam(_) => ParamValue::Bool(plain > 0.5),
                    ParamPtr::EnumParam(_) => {
                        let text = unsafe { ptr.normalized_value_to_string(normalized, false) };
                        let id = ["a4", "a5", "a6", "sq10", "printer", "tracing", "banknote"]
                            .into_iter()
                            .zip([
                                "A4",
                                "A5",
                                "A6",
                                "10 cm square",
                                "Printer paper",
                                "Tracing paper",
                                "Bank note",
                            ])
                            .find(|(_, name)| *name == text)
                            .map(|(id, _)| id)
                            .unwrap_or_else(|| panic!("enum text {text:?}"));
                        ParamValue::String(id.to_string())
                    }
                };
                let mut one = clean_state();
                one.params.clear();
                one.params.insert(id.clone(), value);
                let problems = check(&mut one);
                assert!(problems.is_empty(), "{id} at {normalized}: {problems:?}");
                n += 1;
            }
        }
        assert_eq!(n, 3 * crate::engine::param_values::PARAM_IDS.len());
    }

    #[test]
    fn bad_parameters_are_removed_with_a_reason_each() {
        let mut s = clean_state();
        let bad = [
            ("frobnicate", ParamValue::F32(0.5)),
            ("crumple", ParamValue::F32(f32::NAN)),
            ("slide", ParamValue::F32(7.0)),
            ("size", ParamValue::String("a0".into())),
            ("material", ParamValue::Bool(true)),
            ("table", ParamValue::String("maybe".into())),
            ("seed", ParamValue::I32(-3)),
        ];
        for (id, v) in bad.iter().cloned() {
            s.params.insert(id.to_string(), v);
        }
        let problems = check(&mut s);
        assert_eq!(problems.len(), bad.len(), "{problems:#?}");
        for (id, _) in &bad {
            assert!(!s.params.contains_key(*id), "{id} kept");
            assert!(
                problems.iter().any(|p| p.contains(&format!("`{id}`"))),
                "no reason for {id}: {problems:#?}"
            );
        }
        assert!(problems.iter().all(|p| !p.contains('\n')));
        assert!(s.params.contains_key("gain_db"), "good values stay");
    }

    #[test]
    fn version_problems_and_unknown_fields_are_reported() {
        let mut s = clean_state();
        s.fields
            .insert("state_version".into(), (STATE_VERSION + 1).to_string());
        s.fields.insert("future_thing".into(), "{}".into());
        let p = check(&mut s);
        assert_eq!(p.len(), 2, "{p:#?}");
        assert!(p[0].contains("newer"));
        assert!(p[1].contains("future_thing"));
        assert_eq!(s.params.len(), clean_state().params.len());

        let mut s = clean_state();
        s.fields.remove("state_version");
        assert!(check(&mut s)[0].contains("no state_version"));
        let mut s = clean_state();
        s.fields.insert("state_version".into(), "\"x\"".into());
        assert!(check(&mut s)[0].contains("not a number"));
    }
}
