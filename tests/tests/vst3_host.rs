//! The bundled `Papier.vst3` in a real third-party VST3 host: pedalboard (PyPI), which hosts
//! VST3 through JUCE as many DAWs do. It loads the plugin, checks its parameters, renders MIDI
//! at three sample rates and block sizes, saves the state, restores it into a fresh instance,
//! checks the re-save is byte-identical, and renders again. The Python side is
//! `tests/vst3/pedalboard_check.py`; the interpreter is the virtual environment that the README's
//! test command (`cargo xtask test`) creates in `target/venv`.

use std::process::Command;

use papier_tests::paths;

#[test]
fn papier_vst3_plays_and_restores_state_in_pedalboard() {
    let python = paths::target_dir().join("venv").join("bin").join("python");
    assert!(
        python.exists(),
        "{} is missing: run `cargo xtask test` (it creates the venv with pedalboard)",
        python.display()
    );
    let script = paths::workspace_root()
        .join("tests")
        .join("vst3")
        .join("pedalboard_check.py");
    let out_dir = paths::scratch("vst3_pedalboard");
    let out = Command::new(&python)
        .arg(&script)
        .arg(paths::vst3_bundle())
        .arg(&out_dir)
        .output()
        .expect("run pedalboard");
    let stdout = String::from_utf8_lossy(&out.stdout);
    print!("{stdout}");
    eprint!("{}", String::from_utf8_lossy(&out.stderr));
    assert!(out.status.success(), "pedalboard check failed");
    assert!(stdout.contains("RESULT: PASS"));
}

/// Renders, in pedalboard, each on a fresh instance: no MIDI; grabs (notes) alone; the same
/// grabs with gesture CCs (lift, shake, crumple). Prints one JSON line of peaks.
const MIDI_EFFECT_SCRIPT: &str = r#"
import json, sys
import numpy as np
from mido import Message
from pedalboard import load_plugin

path = sys.argv[1]
sr = 48000
notes = [
    Message("note_on", note=50, velocity=100, time=0.05),
    Message("note_on", note=48, velocity=90, time=0.8),
    Message("note_off", note=50, velocity=0, time=1.4),
    Message("note_off", note=48, velocity=0, time=1.6),
]
ccs = [
    Message("control_change", control=22, value=110, time=0.2),
    Message("control_change", control=24, value=100, time=0.4),
    Message("control_change", control=1, value=90, time=0.6),
    Message("control_change", control=1, value=127, time=1.0),
    Message("control_change", control=23, value=10, time=1.2),
]

def render(msgs):
    # pedalboard waits initialization_timeout for non-silent output; an idle instrument is silent.
    p = load_plugin(path, initialization_timeout=0.1)
    out = p(sorted(msgs, key=lambda m: m.time), duration=2.0, sample_rate=sr,
            num_channels=2, buffer_size=512, reset=True)
    assert out.shape == (2, 2 * sr), out.shape
    assert np.all(np.isfinite(out))
    return out

peak = lambda x: float(np.max(np.abs(x)))
idle = render([])
grabs = render(notes)
gestures = render(notes + ccs)
print(json.dumps({
    "idle_peak": peak(idle),
    "grabs_peak": peak(grabs),
    "gestures_peak": peak(gestures),
    "gestures_vs_idle": peak(gestures - idle),
}))
"#;

/// MIDI into the VST3 build in a third-party host changes what it plays. Detects notes and CCs
/// that the VST3 wrapper drops or the plugin ignores: grabs with gesture CCs must be audible and
/// at least ten times louder than the render without MIDI, and than the same grabs without the
/// CCs (a held, unmoved sheet is quiet: measured silent, against 0.83 with the CCs). pedalboard
/// runs the plugin in real-time mode, where the sheet is simulated on its own thread and two
/// renders of the same MIDI differ (measured: by up to 1.1), so the test compares levels, not
/// samples.
#[test]
fn papier_vst3_midi_notes_and_ccs_change_the_output_in_pedalboard() {
    let python = paths::target_dir().join("venv").join("bin").join("python");
    assert!(
        python.exists(),
        "{} is missing: run `cargo xtask test` (it creates the venv with pedalboard)",
        python.display()
    );
    let out = Command::new(&python)
        .arg("-c")
        .arg(MIDI_EFFECT_SCRIPT)
        .arg(paths::vst3_bundle())
        .output()
        .expect("run pedalboard");
    let stdout = String::from_utf8_lossy(&out.stdout);
    print!("{stdout}");
    eprint!("{}", String::from_utf8_lossy(&out.stderr));
    assert!(out.status.success(), "pedalboard render failed");
    let line = stdout
        .lines()
        .rev()
        .find(|l| l.starts_with('{'))
        .expect("the script prints its measurements");
    let m: serde_json::Value = serde_json::from_str(line).unwrap();
    let get = |k: &str| m[k].as_f64().unwrap_or_else(|| panic!("no {k} in {m}"));
    let (idle, grabs, gestures) = (get("idle_peak"), get("grabs_peak"), get("gestures_peak"));
    assert!(
        gestures >= 1e-3,
        "grabs and gesture CCs are (nearly) silent: peak {gestures:e}"
    );
    assert!(
        gestures >= 10.0 * idle && get("gestures_vs_idle") >= 1e-3,
        "MIDI barely changes the output: peak {gestures:e} with MIDI, {idle:e} without"
    );
    assert!(
        gestures >= 10.0 * grabs,
        "the gesture CCs barely change the output: peak {gestures:e} with them, {grabs:e} \
         with the same notes alone"
    );
}
