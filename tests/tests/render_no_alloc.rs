//! The render path never allocates (style §6.5, digest-sound §12 test 16): a counting
//! `#[global_allocator]` counts every allocation made by this thread while the gate is open, and
//! the test fails if `set_frame`, `trigger`, `render`, `reset`, `set_mix`, `set_scene`,
//! `set_options` or `swap_db` allocate — at several rates, with all processes busy (64 voices and
//! stealing, 16 friction sources with reflectors, tearing), and with block sizes from 1 to 16384.
//!
//! **Run it with `--release`**: `cargo test --release -p papier-tests --test render_no_alloc`.
//! In debug builds `papier` links nice-plug with `assert_process_allocs`, which installs its own
//! `#[global_allocator]` (`AllocDisabler`) whenever `debug_assertions` are on, and a binary can
//! have only one. In debug builds this file therefore compiles to a single ignored test that says
//! so (the plugin's own `process()` is still guarded by nice-plug's allocator there).

#[cfg(debug_assertions)]
#[test]
#[ignore = "run with --release: in debug builds nice-plug's AllocDisabler is the global allocator"]
fn render_path_is_allocation_free() {}

#[cfg(not(debug_assertions))]
mod render_common;

#[cfg(not(debug_assertions))]
mod counting {
    use std::alloc::{GlobalAlloc, Layout, System};
    use std::cell::Cell;
    use std::sync::Arc;

    use super::render_common::*;
    use papier::render::{MixLevels, RenderOptions, Renderer};
    use sounddb::SoundDb;

    struct Counting;

    thread_local! {
        static GATE: Cell<bool> = const { Cell::new(false) };
        static COUNT: Cell<u64> = const { Cell::new(0) };
    }

    // SAFETY: forwards to the system allocator; only counts.
    unsafe impl GlobalAlloc for Counting {
        unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
            if GATE.with(Cell::get) {
                COUNT.with(|c| c.set(c.get() + 1));
            }
            // SAFETY: same contract as the caller's.
            unsafe { System.alloc(layout) }
        }

        unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
            if GATE.with(Cell::get) {
                COUNT.with(|c| c.set(c.get() + 1));
            }
            // SAFETY: same contract as the caller's.
            unsafe { System.dealloc(ptr, layout) }
        }

        unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
            if GATE.with(Cell::get) {
                COUNT.with(|c| c.set(c.get() + 1));
            }
            // SAFETY: same contract as the caller's.
            unsafe { System.realloc(ptr, layout, new_size) }
        }
    }

    #[global_allocator]
    static ALLOC: Counting = Counting;

    /// Runs `f` with counting on; returns the number of allocator calls it made.
    fn count<R>(f: impl FnOnce() -> R) -> (R, u64) {
        COUNT.with(|c| c.set(0));
        GATE.with(|g| g.set(true));
        let r = f();
        GATE.with(|g| g.set(false));
        (r, COUNT.with(Cell::get))
    }

    #[test]
    fn counting_allocator_sees_allocations() {
        // The detector itself works (so the zero below means something).
        let (_, n) = count(|| vec![1u8; 100]);
        assert!(n >= 1);
    }

    #[test]
    fn render_path_is_allocation_free() {
        for rate in [8_000.0, 44_100.0, 96_000.0, 192_000.0] {
            let db = printer_db(rate);
            let other = Arc::new(SoundDb::prepare(
                &sounddb::generate::generate(sounddb::generate::Material::Banknote),
                rate,
            ));
            let wrong_rate = printer_db(if rate == 44_100.0 { 48_000.0 } else { 44_100.0 });
            let steps = busy_steps(120, 3);
            let mut r = Renderer::new(rate, db.clone(), 11);
            let mut l = vec![0.0f32; 16_384];
            let mut rr = vec![0.0f32; 16_384];
            let scene = table_and_wall();
            // Returned databases are kept (capacity reserved: pushing does not allocate) and dropped
            // after the gate closes, as the plugin drops them off the audio thread.
            let mut returned: Vec<Arc<SoundDb>> = Vec::with_capacity(4);
            let mut before_reset = *r.counters();
            // 24 distinct events (different places, sizes): they cannot merge, so the pool fills.
            let extra: Vec<_> = (0..24)
                .map(|k| {
                    let mut res = resonator([2.5, 10.0, 30.0][k % 3], [0.0, 10.0, 40.0][k % 3]);
                    res.centre_m[0] = -0.3 + 0.025 * k as f32;
                    res.centre_m[1] = 0.1 * (k % 2) as f32;
                    crumple(0.5 + 0.02 * k as f32, res)
                })
                .collect();
            let ((), n) = count(|| {
                r.set_scene(scene);
                r.set_mix(MixLevels {
                    crumple_db: -3.0,
                    friction_db: 2.0,
                    tear_db: -6.0,
                    output_db: -1.0,
                });
                r.set_options(RenderOptions::default());
                for (i, s) in steps.iter().enumerate() {
                    r.set_frame(&s.frame);
                    for e in &s.events {
                        r.trigger(e);
                    }
                    // Many triggers: fill the pool and steal.
                    for e in &extra {
                        r.trigger(e);
                    }
                    let block = [1usize, 64, 333, 1024, 16_384][i % 5];
                    r.render(&mut l[..block], &mut rr[..block]);
                    if i == 60 {
                        returned.push(r.swap_db(other.clone()));
                        returned.push(r.swap_db(wrong_rate.clone()));
                    }
                    if i == 90 {
                        before_reset = *r.counters();
                        r.reset();
                        r.set_options(RenderOptions::reference());
                    }
                }
            });
            assert_eq!(n, 0, "{rate} Hz: {n} allocator calls on the render path");
            assert!(r.counters().samples > 0);
            assert!(before_reset.voices_stolen > 0, "{before_reset:?}");
            assert!(before_reset.friction_ffts > 0 && before_reset.tear_samples > 0);
            assert!(before_reset.tear_onsets > 0 && before_reset.tear_tone_kernels > 1);
            assert_eq!(before_reset.db_swaps, 1);
            assert_eq!(before_reset.db_swaps_rejected, 1);
            assert!(Arc::ptr_eq(&returned[0], &db));
            assert!(Arc::ptr_eq(&returned[1], &wrong_rate));
        }
    }
}
