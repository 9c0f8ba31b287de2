//! The editor's window in a real CLAP host (the test host of `papier_tests::clap` with the GUI
//! extension, on a private Xvfb): it is resizable, its size is saved with the project in
//! logical pixels, and it follows the display's scale.
//!
//! 1. A new instance opens at the default size. The host resizes it (`clap_plugin_gui.set_size`,
//!    as when the user drags the host window's corner): the editor's window takes the size and
//!    the saved state carries it; the next window opens at that size, and so does the window of
//!    another instance loaded from the saved state.
//! 2. With the display at 192 dpi (`Xft.dpi`, what desktops set for a 2× screen) the next
//!    window is twice as large in physical pixels, egui draws at 2 pixels per point (read from
//!    the editor's layout probe) and the saved size stays the same logical size.

use std::path::Path;
use std::time::{Duration, Instant};

use papier::editor::layout_probe::LAYOUT_ENV;
use papier::editor::window_size::DEFAULT_SIZE;
use papier_tests::clap::{Bundle, Instance, serial};
use papier_tests::clap_gui::{ParentWindow, close_editor, editor_size, open_editor, resize_editor};
use papier_tests::paths;
use papier_tests::xvfb::Xvfb;

/// How long to wait for a window to take a size (polling): generous, for loaded machines.
const PATIENCE: Duration = Duration::from_secs(60);

/// The editor size in a saved state, as `(width, height)` logical pixels.
fn saved_size(state: &[u8]) -> Option<(u32, u32)> {
    // The persisted field is JSON inside the state's JSON: {"width":…,"height":…}.
    let text = String::from_utf8_lossy(state).replace('\\', "");
    let at = text.find("\"editor_size\"")?;
    let rest = &text[at..];
    let number = |key: &str| -> Option<u32> {
        let i = rest.find(key)? + key.len();
        let digits: String = rest[i..]
            .chars()
            .take_while(|c| c.is_ascii_digit())
            .collect();
        digits.parse().ok()
    };
    Some((number("\"width\":")?, number("\"height\":")?))
}

/// Polls (idling the host) until `f` holds; panics with `what` after [`PATIENCE`].
fn wait_until(inst: &mut Instance, what: &str, mut f: impl FnMut(&mut Instance) -> bool) {
    let t0 = Instant::now();
    while !f(inst) {
        assert!(t0.elapsed() < PATIENCE, "{what} (waited {PATIENCE:?})");
        inst.idle();
        std::thread::sleep(Duration::from_millis(20));
    }
}

/// The editor's pixels per point from the layout probe's file, once written.
fn pixels_per_point(layout: &Path) -> Option<f32> {
    std::fs::read_to_string(layout)
        .ok()?
        .lines()
        .find_map(|l| l.strip_prefix("pixels_per_point "))
        .and_then(|v| v.trim().parse().ok())
}

#[test]
fn the_window_is_resizable_follows_the_display_scale_and_its_size_is_saved() {
    let _serial = serial();
    let t_start = Instant::now();
    let x = Xvfb::start(2600, 1800).expect("Xvfb");
    let layout = paths::scratch("editor_window_size").join("layout.txt");
    // SAFETY: set before the plugin (baseview) is loaded and before this test starts threads;
    // this binary has no other test that reads the environment concurrently.
    unsafe {
        std::env::set_var("DISPLAY", x.display());
        std::env::set_var(LAYOUT_ENV, &layout);
    }
    let bundle = Bundle::load(&paths::clap_bundle()).expect("load Papier.clap");
    let parent = ParentWindow::new(&x.display(), 800, 600).expect("host window");
    let (w0, h0) = DEFAULT_SIZE;
    let (w1, h1) = (w0 + 140, h0 + 80);

    // 1. Resizable, and the size is saved.
    let mut inst = bundle.instance().expect("instance");
    let size = open_editor(&mut inst, &parent).expect("open the editor");
    assert_eq!((size.width, size.height), (w0, h0), "a new editor's size");
    wait_until(&mut inst, "the editor's window at the default size", |_| {
        parent.child_sizes().unwrap_or_default() == [(w0, h0)]
    });
    resize_editor(&mut inst, &parent, w1, h1).expect("the host resizes the editor");
    wait_until(&mut inst, "the editor's window took the new size", |_| {
        parent.child_sizes().unwrap_or_default() == [(w1, h1)]
    });
    wait_until(&mut inst, "the saved state has the new size", |i| {
        saved_size(&i.save_state().expect("save")) == Some((w1, h1))
    });
    close_editor(&mut inst).expect("close");
    inst.idle();
    let size = open_editor(&mut inst, &parent).expect("open again");
    assert_eq!(
        (size.width, size.height),
        (w1, h1),
        "the next window's size"
    );
    close_editor(&mut inst).expect("close");
    inst.idle();
    let state = inst.save_state().expect("save");
    drop(inst);

    let mut other = bundle.instance().expect("instance");
    other.load_state(&state).expect("load the saved state");
    let size = open_editor(&mut other, &parent).expect("open in the reloaded project");
    assert_eq!(
        (size.width, size.height),
        (w1, h1),
        "the reloaded project's window size"
    );
    wait_until(
        &mut other,
        "the reloaded project's window size on screen",
        |_| parent.child_sizes().unwrap_or_default() == [(w1, h1)],
    );
    close_editor(&mut other).expect("close");
    other.idle();

    // 2. A 2× display: the same logical size, twice the pixels.
    parent.set_xft_dpi(192).expect("set Xft.dpi");
    let _ = std::fs::remove_file(&layout);
    open_editor(&mut other, &parent).expect("open on the 2x display");
    wait_until(
        &mut other,
        "the window on the 2x display is twice as large",
        |_| parent.child_sizes().unwrap_or_default() == [(2 * w1, 2 * h1)],
    );
    wait_until(&mut other, "egui draws at 2 pixels per point", |_| {
        pixels_per_point(&layout) == Some(2.0)
    });
    let size = editor_size(&mut other).expect("size");
    assert_eq!(
        (size.width, size.height),
        (2 * w1, 2 * h1),
        "the size the plugin reports on the 2x display (physical pixels)"
    );
    assert_eq!(
        saved_size(&other.save_state().expect("save")),
        Some((w1, h1)),
        "the saved size is logical"
    );
    close_editor(&mut other).expect("close");
    other.idle();
    eprintln!(
        "editor window size: {w0}x{h0} → {w1}x{h1}, saved and reloaded; 2x display: {}x{}; \
         {:.1} s",
        2 * w1,
        2 * h1,
        t_start.elapsed().as_secs_f64()
    );
}
