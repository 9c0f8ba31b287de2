//! Damaged input files for `papier-render`: scripts, MIDI files and frame logs edited at random
//! (tests/input_mutation/mod.rs) and played through the offline renderer at random rates and
//! block sizes. Every case must be refused with a one-line error or render a WAV of finite
//! samples within ±1; none may panic. The hand-written bad inputs of `papier_render_cli.rs`
//! cover each error message; this covers what nobody thought to write. The same run, longer:
//! `cargo run --release -p papier-tests --example fuzz_inputs -- CASES SEED`.

mod input_mutation;

use input_mutation::{Kind, Tally, bases, mutated, run_case};
use papier_tests::paths;
use rand::SeedableRng;

#[test]
fn damaged_scripts_midi_files_and_frame_logs_never_panic() {
    let dir = paths::scratch("bad_input_files");
    // Keep one prepared embedded database per rate alive for the whole run (default_db shares
    // it), so each case does not prepare it again.
    let _dbs: Vec<_> = input_mutation::RATES_HZ
        .iter()
        .map(|&r| papier::render::default_db(f64::from(r)))
        .collect();
    // A crumple, a slide, a two-hand tear and a pull (the tear and pull lanes).
    let bases = bases(
        &dir,
        &[
            "c1_first_sharp_feature",
            "s6_slide_on_table",
            "t1_two_hand_tear",
            "t3_pull_equal",
        ],
    );
    let mut rng = rand_pcg::Pcg32::seed_from_u64(11);
    let mut per_kind = [Tally::default(); 3];
    for case in 0..160 {
        let base = &bases[case % bases.len()];
        let bytes = mutated(base, &mut rng);
        let t = run_case(base.kind, &bytes, &dir, &mut rng).unwrap_or_else(|e| {
            let keep = dir.join(format!("failed_{case}.bin"));
            std::fs::write(&keep, &bytes).unwrap();
            panic!(
                "case {case} ({}): {e}; input kept in {}",
                base.scene,
                keep.display()
            )
        });
        let k = base.kind.index();
        per_kind[k].add(&t);
    }
    // The cases reach both outcomes for every kind of file: edits that are refused and edits
    // that still play (else the test would only exercise the first check of each parser).
    for (t, kind) in per_kind.iter().zip(Kind::ALL.map(|(_, name)| name)) {
        eprintln!("{kind}: {t:?}");
        assert!(t.refused > 0, "{kind}: no edit was refused: {t:?}");
        assert!(t.played > 0, "{kind}: no edited input played: {t:?}");
    }
}
