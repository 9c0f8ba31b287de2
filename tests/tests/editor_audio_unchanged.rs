//! The editor does not change a single sample: in the host's offline mode the engine steps the
//! sheet itself and its output is a pure function of the input, so the audio of a run during
//! which the editor is opened and closed again and again (and copies the sheet for its view
//! while open) must equal, bit for bit, a render of the same gesture without any editor.
//!
//! The run: a real CLAP host (`papier_tests::clap` with the GUI extension) on a private Xvfb;
//! a host audio thread ([`papier_tests::live`]) calls `process()` at real-time pace with a
//! repeating gesture and records the output, while the main thread opens the editor in a host
//! window, lets it draw for a while, and closes it, [`CYCLES`] times. The reference: a fresh
//! instance renders as many samples of the same gesture, offline, without a window.
//!
//! A dropout, a click, a stale or doubled block caused by the window would all show as a
//! difference in the audio; the view copy disturbing the simulation would also show in the
//! sheet itself, which the saved state carries: both runs must end with identical states (and
//! the sheet must have moved, so that the comparison says something even while the engine's
//! sound analysis is not wired and the output is silent).

use std::sync::atomic::Ordering;
use std::time::{Duration, Instant};

use papier_tests::clap::{Bundle, serial};
use papier_tests::clap_gui::{ParentWindow, close_editor, open_editor};
use papier_tests::live::{self, Gesture, LIVE_BLOCK, Live, LiveMode, StopOnDrop};
use papier_tests::paths;
use papier_tests::xvfb::Xvfb;

const SAMPLE_RATE: f64 = 48_000.0;
/// Editor windows opened and closed during the recorded run.
const CYCLES: usize = 12;
/// Blocks the audio thread gets through while each window is open (~0.2 s of audio, so the
/// editor draws several frames and the engine copies the sheet for it).
const BLOCKS_WHILE_OPEN: u64 = 40;
/// Blocks between two windows.
const BLOCKS_WHILE_CLOSED: u64 = 10;
/// How long to wait for the audio thread: generous, for loaded machines.
const AUDIO_PATIENCE: Duration = Duration::from_secs(120);

#[test]
fn audio_with_the_editor_opening_and_closing_equals_audio_without_it() {
    let _serial = serial();
    let t_start = Instant::now();
    let x = Xvfb::start(1400, 1000).expect("Xvfb");
    // SAFETY: set before the plugin (baseview) is loaded and before this test starts threads;
    // this binary has no other test that reads the environment concurrently.
    unsafe { std::env::set_var("DISPLAY", x.display()) };
    let bundle = Bundle::load(&paths::clap_bundle()).expect("load Papier.clap");
    let gesture = Gesture::shake_and_crumple();

    // 1. The run with the editor.
    let mut inst = bundle.instance().expect("instance");
    inst.set_offline(true).expect("offline mode");
    inst.activate(SAMPLE_RATE, LIVE_BLOCK as u32)
        .expect("activate");
    let processor = inst.take_processor().expect("processor");
    let parent = ParentWindow::new(&x.display(), 800, 600).expect("host window");
    let live = Live::default();
    let (stopped, run) = std::thread::scope(|s| {
        let audio = s.spawn(|| {
            live::run(
                processor,
                SAMPLE_RATE,
                &gesture,
                LiveMode::OfflineRecorded,
                &live,
            )
        });
        let stopper = StopOnDrop(&live);
        for i in 0..CYCLES {
            let before = live.blocks.load(Ordering::Acquire);
            assert!(
                live.wait_for_blocks(before, BLOCKS_WHILE_CLOSED, AUDIO_PATIENCE),
                "cycle {i}: the audio thread stalled"
            );
            open_editor(&mut inst, &parent).expect("open the editor");
            let opened = live.blocks.load(Ordering::Acquire);
            let t0 = Instant::now();
            while live.blocks.load(Ordering::Acquire) < opened + BLOCKS_WHILE_OPEN {
                assert!(
                    t0.elapsed() < AUDIO_PATIENCE,
                    "cycle {i}: the audio thread stalled while the editor was open"
                );
                inst.idle();
                std::thread::sleep(Duration::from_millis(5));
            }
            close_editor(&mut inst).expect("close the editor");
            inst.idle();
        }
        let before = live.blocks.load(Ordering::Acquire);
        assert!(live.wait_for_blocks(before, BLOCKS_WHILE_CLOSED, AUDIO_PATIENCE));
        drop(stopper);
        audio.join().expect("audio thread")
    });
    inst.put_processor(stopped);
    inst.deactivate();
    let run_state = inst.save_state().expect("save the state after the run");
    drop(inst);
    let (left, right) = run.output.expect("recorded output");
    let total = left.len() as u64;
    assert_eq!(run.errors, 0, "process() failed");
    assert_eq!(run.non_finite, 0, "non-finite samples");
    assert!(
        run.blocks >= CYCLES as u64 * (BLOCKS_WHILE_OPEN + BLOCKS_WHILE_CLOSED),
        "{} blocks",
        run.blocks
    );

    // 2. The reference, without any editor.
    let mut reference = bundle.instance().expect("instance");
    reference.set_offline(true).expect("offline mode");
    let (ref_left, ref_right) = reference
        .render(
            SAMPLE_RATE,
            LIVE_BLOCK as u32,
            &[],
            total,
            &gesture.unrolled(total),
        )
        .expect("reference render");
    let reference_state = reference.save_state().expect("save the reference state");
    let fresh_state = bundle
        .instance()
        .expect("instance")
        .save_state()
        .expect("save a fresh state");

    let first_difference = |a: &[f32], b: &[f32]| {
        a.iter()
            .zip(b)
            .position(|(x, y)| x.to_bits() != y.to_bits())
    };
    eprintln!(
        "editor during offline audio: {CYCLES} windows over {} blocks ({:.1} s of audio), peak \
         {:.4}; {:.1} s",
        run.blocks,
        total as f64 / SAMPLE_RATE,
        run.peak,
        t_start.elapsed().as_secs_f64()
    );
    assert_ne!(
        reference_state, fresh_state,
        "the gesture did not move the sheet (the comparison would say nothing)"
    );
    assert!(
        run_state == reference_state,
        "the sheet after the run with the editor differs from the sheet without it"
    );
    assert_eq!(ref_left.len(), left.len());
    assert_eq!(
        first_difference(&left, &ref_left),
        None,
        "left channel differs from the render without the editor"
    );
    assert_eq!(
        first_difference(&right, &ref_right),
        None,
        "right channel differs from the render without the editor"
    );
}
