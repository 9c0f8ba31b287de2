//! Phrases (issue 54): takes played from MIDI notes through the engine, in lockstep at 48 kHz,
//! exactly as the host's offline mode and `papier-render --midi` play them.
//!
//! - every factory phrase plays from its note and moves the sheet;
//! - velocity changes the crumple events per second and the level, monotonically;
//! - two hits of one note differ, two renders of one performance are bit-identical at any
//!   block size;
//! - a reset or CC 121 stops a phrase; a user's phrase on a factory note replaces it.

use std::sync::Arc;
use std::sync::atomic::Ordering;

use papier::engine::{Engine, Meters, ParamValues, SheetStore, SimMode};
use papier::gesture_map::MidiInput;
use papier::phrase::PhraseBank;
use papier::phrase::player::{SLOWEST_SPEED, speed_for_velocity};
use sim_core::Sim;

const RATE: f64 = 48_000.0;

/// A MIDI message at a time.
type Timed = (f64, MidiInput);

fn note_on(t: f64, key: u8, velocity_7bit: u8) -> Timed {
    (
        t,
        MidiInput::NoteOn {
            key,
            velocity: f32::from(velocity_7bit) / 127.0,
        },
    )
}

/// What a performance did.
struct Take {
    /// Left + right, averaged.
    mono: Vec<f32>,
    /// Both channels, for bit comparisons.
    hash: u64,
    crumple_events: u64,
    /// Fastest vertex seen at a block end, m/s.
    max_speed_m_s: f64,
    phrases_playing_at_end: usize,
    /// The sheet's crumple gesture at the end.
    crumple_at_end: f32,
}

fn play(bank: &Arc<PhraseBank>, midi: &[Timed], length_s: f64, block: usize) -> Take {
    let params = ParamValues::default();
    let mut sim = Sim::new(papier::engine::sim_config(&params));
    papier::engine::sync_fresh_sim(&mut sim, &params);
    let meters = Arc::new(Meters::default());
    let mut e = Engine::new(
        SimMode::Lockstep,
        RATE,
        sim,
        &params,
        papier::render::default_db(RATE),
        Arc::new(SheetStore::default()),
        0,
        meters.clone(),
        Arc::new(papier::engine::ViewShared::default()),
        papier::engine::permit_always,
    )
    .expect("engine");
    e.swap_phrases(bank.clone());
    let total = (length_s * RATE) as usize;
    let mut events: Vec<(usize, MidiInput)> = midi
        .iter()
        .map(|(t, m)| ((t * RATE).round() as usize, *m))
        .collect();
    events.sort_by_key(|(s, _)| *s);
    let (mut l, mut r) = (vec![0.0f32; block], vec![0.0f32; block]);
    let mut mono = Vec::with_capacity(total);
    let mut hash = 0xcbf2_9ce4_8422_2325u64;
    let mut next = 0;
    let mut max_speed_m_s: f64 = 0.0;
    let mut pos = 0;
    while pos < total {
        let n = block.min(total - pos);
        e.begin_block(&params);
        while next < events.len() && events[next].0 < pos + n {
            e.midi(events[next].1, (events[next].0.max(pos) - pos) as u32);
            next += 1;
        }
        e.render(&mut l[..n], &mut r[..n]);
        for i in 0..n {
            mono.push(0.5 * (l[i] + r[i]));
            for x in [l[i], r[i]] {
                hash = (hash ^ u64::from(x.to_bits())).wrapping_mul(0x100_0000_01b3);
            }
        }
        let sim = e.lockstep_sim().expect("lockstep");
        for v in &sim.sheet().sp.vel {
            max_speed_m_s = max_speed_m_s.max(v.norm());
        }
        pos += n;
    }
    let crumple_at_end = e
        .lockstep_sim()
        .expect("lockstep")
        .gesture(sim_core::GestureParam::Crumple);
    Take {
        crumple_at_end,
        mono,
        hash,
        crumple_events: meters.crumple_events.load(Ordering::Relaxed),
        max_speed_m_s,
        phrases_playing_at_end: e.phrases_playing(),
    }
}

fn dbfs(x: &[f32]) -> f64 {
    let ms = x.iter().map(|v| f64::from(*v).powi(2)).sum::<f64>() / x.len().max(1) as f64;
    10.0 * ms.max(1e-24).log10()
}

#[test]
fn every_factory_phrase_plays_from_its_note_and_moves_the_sheet() {
    let bank = Arc::new(PhraseBank::factory());
    let silent = play(&bank, &[], 1.0, 512);
    assert!(
        silent.max_speed_m_s < 0.05,
        "a sheet nobody plays stays still"
    );
    let mut report = Vec::new();
    for p in bank.by_note() {
        let length_s = 0.1 + p.duration_s * 1.1 + 0.3;
        let take = play(&bank, &[note_on(0.1, p.note, 100)], length_s, 512);
        report.push(format!(
            "{} {}: {:.2} m/s, {} events, {:.1} dBFS",
            p.note,
            p.name,
            take.max_speed_m_s,
            take.crumple_events,
            dbfs(&take.mono)
        ));
        assert!(
            take.max_speed_m_s > 0.05,
            "{}: the sheet did not move\n{}",
            p.name,
            report.join("\n")
        );
        assert!(
            take.mono.iter().any(|x| *x != 0.0),
            "{}: silent\n{}",
            p.name,
            report.join("\n")
        );
    }
    println!("{}", report.join("\n"));
}

#[test]
fn velocity_changes_crumple_events_and_level_monotonically() {
    let bank = Arc::new(PhraseBank::factory());
    // A receipt (A6) and the seeds' S4 crumple (A4), each struck soft, medium and hard, four
    // hits per velocity (four seeds: one crumple's events are chaotic); the events per second
    // of the takes (the phrase's length at that velocity's speed) and their level. (C5, note 70,
    // behaves the same: docs/benchmarks.md "Phrases".)
    const HITS: usize = 4;
    for note in [61u8, 75] {
        let p = bank.get(note).expect("factory phrase");
        let spacing_s = p.duration_s / f64::from(SLOWEST_SPEED) + 0.3;
        let mut last: Option<(f64, f64)> = None;
        for velocity in [30u8, 75, 120] {
            let midi: Vec<Timed> = (0..HITS)
                .flat_map(|h| {
                    let t = 0.1 + h as f64 * spacing_s;
                    [
                        note_on(t, note, velocity),
                        (t, MidiInput::NoteOff { key: note }),
                    ]
                })
                .collect();
            let take = play(&bank, &midi, 0.1 + HITS as f64 * spacing_s, 512);
            let played_s = HITS as f64 * p.duration_s
                / f64::from(speed_for_velocity(f32::from(velocity) / 127.0));
            let rate = take.crumple_events as f64 / played_s;
            let level = dbfs(&take.mono);
            println!(
                "{}: velocity {velocity}: {rate:.1} events/s, {level:.1} dBFS",
                p.name
            );
            if let Some((r0, l0)) = last {
                assert!(rate > r0, "{}: events/s {r0:.1} → {rate:.1}", p.name);
                assert!(level > l0, "{}: level {l0:.1} → {level:.1} dBFS", p.name);
            }
            last = Some((rate, level));
        }
    }
}

#[test]
fn two_hits_differ_and_two_renders_are_bit_identical_at_any_block_size() {
    let bank = Arc::new(PhraseBank::factory());
    // Crumple a receipt twice, the same velocity: the second hit is another take.
    let midi = [note_on(0.1, 61, 100), note_on(3.1, 61, 100)];
    let a = play(&bank, &midi, 6.0, 512);
    let hit = |take: &Take, t0: f64| {
        let s = (t0 * RATE) as usize;
        take.mono[s..s + (2.5 * RATE) as usize].to_vec()
    };
    let (first, second) = (hit(&a, 0.1), hit(&a, 3.1));
    assert!(dbfs(&first) > -60.0 && dbfs(&second) > -60.0);
    let differing = first.iter().zip(&second).filter(|(x, y)| x != y).count();
    assert!(
        differing > first.len() / 2,
        "two hits sound the same ({differing} of {} samples differ)",
        first.len()
    );
    for block in [37, 4096] {
        let b = play(&bank, &midi, 6.0, block);
        assert_eq!(a.hash, b.hash, "block {block} renders other bits");
    }
    assert_eq!(a.hash, play(&bank, &midi, 6.0, 512).hash);
}

#[test]
fn a_reset_or_cc_121_stops_a_phrase_and_a_user_phrase_replaces_a_factory_one() {
    let bank = Arc::new(PhraseBank::factory());
    let slow = bank.get(63).expect("slow tear");
    assert!(slow.duration_s > 3.0);
    let playing = play(&bank, &[note_on(0.1, 63, 100)], 1.0, 256);
    assert_eq!(playing.phrases_playing_at_end, 1);
    for stop in [
        MidiInput::NoteOn {
            key: 36,
            velocity: 1.0,
        },
        MidiInput::Cc {
            cc: 121,
            value: 0.0,
        },
    ] {
        let take = play(&bank, &[note_on(0.1, 63, 100), (0.5, stop)], 1.0, 256);
        assert_eq!(take.phrases_playing_at_end, 0, "{stop:?}");
    }
    // A user's crumple on C4 replaces the page turn.
    let dir = std::env::temp_dir().join(format!("papier-user-phrases-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(
        dir.join("big_crumple.toml"),
        "version = 1\nduration_s = 2.0\n[phrase]\nnote = 60\nstart = \"fresh\"\n\
         [[lane]]\nid = \"crumple\"\npoints = [[0.0, 0.0], [1.5, 1.0]]\n",
    )
    .unwrap();
    let user = Arc::new(PhraseBank::with_folder(&dir));
    std::fs::remove_dir_all(&dir).unwrap();
    assert!(user.errors.is_empty(), "{:?}", user.errors);
    let take = play(&user, &[note_on(0.1, 60, 100)], 2.5, 512);
    let page_turn = play(&bank, &[note_on(0.1, 60, 100)], 2.5, 512);
    assert!(
        take.crumple_events > page_turn.crumple_events + 20,
        "the user's crumple plays: {} events, the page turn {}",
        take.crumple_events,
        page_turn.crumple_events
    );
}

#[test]
fn a_phrase_and_a_cc_on_one_gesture_the_latest_change_wins() {
    let dir = std::env::temp_dir().join(format!("papier-latest-wins-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    // A phrase holding the crumple at 0.5 while its key is down.
    std::fs::write(
        dir.join("hold.toml"),
        "version = 1\nduration_s = 3.0\n[phrase]\nnote = 100\nnote_off = \"release\"\n\
         [[lane]]\nid = \"crumple\"\ninterp = \"step\"\npoints = [[0.0, 0.5]]\n",
    )
    .unwrap();
    let bank = Arc::new(PhraseBank::with_folder(&dir));
    std::fs::remove_dir_all(&dir).unwrap();
    let cc_zero = |t: f64| (t, MidiInput::Cc { cc: 20, value: 0.0 });
    // The CC after the phrase's value: the CC wins.
    let later = play(&bank, &[note_on(0.1, 100, 100), cc_zero(1.0)], 1.5, 256);
    assert_eq!(later.crumple_at_end, 0.0);
    // The phrase after the CC: the phrase wins (0.5 within the hit's ±8 %).
    let earlier = play(&bank, &[cc_zero(0.05), note_on(0.1, 100, 100)], 1.5, 256);
    assert!(
        (earlier.crumple_at_end - 0.5).abs() < 0.05,
        "{}",
        earlier.crumple_at_end
    );
}
