//! # Papier: a sheet of paper as an instrument
//!
//! A CLAP/VST3 instrument (MIDI in, stereo out) whose voice is a simulated sheet of paper. MIDI
//! notes grab and release its edges and corners, CCs and automation drive gestures (crumple,
//! slide, lift, twist, shake, tear), a physically inspired simulation of the sheet runs on a
//! worker thread ([`engine`]), and the sound is synthesized from the sheet's geometry
//! ([`render`]).
//!
//! Modules:
//! - [`params`]: the automatable parameters and the persisted state layout;
//! - [`gesture_map`]: MIDI → gesture commands (shared with `papier-render`);
//! - [`engine`]: parameter diffing, the simulation thread / lockstep stepping, the render call;
//! - [`phrase`]: gesture scripts played from MIDI notes (C4 up);
//! - [`preset`]: paper, room and mix presets (factory and user files);
//! - [`render`]: the audio render path (no nice-plug types);
//! - [`state`]: the sheet saved with the project (the persistence adapter);
//! - [`state_check`]: a saved state's version and parameters checked before they load;
//! - [`db_loader`]: the embedded or user sound database, loaded off the audio thread;
//! - [`editor`]: the egui window;
//! - [`offline`]: the offline renderer behind `papier-render`.

pub mod db_loader;
pub mod editor;
pub mod engine;
pub mod gesture_map;
pub mod offline;
pub mod params;
pub mod phrase;
pub mod preset;
pub mod render;
pub mod state;
pub mod state_check;

use std::num::NonZeroU32;
use std::sync::Arc;

use nice_plug::prelude::*;
use sim_core::Sim;
use sounddb::SoundDb;

use crate::editor::window_threads::WindowThreads;
use crate::engine::{Engine, Meters, ParamValues, SimMode, ViewShared, sim_config};
use crate::gesture_map::MidiInput;
use crate::params::PapierParams;
use crate::phrase::PhraseShelf;

/// Converts a nice-plug note event into the engine's MIDI input; `None` for events Papier does
/// not use.
pub fn midi_input<S>(event: &NoteEvent<S>) -> Option<(MidiInput, u32)> {
    match *event {
        NoteEvent::NoteOn {
            timing,
            key,
            velocity,
            ..
        } => match key.number() {
            Some(k) if velocity > 0.0 => Some((MidiInput::NoteOn { key: k, velocity }, timing)),
            Some(k) => Some((MidiInput::NoteOff { key: k }, timing)),
            None => None,
        },
        NoteEvent::NoteOff { timing, key, .. } | NoteEvent::Choke { timing, key, .. } => {
            match key.number() {
                Some(k) => Some((MidiInput::NoteOff { key: k }, timing)),
                None => Some((MidiInput::AllNotesOff, timing)),
            }
        }
        NoteEvent::MidiCC {
            timing, cc, value, ..
        } => Some((MidiInput::Cc { cc, value }, timing)),
        _ => None,
    }
}

/// The plugin.
pub struct Papier {
    params: Arc<PapierParams>,
    meters: Arc<Meters>,
    view: Arc<ViewShared>,
    /// The editor's window threads still running (`editor/window_threads.rs`).
    window_threads: Arc<WindowThreads>,
    /// The running engine (between `activate()` and `deactivate()`).
    engine: Option<Engine>,
    /// The sheet while no engine runs, with the store generation it is based on and the
    /// parameter values it reflects.
    parked: Option<(Sim, u64, ParamValues)>,
    /// The sound database in use.
    db: Arc<SoundDb>,
    /// Sample rate (bits) and user path the database was prepared for.
    db_key: Option<(u64, Option<std::path::PathBuf>)>,
    /// Sample rate of the running engine, Hz.
    sample_rate_hz: f64,
    /// The phrases the notes from C4 play.
    phrases: Arc<PhraseShelf>,
}

impl Default for Papier {
    fn default() -> Self {
        Self {
            params: Arc::new(PapierParams::default()),
            meters: Arc::new(Meters::default()),
            view: Arc::new(ViewShared::default()),
            window_threads: Arc::new(WindowThreads::default()),
            engine: None,
            parked: None,
            db: Arc::new(SoundDb::empty()),
            db_key: None,
            sample_rate_hz: 48_000.0,
            phrases: Arc::new(PhraseShelf::new(phrase::shelf::user_phrase_dir())),
        }
    }
}

impl Papier {
    fn stop_engine(&mut self) {
        if let Some(engine) = self.engine.take() {
            let last = engine.last_params();
            let Some((sim, generation)) = engine.into_sim() else {
                return;
            };
            // A moving sheet is published so the saved project holds where it is now; a sheet
            // at rest was already published when it came to rest.
            if !sim.is_asleep() {
                self.params.sheet_store.publish(sim.save(), generation);
            }
            self.parked = Some((sim, generation, last));
        }
    }
}

/// The allocation checker's permit (`assert_process_allocs`), handed to the engine for what
/// it may allocate on the audio thread in offline (lockstep) mode.
fn permit_alloc(f: &mut dyn FnMut()) {
    nice_plug::util::permit_alloc(f);
}

/// How long closing the plugin waits for an editor window thread baseview did not join.
const WINDOW_THREAD_PATIENCE: std::time::Duration = std::time::Duration::from_secs(2);

impl Drop for Papier {
    fn drop(&mut self) {
        self.stop_engine();
        // A window thread baseview did not join may still be tearing down its GL context; the
        // host may unload the library right after this (editor/window_threads.rs).
        if !self.window_threads.wait_until_ended(WINDOW_THREAD_PATIENCE) {
            nice_warn!("an editor window thread is still running as the plugin closes");
        }
    }
}

impl Plugin for Papier {
    const NAME: &'static str = "Papier";
    const VENDOR: &'static str = "Papier";
    const URL: &'static str = "https://papier.invalid";
    const EMAIL: &'static str = "papier@papier.invalid";
    const VERSION: &'static str = env!("CARGO_PKG_VERSION");

    const AUDIO_IO_LAYOUTS: &'static [AudioIOLayout] = &[AudioIOLayout {
        main_input_channels: None,
        main_output_channels: NonZeroU32::new(2),
        ..AudioIOLayout::const_default()
    }];
    const MIDI_INPUT: MidiConfig = MidiConfig::MidiCCs;
    const SAMPLE_ACCURATE_AUTOMATION: bool = true;

    type Editor = editor::EditorShell;
    type SysExMessage = ();
    type BackgroundTask = ();

    fn filter_state(state: &mut PluginState) {
        for problem in state_check::check(state) {
            nice_warn!("{problem}");
        }
    }

    fn params(&self) -> Arc<dyn Params> {
        self.params.clone()
    }

    fn editor(&mut self, _async_executor: AsyncExecutor<Self>) -> Option<Self::Editor> {
        editor::create(
            self.params.clone(),
            self.meters.clone(),
            self.view.clone(),
            self.window_threads.clone(),
            self.phrases.clone(),
        )
    }

    fn activate(
        &mut self,
        _audio_io_layout: &AudioIOLayout,
        buffer_config: &BufferConfig,
        _context: &mut impl ActivateContext<Self>,
    ) -> bool {
        self.stop_engine();
        let mode = if buffer_config.process_mode == ProcessMode::Offline {
            SimMode::Lockstep
        } else {
            SimMode::Threaded
        };
        let rate = f64::from(buffer_config.sample_rate);
        let key = (rate.to_bits(), self.params.db.path());
        if self.db_key.as_ref() != Some(&key) {
            // The database resampled for this rate (here, never on the audio thread).
            self.db = self.params.db.prepare_for_rate(rate);
            self.db_key = Some(key);
        }
        let values = self.params.values();
        let store = self.params.sheet_store.clone();
        let (mut sim, mut generation, mut reflected) = self.parked.take().unwrap_or_else(|| {
            let mut sim = Sim::new(sim_config(&values));
            engine::sync_fresh_sim(&mut sim, &values);
            (sim, 0, values)
        });
        if generation != store.generation() {
            // A project was loaded: its sheet goes with its parameters, in its room.
            generation =
                engine::frame_loop::restore_sheet(&mut sim, &store, generation, values.room);
            reflected = values;
        }
        match Engine::new(
            mode,
            rate,
            sim,
            &reflected,
            self.db.clone(),
            store,
            generation,
            self.meters.clone(),
            self.view.clone(),
            permit_alloc,
        ) {
            Ok(mut engine) => {
                engine.start_sound_at(&values);
                // The phrases as the folder holds them now (the editor's Reload does it live).
                self.phrases.reload_if_changed();
                while self.phrases.ready.pop().is_some() {}
                let bank = self.phrases.current();
                for e in &bank.errors {
                    nice_warn!("phrase refused: {e}");
                }
                engine.swap_phrases(bank);
                self.engine = Some(engine);
                self.sample_rate_hz = rate;
                true
            }
            Err(e) => {
                nice_error!("Papier cannot activate: {e}");
                false
            }
        }
    }

    fn reset(&mut self) {
        if let Some(engine) = self.engine.as_mut() {
            engine.reset_audio();
        }
    }

    fn deactivate(&mut self) {
        self.stop_engine();
        self.params.db.drain_retired();
        self.phrases.drain_retired();
    }

    fn process(
        &mut self,
        buffer: &mut Buffer,
        _aux: &mut AuxiliaryBuffers,
        context: &mut impl ProcessContext<Self>,
    ) -> ProcessStatus {
        let started = std::time::Instant::now();
        let channels = buffer.as_slice();
        let Some(engine) = self.engine.as_mut() else {
            for c in channels.iter_mut() {
                c.fill(0.0);
            }
            return ProcessStatus::Normal;
        };
        // A user database loaded off-thread is swapped in; the old one leaves through the
        // retired queue, to be dropped off the audio thread (skip the swap if that is full).
        let loader = &self.params.db;
        if !loader.retired.is_full()
            && let Some(new_db) = loader.ready.pop()
        {
            let old = engine.swap_db(new_db.clone());
            let _ = loader.retired.push(old);
            self.db = new_db;
        }
        // A phrase bank reloaded by the editor, the same way.
        let shelf = &self.phrases;
        if !shelf.retired.is_full()
            && let Some(bank) = shelf.ready.pop()
        {
            let old = engine.swap_phrases(bank);
            let _ = shelf.retired.push(old);
        }
        engine.begin_block(&self.params.values());
        while let Some(input) = self.view.gui_midi.pop() {
            engine.midi(input, 0);
        }
        while let Some(event) = context.next_event() {
            if let Some((input, timing)) = midi_input(&event) {
                engine.midi(input, timing);
            }
        }
        match channels {
            [left, right, ..] => engine.render(left, right),
            [mono] => {
                // Not a layout Papier declares; render the left ear into it rather than fail.
                let n = mono.len();
                let mut scratch = [0.0f32; 64];
                let mut pos = 0;
                while pos < n {
                    let m = (n - pos).min(scratch.len());
                    let (l, r) = (&mut mono[pos..pos + m], &mut scratch[..m]);
                    engine.render(l, r);
                    pos += m;
                }
            }
            [] => {}
        }
        let block_s = buffer.samples() as f64 / self.sample_rate_hz;
        self.meters
            .record_audio_load(started.elapsed().as_secs_f64(), block_s);
        ProcessStatus::KeepAlive
    }
}

impl ClapPlugin for Papier {
    const CLAP_ID: &'static str = "org.papier.papier";
    const CLAP_DESCRIPTION: Option<&'static str> =
        Some("A sheet of paper: crumple, bend, slide, shake and tear it, hear it.");
    const CLAP_MANUAL_URL: Option<&'static str> = None;
    const CLAP_SUPPORT_URL: Option<&'static str> = None;
    const CLAP_FEATURES: &'static [ClapFeature] = &[
        ClapFeature::Instrument,
        ClapFeature::Synthesizer,
        ClapFeature::Stereo,
    ];
}

impl Vst3Plugin for Papier {
    const VST3_CLASS_ID: [u8; 16] = *b"PapierSheetPaper";
    const VST3_SUBCATEGORIES: &'static [Vst3SubCategory] =
        &[Vst3SubCategory::Instrument, Vst3SubCategory::Synth];
}

nice_export_clap!(Papier);
nice_export_vst3!(Papier);
