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
