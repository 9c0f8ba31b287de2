//! A small CLAP host on `clack-host`, loading the bundled `Papier.clap` the way a DAW does:
//! scan the factory, instantiate, read the parameter list, set the render mode, activate,
//! process on a separate audio thread with events, deactivate, save and load state; also
//! flush parameters without processing, and keep the audio thread running while the main thread
//! works on the plugin ([`Instance::process_concurrently`]).

use std::ffi::CString;
use std::path::Path;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};

use clack_extensions::params::{ParamInfoBuffer, ParamInfoFlags, PluginParams};
use clack_extensions::render::{PluginRender, RenderMode};
use clack_extensions::state::PluginState;
use clack_host::events::event_types::{
    MidiEvent, NoteChokeEvent, NoteOffEvent, NoteOnEvent, ParamValueEvent,
};
use clack_host::prelude::*;

/// Serializes plugin use within one test process. A DAW drives every instance of a plugin from
/// one main thread; the test harness runs tests on parallel threads, which nice-plug's
/// main-thread bookkeeping does not expect. Every test takes this guard first.
pub fn serial() -> std::sync::MutexGuard<'static, ()> {
    static LOCK: std::sync::Mutex<()> = std::sync::Mutex::new(());
    LOCK.lock().unwrap_or_else(|e| e.into_inner())
}

/// Host callbacks: nothing to do, the tests drive everything.
pub struct TestShared;

impl<'a> SharedHandler<'a> for TestShared {
    fn request_restart(&self) {}
    fn request_process(&self) {}
    fn request_callback(&self) {}
}

/// The test host's handler types.
pub struct TestHost;

impl HostHandlers for TestHost {
    type Shared<'a> = TestShared;
    type MainThread<'a> = ();
    type AudioProcessor<'a> = ();

    fn declare_extensions(builder: &mut HostExtensions<Self>, _shared: &Self::Shared<'_>) {
        // Hosts that show plugin windows offer the GUI extension (see `crate::clap_gui`).
        builder.register::<clack_extensions::gui::HostGui>();
    }
}

/// A parameter as the host sees it.
#[derive(Clone, Debug)]
pub struct ParamDesc {
    /// CLAP id.
    pub id: ClapId,
    /// Display name.
    pub name: String,
    /// Module (group) path.
    pub module: String,
    /// Minimum value (nice-plug exposes normalized 0–1).
    pub min: f64,
    /// Maximum value.
    pub max: f64,
    /// Default value.
    pub default: f64,
    /// Takes whole-number values only (`CLAP_PARAM_IS_STEPPED`).
    pub stepped: bool,
}

/// The kind of a raw CLAP note event ([`HostEvent::Note`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum NoteKind {
    /// `CLAP_EVENT_NOTE_ON`.
    On,
    /// `CLAP_EVENT_NOTE_OFF`.
    Off,
    /// `CLAP_EVENT_NOTE_CHOKE`.
    Choke,
}

/// A host-side event at an absolute sample position.
#[derive(Clone, Copy, Debug)]
pub enum HostEvent {
    /// Raw 3-byte MIDI.
    Midi {
        /// Sample position.
        at: u64,
        /// Status and data bytes.
        data: [u8; 3],
    },
    /// A CLAP note on (key, velocity 0–1).
    NoteOn {
        /// Sample position.
        at: u64,
        /// Key.
        key: u8,
        /// Velocity.
        velocity: f64,
    },
    /// A CLAP note off; `key` −1 = wildcard.
    NoteOff {
        /// Sample position.
        at: u64,
        /// Key, or −1.
        key: i16,
    },
    /// A CLAP note event with every address field given raw: port, channel, key and note id,
    /// each −1 for a wildcard where the spec allows it (or to see how a plugin copes where it
    /// does not).
    Note {
        /// Sample position.
        at: u64,
        /// On, off or choke.
        kind: NoteKind,
        /// Note port, or −1.
        port: i16,
        /// Channel, or −1.
        channel: i16,
        /// Key, or −1.
        key: i16,
        /// Note id, or −1.
        note_id: i32,
        /// Velocity 0–1.
        velocity: f64,
    },
    /// A parameter change (normalized value).
    Param {
        /// Sample position.
        at: u64,
        /// Parameter id.
        id: ClapId,
        /// Normalized value.
        value: f64,
    },
}

impl HostEvent {
    /// Sample position.
    pub fn at(&self) -> u64 {
        match *self {
            HostEvent::Midi { at, .. }
            | HostEvent::NoteOn { at, .. }
            | HostEvent::NoteOff { at, .. }
            | HostEvent::Note { at, .. }
            | HostEvent::Param { at, .. } => at,
        }
    }

    /// Adds the event to a block's input events at `offset` samples into the block.
    pub fn push_to(&self, ev: &mut EventBuffer, offset: u32) {
        match *self {
            HostEvent::Midi { data, .. } => ev.push(&MidiEvent::new(offset, 0, data)),
            HostEvent::NoteOn { key, velocity, .. } => ev.push(&NoteOnEvent::new(
                offset,
                Pckn::from_raw(0, 0, i16::from(key), -1),
                velocity,
            )),
            HostEvent::NoteOff { key, .. } => ev.push(&NoteOffEvent::new(
                offset,
                Pckn::from_raw(0, 0, key, -1),
                0.0,
            )),
            HostEvent::Note {
                kind,
                port,
                channel,
                key,
                note_id,
                velocity,
                ..
            } => {
                let pckn = Pckn::from_raw(port, channel, key, note_id);
                match kind {
                    NoteKind::On => ev.push(&NoteOnEvent::new(offset, pckn, velocity)),
                    NoteKind::Off => ev.push(&NoteOffEvent::new(offset, pckn, velocity)),
                    NoteKind::Choke => ev.push(&NoteChokeEvent::new(offset, pckn)),
                }
            }
            HostEvent::Param { id, value, .. } => {
                ev.push(&ParamValueEvent::new(offset, id, Pckn::match_all(), value))
            }
        }
    }
}

/// A loaded plugin bundle.
pub struct Bundle {
    entry: PluginEntry,
    id: CString,
    host_info: HostInfo,
}

impl Bundle {
    /// Loads a `.clap` file and finds its (only) plugin.
    pub fn load(path: &Path) -> Result<Self, String> {
        let host_info = HostInfo::new("papier-tests", "Papier", "https://papier.invalid", "0.1")
            .map_err(|e| e.to_string())?;
        // SAFETY: loading a plugin library runs its code; the plugin under test is ours.
        let entry = unsafe { PluginEntry::load(path) }.map_err(|e| format!("{e:?}"))?;
        let factory = entry
            .get_plugin_factory()
            .ok_or("the bundle has no plugin factory")?;
        let d = factory
            .plugin_descriptors()
            .next()
            .ok_or("the bundle has no plugin")?;
        let id = CString::from(d.id().ok_or("descriptor without id")?);
        Ok(Self {
            entry,
            id,
            host_info,
        })
    }

    /// The plugin's id and name, and its feature list.
    pub fn descriptor(&self) -> (String, String, Vec<String>) {
        let factory = self.entry.get_plugin_factory().expect("factory");
        let d = factory.plugin_descriptors().next().expect("descriptor");
        (
            d.id()
                .map(|s| s.to_string_lossy().into_owned())
                .unwrap_or_default(),
            d.name()
                .map(|s| s.to_string_lossy().into_owned())
                .unwrap_or_default(),
            d.features()
                .map(|f| f.to_string_lossy().into_owned())
                .collect(),
        )
    }

    /// A new plugin instance.
    pub fn instance(&self) -> Result<Instance, String> {
        let inst = PluginInstance::<TestHost>::new(
            |_| TestShared,
            |_| (),
            &self.entry,
            &self.id,
            &self.host_info,
        )
        .map_err(|e| format!("{e:?}"))?;
        let mut i = Instance {
            inst,
            params: Vec::new(),
            active: None,
        };
        i.params = i.read_params();
        Ok(i)
    }
}

/// One plugin instance.
pub struct Instance {
    inst: PluginInstance<TestHost>,
    /// The parameter list.
    pub params: Vec<ParamDesc>,
    active: Option<StoppedPluginAudioProcessor<TestHost>>,
}

impl Instance {
    fn read_params(&mut self) -> Vec<ParamDesc> {
        let mut out = Vec::new();
        let h = self.inst.plugin_handle();
        let Some(ext) = h.get_extension::<PluginParams>() else {
            return out;
        };
        for i in 0..ext.count(&h) {
            let mut buf = ParamInfoBuffer::new();
            if let Some(info) = ext.get_info(&h, i, &mut buf) {
                out.push(ParamDesc {
                    id: info.id,
                    name: String::from_utf8_lossy(info.name).into_owned(),
                    module: String::from_utf8_lossy(info.module).into_owned(),
                    min: info.min_value,
                    max: info.max_value,
                    default: info.default_value,
                    stepped: info.flags.contains(ParamInfoFlags::IS_STEPPED),
                });
            }
        }
        out
    }

    /// Formats a parameter value as the host shows it (`clap_plugin_params.value_to_text`).
    pub fn value_to_text(&mut self, id: ClapId, value: f64) -> Option<String> {
        let h = self.inst.plugin_handle();
        let ext = h.get_extension::<PluginParams>()?;
        let mut buf = [0u8; 256];
        let text = ext.value_to_text(&h, id, value, &mut buf).ok()?;
        Some(String::from_utf8_lossy(text).into_owned())
    }

    /// Parses a text a user typed (`clap_plugin_params.text_to_value`).
    pub fn text_to_value(&mut self, id: ClapId, text: &str) -> Option<f64> {
        let h = self.inst.plugin_handle();
        let ext = h.get_extension::<PluginParams>()?;
        let c = std::ffi::CString::new(text).ok()?;
        ext.text_to_value(&h, id, &c)
    }

    /// The CLAP id of a parameter by display name.
    pub fn param(&self, name: &str) -> ClapId {
        self.params
            .iter()
            .find(|p| p.name == name)
            .unwrap_or_else(|| panic!("no parameter named {name:?}"))
            .id
    }

    /// Current value of a parameter (main thread).
    pub fn param_value(&mut self, id: ClapId) -> Option<f64> {
        let h = self.inst.plugin_handle();
        let ext = h.get_extension::<PluginParams>()?;
        ext.get_value(&h, id)
    }

    /// Sets the render mode (offline or real time).
    pub fn set_offline(&mut self, offline: bool) -> Result<(), String> {
        let h = self.inst.plugin_handle();
        let ext = h
            .get_extension::<PluginRender>()
            .ok_or("no render extension")?;
        ext.set(
            &h,
            if offline {
                RenderMode::Offline
            } else {
                RenderMode::Realtime
            },
        )
        .map_err(|e| format!("{e:?}"))
    }

    /// Saves the state.
    pub fn save_state(&mut self) -> Result<Vec<u8>, String> {
        let h = self.inst.plugin_handle();
        let ext = h
            .get_extension::<PluginState>()
            .ok_or("no state extension")?;
        let mut out = Vec::new();
        ext.save(&h, &mut out).map_err(|e| e.to_string())?;
        Ok(out)
    }

    /// Loads a state.
    pub fn load_state(&mut self, bytes: &[u8]) -> Result<(), String> {
        let h = self.inst.plugin_handle();
        let ext = h
            .get_extension::<PluginState>()
            .ok_or("no state extension")?;
        let mut r = std::io::Cursor::new(bytes);
        ext.load(&h, &mut r).map_err(|e| e.to_string())
    }

    /// Loads a state through a stream that hands out at most `chunk` bytes per read, as some
    /// hosts do.
    pub fn load_state_in_chunks(&mut self, bytes: &[u8], chunk: usize) -> Result<(), String> {
        struct Trickle<'a>(&'a [u8], usize);
        impl std::io::Read for Trickle<'_> {
            fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
                let n = buf.len().min(self.1).min(self.0.len());
                buf[..n].copy_from_slice(&self.0[..n]);
                self.0 = &self.0[n..];
                Ok(n)
            }
        }
        let h = self.inst.plugin_handle();
        let ext = h
            .get_extension::<PluginState>()
            .ok_or("no state extension")?;
        let mut r = Trickle(bytes, chunk.max(1));
        ext.load(&h, &mut r).map_err(|e| e.to_string())
    }

    /// Activates the plugin as a host does (blocks of 1 to `max_block` samples) and returns
    /// its audio processor, not yet started.
    fn start(
        &mut self,
        sample_rate: f64,
        max_block: u32,
    ) -> Result<StoppedPluginAudioProcessor<TestHost>, String> {
        let cfg = PluginAudioConfiguration {
            sample_rate,
            min_frames_count: 1,
            max_frames_count: max_block,
        };
        self.inst
            .activate(|_, _| (), cfg)
            .map_err(|e| format!("activate: {e:?}"))
    }

    /// Activates without processing (see [`Instance::deactivate`]).
    pub fn activate(&mut self, sample_rate: f64, max_block: u32) -> Result<(), String> {
        let stopped = self.start(sample_rate, max_block)?;
        self.active = Some(stopped);
        Ok(())
    }

    /// Deactivates after [`Instance::activate`].
    pub fn deactivate(&mut self) {
        if let Some(stopped) = self.active.take() {
            self.inst.deactivate(stopped);
        }
    }

    /// The plugin's main-thread handle (for extensions the helpers do not wrap).
    pub fn plugin_handle(&mut self) -> PluginMainThreadHandle<'_> {
        self.inst.plugin_handle()
    }

    /// Takes the audio processor of an [`Instance::activate`]d plugin, to run it on a thread of
    /// the caller's (give it back with [`Instance::put_processor`] before deactivating).
    pub fn take_processor(&mut self) -> Option<StoppedPluginAudioProcessor<TestHost>> {
        self.active.take()
    }

    /// Gives back a processor taken with [`Instance::take_processor`].
    pub fn put_processor(&mut self, processor: StoppedPluginAudioProcessor<TestHost>) {
        self.active = Some(processor);
    }

    /// Runs pending main-thread callbacks (nice-plug posts GUI/param rescans there).
    pub fn idle(&mut self) {
        self.inst.call_on_main_thread_callback();
    }

    /// Sends parameter changes through `clap_plugin_params.flush`, without processing: on the
    /// main thread while inactive, or (activated with [`Instance::activate`], not processing)
    /// on the processor's handle. Returns how many events the plugin sent back.
    pub fn flush_params(&mut self, changes: &[(ClapId, f64)]) -> Result<usize, String> {
        let events = || {
            let mut input = EventBuffer::new();
            for &(id, value) in changes {
                input.push(&ParamValueEvent::new(0, id, Pckn::match_all(), value));
            }
            input
        };
        if let Some(mut processor) = self.active.take() {
            // Active: the spec wants the flush on the audio thread.
            let (processor, sent_back) = std::thread::scope(|s| {
                s.spawn(move || {
                    let input = events();
                    let mut output = EventBuffer::new();
                    let mut h = processor.plugin_handle();
                    let found = h.get_extension::<PluginParams>().map(|ext| {
                        ext.flush_active(&mut h, &input.as_input(), &mut output.as_output());
                    });
                    (processor, found.map(|()| output.len() as usize))
                })
                .join()
                .map_err(|_| "flush panicked".to_string())
            })?;
            self.active = Some(processor);
            sent_back.ok_or_else(|| "no params extension".to_string())
        } else {
            let input = events();
            let mut output = EventBuffer::new();
            let mut h = self
                .inst
                .inactive_plugin_handle()
                .ok_or("the plugin is active but its processor is elsewhere")?;
            let ext = h
                .get_extension::<PluginParams>()
                .ok_or("no params extension")?;
            ext.flush(&mut h, &input.as_input(), &mut output.as_output());
            Ok(output.len() as usize)
        }
    }

    /// Activates at `sample_rate`, processes `total` samples in blocks of `block` (the last may be
    /// shorter) with `events` on an audio thread, deactivates, and returns the stereo output.
    /// `block_sizes`, if given, overrides `block` with a repeating pattern of sizes (each ≤ max).
    pub fn render(
        &mut self,
        sample_rate: f64,
        max_block: u32,
        block_sizes: &[u32],
        total: u64,
        events: &[HostEvent],
    ) -> Result<(Vec<f32>, Vec<f32>), String> {
        let stopped = self.start(sample_rate, max_block)?;
        let sizes: Vec<u32> = if block_sizes.is_empty() {
            vec![max_block]
        } else {
            block_sizes
                .iter()
                .map(|b| (*b).clamp(1, max_block))
                .collect()
        };
        let result = std::thread::scope(|s| {
            s.spawn(move || -> Result<_, String> {
                let mut proc = stopped
                    .start_processing()
                    .map_err(|e| format!("start_processing: {e:?}"))?;
                let mut feed = Feed::new(events, max_block, total as usize);
                let mut k = 0usize;
                while feed.pos < total {
                    let n = u64::from(sizes[k % sizes.len()]).min(total - feed.pos);
                    k += 1;
                    feed.block(&mut proc, n as u32)?;
                }
                Ok((proc.stop_processing(), feed.left, feed.right))
            })
            .join()
            .map_err(|_| "audio thread panicked".to_string())?
        });
        let (stopped, left, right) = result?;
        self.inst.deactivate(stopped);
        self.idle();
        Ok((left, right))
    }

    /// Activates at `sample_rate` and starts an audio thread that processes blocks of
    /// `max_block` samples with `events` (absolute sample positions) whenever
    /// [`AudioThread::play_to`] lets it, while `main` runs on this (main) thread with the
    /// instance: it can save or load state, read parameters, … while audio is processed. Then
    /// stops the audio thread, deactivates, and returns `main`'s result and the stereo output.
    pub fn process_concurrently<R>(
        &mut self,
        sample_rate: f64,
        max_block: u32,
        events: &[HostEvent],
        main: impl FnOnce(&mut Instance, &AudioThread) -> R,
    ) -> Result<(R, Vec<f32>, Vec<f32>), String> {
        let stopped = self.start(sample_rate, max_block)?;
        let ctl = AudioThread {
            target: AtomicU64::new(0),
            done: AtomicU64::new(0),
            stop: AtomicBool::new(false),
            ended: AtomicBool::new(false),
        };
        let (r, audio) = std::thread::scope(|s| {
            let ctl = &ctl;
            let audio = s.spawn(move || -> Result<_, String> {
                let run = || -> Result<_, String> {
                    let mut proc = stopped
                        .start_processing()
                        .map_err(|e| format!("start_processing: {e:?}"))?;
                    let mut feed = Feed::new(events, max_block, 0);
                    while !ctl.stop.load(Ordering::Acquire) {
                        let target = ctl.target.load(Ordering::Acquire);
                        if feed.pos < target {
                            let n = (target - feed.pos).min(u64::from(max_block));
                            feed.block(&mut proc, n as u32)?;
                            ctl.done.store(feed.pos, Ordering::Release);
                        } else {
                            std::thread::sleep(std::time::Duration::from_micros(100));
                        }
                    }
                    Ok((proc.stop_processing(), feed.left, feed.right))
                };
                let result = run();
                ctl.ended.store(true, Ordering::Release);
                result
            });
            // Stops the audio thread also when `main` panics (else the scope would wait forever).
            struct StopOnDrop<'a>(&'a AtomicBool);
            impl Drop for StopOnDrop<'_> {
                fn drop(&mut self) {
                    self.0.store(true, Ordering::Release);
                }
            }
            let stop = StopOnDrop(&ctl.stop);
            let r = main(self, ctl);
            drop(stop);
            (r, audio.join())
        });
        let (stopped, left, right) = audio.map_err(|_| "audio thread panicked".to_string())??;
        self.inst.deactivate(stopped);
        self.idle();
        Ok((r, left, right))
    }
}

/// The main thread's control of the audio thread of [`Instance::process_concurrently`].
pub struct AudioThread {
    target: AtomicU64,
    done: AtomicU64,
    stop: AtomicBool,
    ended: AtomicBool,
}

impl AudioThread {
    /// Lets the audio thread process up to sample `n` (returns at once; it runs meanwhile).
    pub fn play_to(&self, n: u64) {
        self.target.fetch_max(n, Ordering::AcqRel);
    }

    /// Samples processed so far.
    pub fn processed(&self) -> u64 {
        self.done.load(Ordering::Acquire)
    }

    /// Waits until the audio thread has processed everything [`AudioThread::play_to`] allowed.
    /// Returns false if the audio thread ended early (failed or panicked).
    pub fn wait(&self) -> bool {
        loop {
            if self.processed() >= self.target.load(Ordering::Acquire) {
                return true;
            }
            if self.ended.load(Ordering::Acquire) {
                return false;
            }
            std::thread::sleep(std::time::Duration::from_micros(100));
        }
    }

    /// [`AudioThread::play_to`] then [`AudioThread::wait`].
    pub fn play_and_wait(&self, n: u64) -> bool {
        self.play_to(n);
        self.wait()
    }
}

/// Feeds blocks to a processing plugin: the host events in time order, the output buffers, the
/// collected output.
struct Feed {
    sorted: Vec<HostEvent>,
    next: usize,
    pos: u64,
    l: Vec<f32>,
    r: Vec<f32>,
    ports: AudioPorts,
    left: Vec<f32>,
    right: Vec<f32>,
}

impl Feed {
    fn new(events: &[HostEvent], max_block: u32, capacity: usize) -> Self {
        let mut sorted = events.to_vec();
        sorted.sort_by_key(|e| e.at());
        Self {
            sorted,
            next: 0,
            pos: 0,
            l: vec![0.0; max_block as usize],
            r: vec![0.0; max_block as usize],
            ports: AudioPorts::with_capacity(2, 1),
            left: Vec::with_capacity(capacity),
            right: Vec::with_capacity(capacity),
        }
    }

    /// Processes the next `n` samples (n ≤ the maximum block size).
    fn block(
        &mut self,
        proc: &mut StartedPluginAudioProcessor<TestHost>,
        n: u32,
    ) -> Result<(), String> {
        let pos = self.pos;
        let mut ev = EventBuffer::new();
        while self.next < self.sorted.len() && self.sorted[self.next].at() < pos + u64::from(n) {
            let t = (self.sorted[self.next].at().max(pos) - pos) as u32;
            self.sorted[self.next].push_to(&mut ev, t);
            self.next += 1;
        }
        let mut out_ev = EventBuffer::new();
        let nn = n as usize;
        {
            let mut outputs = self.ports.with_output_buffers([AudioPortBuffer {
                latency: 0,
                channels: AudioPortBufferType::f32_output_only(
                    [&mut self.l[..nn], &mut self.r[..nn]].into_iter(),
                ),
            }]);
            proc.process(
                &InputAudioBuffers::empty(),
                &mut outputs,
                &ev.as_input(),
                &mut out_ev.as_output(),
                Some(pos),
                None,
            )
            .map_err(|e| format!("process: {e:?}"))?;
        }
        self.left.extend_from_slice(&self.l[..nn]);
        self.right.extend_from_slice(&self.r[..nn]);
        self.pos += u64::from(n);
        Ok(())
    }
}
