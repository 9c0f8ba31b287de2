//! Proof that the audio thread's work does not allocate: the gesture mapping, the engine's
//! parameter diffing and MIDI handling, and the render call, at block sizes 1 to 16384, with every
//! kind of MIDI message and automation — counted by a global allocator that records allocations
//! made on the current thread while a check is running.
//!
//! In real-time (threaded) mode nothing on the audio thread allocates, including resets and size
//! changes (those rebuild the sheet on the worker thread). In offline lockstep mode the sheet is
//! stepped on the audio thread; its steady-state step is allocation-free too (a sheet rebuild or
//! the sheet's publication for the saved project may allocate there, which is permitted offline
//! and excluded from this check by not sending resets/size changes and keeping the run short).
//!
//! The counting uses nice-plug's own checker (`assert_process_allocs`), in counting mode.

use std::sync::Arc;

use papier::engine::SheetStore;
use papier::engine::{Engine, Meters, ParamValues, SimMode};
use papier::gesture_map::{self, MidiInput};
use sim_core::{GestureParam, Sim};
use sounddb::SoundDb;

/// Runs `f` under nice-plug's own allocation checker (the global allocator that
/// `assert_process_allocs` installs in debug builds, here in counting mode) and returns how many
/// allocations and deallocations it made on this thread.
fn count_allocs(f: impl FnOnce()) -> u32 {
    // The allocation checker is only active in debug builds (run these tests without
    // --release); `the_checker_counts_allocations` fails otherwise.
    nice_assert_no_alloc::reset_violation_count();
    nice_assert_no_alloc::assert_no_alloc(f);
    nice_assert_no_alloc::violation_count()
}

#[test]
fn the_checker_counts_allocations() {
    // The test would prove nothing if the checker were not installed.
    let n = count_allocs(|| {
        std::hint::black_box(vec![1u8; 64]);
    });
    assert!(
        n >= 1,
        "an allocation inside assert_no_alloc was not counted"
    );
}

fn engine(mode: SimMode, sample_rate: f64) -> Engine {
    let params = ParamValues::default();
    let mut sim = Sim::new(papier::engine::sim_config(&params));
    papier::engine::sync_fresh_sim(&mut sim, &params);
    Engine::new(
        mode,
        sample_rate,
        sim,
        &params,
        Arc::new(SoundDb::empty()),
        Arc::new(SheetStore::default()),
        0,
        Arc::new(Meters::default()),
        Arc::new(papier::engine::ViewShared::default()),
        // What the plugin hands the engine: the allocation checker's permit.
        |f| nice_assert_no_alloc::permit_alloc(f),
    )
    .map(|mut e| {
        // The factory phrases, so that the notes from 60 play them (swapped in off the count).
        e.swap_phrases(Arc::new(papier::phrase::PhraseBank::factory()));
        e
    })
    .expect("engine")
}

/// Every MIDI message the map knows, plus unmapped ones, plus every factory phrase's note.
fn all_midi() -> Vec<MidiInput> {
    let mut v = Vec::new();
    for key in [
        36u8, 48, 50, 52, 53, 55, 59, 60, 61, 62, 63, 64, 65, 70, 75, 81, 90,
    ] {
        v.push(MidiInput::NoteOn { key, velocity: 0.7 });
        v.push(MidiInput::NoteOff { key });
    }
    for cc in [
        1u8, 7, 20, 21, 22, 23, 24, 25, 26, 27, 28, 29, 30, 74, 120, 121, 123,
    ] {
        v.push(MidiInput::Cc { cc, value: 0.6 });
    }
    v.push(MidiInput::AllNotesOff);
    v
}

#[test]
fn gesture_mapping_does_not_allocate() {
    let inputs = all_midi();
    let n = count_allocs(|| {
        for i in &inputs {
            std::hint::black_box(gesture_map::map(*i));
        }
    });
    assert_eq!(n, 0);
}

fn drive(
    engine: &mut Engine,
    block: usize,
    blocks: usize,
    midi: &[MidiInput],
    allow_rebuild: bool,
) -> u32 {
    let mut left = vec![0.0f32; block];
    let mut right = vec![0.0f32; block];
    let mut params = ParamValues::default();
    count_allocs(|| {
        for b in 0..blocks {
            // Automation on every gesture and the room, listener and mix.
            for g in GestureParam::ALL {
                let (lo, hi) = g.range();
                params.gestures[g.index()] = lo + (hi - lo) * ((b % 7) as f32 / 7.0);
            }
            params.room.table_height_cm = 70.0 + (b % 3) as f32;
            params.room.wall = b % 2 == 0;
            params.listener_az_deg = (b % 360) as f32 - 180.0;
            params.gain_db = -((b % 12) as f32);
            if allow_rebuild {
                params.size = sim_core::SheetSize::ALL[b % 4];
            }
            engine.begin_block(&params);
            for (i, m) in midi.iter().enumerate() {
                if !allow_rebuild && matches!(m, MidiInput::NoteOn { key: 36, .. }) {
                    continue;
                }
                engine.midi(*m, (i % block) as u32);
            }
            engine.render(&mut left, &mut right);
        }
    })
}

#[test]
fn real_time_engine_does_not_allocate_on_the_audio_thread() {
    let midi = all_midi();
    for (sr, block, blocks) in [
        (44_100.0, 1usize, 3000usize),
        (48_000.0, 64, 200),
        (96_000.0, 16_384, 4),
    ] {
        let mut e = engine(SimMode::Threaded, sr);
        let n = drive(&mut e, block, blocks, &midi, true);
        assert_eq!(n, 0, "{n} allocations at {sr} Hz, block {block}");
        drop(e);
    }
}

#[test]
fn offline_engine_steady_state_does_not_allocate() {
    let midi = all_midi();
    for (sr, block, blocks) in [
        (44_100.0, 1usize, 2000usize),
        (48_000.0, 256, 20),
        (8_000.0, 16_384, 1),
    ] {
        let mut e = engine(SimMode::Lockstep, sr);
        let n = drive(&mut e, block, blocks, &midi, false);
        assert_eq!(n, 0, "{n} allocations at {sr} Hz, block {block}");
    }
}
