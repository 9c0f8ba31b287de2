//! # Render counters: proof that the skips of digest-sound §11 happen
//!
//! Every shortcut the render path takes is counted, so tests and benches can check that it was
//! taken (and that the full path runs when it must). Plain integers, updated on the audio thread
//! without atomics; read them between `render()` calls ([`super::Renderer::counters`]). They are
//! zeroed by [`super::Renderer::reset`].

/// Counters of the render path (cumulative since `new()` or the last `reset()`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct RenderCounters {
    /// Samples rendered.
    pub samples: u64,
    /// `render()` calls.
    pub render_calls: u64,
    /// `set_frame()` calls.
    pub frames: u64,

    /// Crumple triggers received.
    pub triggers: u64,
    /// Triggers ignored because the amplitude was not finite or zero.
    pub triggers_invalid: u64,
    /// Triggers with no crumple unit in the database (empty crumple part or rate mismatch).
    pub triggers_without_unit: u64,
    /// Voices started.
    pub voices_started: u64,
    /// Triggers merged into a voice of the same unit started in the same batch (§11.5).
    pub voices_merged: u64,
    /// Triggers not started: estimated level below −90 dBFS (§11.5).
    pub voices_culled_quiet: u64,
    /// Triggers not started: more than 60 dB below the loudest voice of the last 50 ms (§11.5).
    pub voices_culled_masked: u64,
    /// Voices stolen (faded out over 2 ms) to make room.
    pub voices_stolen: u64,
    /// Triggers dropped because the pool was full of louder voices.
    pub voices_dropped_pool_full: u64,
    /// Voices that played to their (trimmed) end.
    pub voices_finished: u64,
    /// Blocks × image taps rendered for units (0 without reflectors: §11.1).
    pub unit_image_tap_blocks: u64,
    /// Image taps not created because the reflection was > 20 ms late or 40 dB below the direct
    /// sound, or the source/ear was behind the plane.
    pub image_taps_skipped: u64,

    /// Friction hops (hop boundaries reached).
    pub friction_hops: u64,
    /// Friction frames synthesized (inverse FFTs run, one per ear).
    pub friction_ffts: u64,
    /// Friction hops with no source: no iFFT (§11.2).
    pub friction_hops_skipped: u64,
    /// Samples of friction output not computed at all (silent after the tail).
    pub friction_samples_silent: u64,
    /// Per-bin comb evaluations (entries × ears × bins; 0 without reflectors: §11.1).
    pub friction_comb_bins: u64,
    /// Comb magnitudes reused from the geometry cache (§11.6).
    pub friction_comb_cache_hits: u64,
    /// Friction sources folded into an existing entry of the same cell and place (§11.4).
    pub friction_sources_merged: u64,
    /// Friction sources dropped because the entry table was full.
    pub friction_sources_dropped: u64,
    /// Friction sources with no spectrum in the database.
    pub friction_sources_without_spectrum: u64,

    /// Tear-noise samples generated.
    pub tear_samples: u64,
    /// Tear-noise samples skipped: no tearing (§11.3).
    pub tear_samples_skipped: u64,
    /// Tear onsets played.
    pub tear_onsets: u64,
    /// Tear-tone kernels designed (the flaps' cell changed).
    pub tear_tone_kernels: u64,

    /// Air-noise samples generated (render/air.rs).
    pub air_samples: u64,
    /// Air-noise samples skipped: the sheet moved no air.
    pub air_samples_skipped: u64,
    /// Crackle samples generated (render/crackle.rs).
    pub crackle_samples: u64,
    /// Crackle samples skipped: no bent part of the sheet moved.
    pub crackle_samples_skipped: u64,

    /// Output samples (per channel) touched by the safety clipper.
    pub clipped_samples: u64,
    /// Non-finite output samples replaced by 0 (should stay 0).
    pub nonfinite_samples: u64,
    /// Database swaps done.
    pub db_swaps: u64,
    /// Database swaps rejected (prepared for another sample rate).
    pub db_swaps_rejected: u64,
}
