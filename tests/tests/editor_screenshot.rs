//! The editor on screen: the standalone application (`target/release/papier`, dummy audio
//! backend) runs under a private Xvfb; the test waits for its window, checks that the 3D view
//! shows the sheet and that text was drawn, then plays a gesture through the editor's own
//! controls with `xdotool` (Hold on, grab the front edge, drag the XY pad up and right), and
//! checks that the sheet on screen changed accordingly: it moved, parts of it are now curved,
//! and the held vertices are marked. Then it holds the phrase pad's first button (the page turn)
//! and checks that the phrase plays: the sheet on screen changes again, with held vertices.
//!
//! The standalone receives no MIDI and its dummy backend runs `process()` at real-time pace,
//! so this is the whole path: editor → GUI queue / host parameters → audio thread → simulation
//! worker → the editor's view buffer → the screen.
//!
//! Where the controls are comes from the editor's layout probe (`PAPIER_EDITOR_LAYOUT`, see
//! `papier::editor::layout_probe`). The screenshots are kept as CI artefacts:
//! `target/ci-artifacts/editor-start.png` and `target/ci-artifacts/editor.png` (the README's
//! `docs/editor.png` is a copy of the latter).
//!
//! Sheet pixels are recognised by colour: a pixel is the sheet if it is one of the region
//! colours (or its back-face tint) under some lighting, i.e. all three channels are the same
//! fraction (from the ambient level to 1, up to rounding) of the base colour. The table, the
//! background, the room lines, antialiased edges between them and the UI's greys all fail that
//! test. Only the scene is searched: the legend and the top-view inset drawn over it (which
//! show the same colours) are left out, using their rectangles from the layout probe.

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::process::{Child, Stdio};
use std::time::{Duration, Instant};

use papier::editor::region::{HANDLE_DOT_COLOUR, RegionKind};
use papier::editor::shading::{AMBIENT, BACK_TINT, BACK_TINT_AMOUNT, blend};
use papier_tests::clap::serial;
use papier_tests::paths;
use papier_tests::screenshot::{Image, PixelRect};
use papier_tests::xvfb::{Xvfb, require_tool};

/// A sheet on screen covers at least this many pixels of the view (an A4 sheet at the default
/// camera covers ~30 000).
const MIN_SHEET_PX: usize = 5_000;

/// How long to wait for each thing to appear on screen (polling): generous, for loaded
/// machines and a software GL driver.
const PATIENCE: Duration = Duration::from_secs(90);

/// Is `p` the colour `base` lit by some factor? Faces are lit by a factor from the ambient
/// level to 1 (`papier::editor::shading`), rounded per channel; anything else (antialiased
/// edges against the table or the background, text) is off by more than rounding in some
/// channel.
fn lit(base: [u8; 3], p: [u8; 3]) -> bool {
    let k: Vec<f32> = (0..3)
        .map(|i| f32::from(p[i]) / f32::from(base[i]))
        .collect();
    let mean = (k[0] + k[1] + k[2]) / 3.0;
    (AMBIENT - 0.02..=1.02).contains(&mean)
        && (0..3).all(|i| (k[i] - mean).abs() <= 0.012 + 1.0 / f32::from(base[i]))
}

fn is_kind(kind: RegionKind, p: [u8; 3]) -> bool {
    let c = kind.colour();
    lit(c, p) || lit(blend(c, BACK_TINT, BACK_TINT_AMOUNT), p)
}

/// A curved region seen from its front (the distinctive yellow; its back-face tint is a grey
/// that antialiased outlines can imitate).
fn is_curved_front(p: [u8; 3]) -> bool {
    lit(RegionKind::Curved.colour(), p)
}

fn is_sheet(p: [u8; 3]) -> bool {
    RegionKind::ALL.iter().any(|k| is_kind(*k, p))
}

fn is_handle_dot(p: [u8; 3]) -> bool {
    let c = HANDLE_DOT_COLOUR;
    (0..3).all(|i| (i32::from(p[i]) - i32::from(c[i])).abs() <= 3)
}

/// The layout probe's file: name → rectangles (window pixels).
fn read_layout(path: &Path) -> HashMap<String, Vec<PixelRect>> {
    let mut out: HashMap<String, Vec<PixelRect>> = HashMap::new();
    let Ok(text) = std::fs::read_to_string(path) else {
        return out;
    };
    for line in text.lines() {
        let f: Vec<&str> = line.split_whitespace().collect();
        if f.len() == 5
            && let (Ok(x0), Ok(y0), Ok(x1), Ok(y1)) =
                (f[1].parse(), f[2].parse(), f[3].parse(), f[4].parse())
        {
            out.entry(f[0].to_owned())
                .or_default()
                .push(PixelRect { x0, y0, x1, y1 });
        }
    }
    out
}

/// Runs the standalone and kills it when dropped.
struct App {
    child: Child,
    log: PathBuf,
}

impl App {
    fn log(&self) -> String {
        std::fs::read_to_string(&self.log).unwrap_or_default()
    }
}

impl Drop for App {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// Pixels that are text ink in `r` (light grey on the dark panels: egui's dark theme draws
/// text at grey 140 and brighter, on panels at grey 27), and the largest number of separate
/// runs of ink a row of `r` crosses (about the number of glyphs on a line).
fn ink(img: &Image, r: PixelRect) -> (usize, usize) {
    let bright = |p: [u8; 3]| {
        let (lo, hi) = (p.iter().min().unwrap(), p.iter().max().unwrap());
        *lo >= 100 && hi - lo <= 16
    };
    let count = img.count(r, bright);
    let mut best = 0;
    for y in r.y0..r.y1 {
        let mut runs = 0;
        let mut inside = false;
        for x in r.x0..r.x1 {
            let on = bright(img.pixel(x as u32, y as u32));
            if on && !inside {
                runs += 1;
            }
            inside = on;
        }
        best = best.max(runs);
    }
    (count, best)
}

struct Pointer<'a> {
    x: &'a Xvfb,
    origin: (i64, i64),
}

impl Pointer<'_> {
    fn xdotool(&self, args: &[String]) {
        let a: Vec<&str> = args.iter().map(String::as_str).collect();
        self.x.run("xdotool", &a).expect("xdotool");
    }

    fn move_to(&self, (x, y): (i64, i64)) {
        self.xdotool(&[
            "mousemove".into(),
            (self.origin.0 + x).to_string(),
            (self.origin.1 + y).to_string(),
        ]);
        std::thread::sleep(Duration::from_millis(40));
    }

    /// A click held for 120 ms (several frames), like a person's.
    fn click(&self, at: (i64, i64)) {
        self.move_to(at);
        self.xdotool(&["mousedown".into(), "1".into()]);
        std::thread::sleep(Duration::from_millis(120));
        self.xdotool(&["mouseup".into(), "1".into()]);
        std::thread::sleep(Duration::from_millis(120));
    }

    /// Drags along a straight line in `steps` moves over ~`steps`·30 ms.
    fn drag(&self, from: (i64, i64), to: (i64, i64), steps: i64) {
        self.move_to(from);
        self.xdotool(&["mousedown".into(), "1".into()]);
        std::thread::sleep(Duration::from_millis(60));
        for i in 1..=steps {
            let p = (
                from.0 + (to.0 - from.0) * i / steps,
                from.1 + (to.1 - from.1) * i / steps,
            );
            self.move_to(p);
        }
        std::thread::sleep(Duration::from_millis(60));
        self.xdotool(&["mouseup".into(), "1".into()]);
    }
}

/// The 3D view's scene: its rectangle less the legend and the room map drawn over it.
struct Scene {
    view: PixelRect,
    overlays: Vec<PixelRect>,
}

impl Scene {
    fn in_scene(&self, x: i64, y: i64) -> bool {
        !self
            .overlays
            .iter()
            .any(|o| (o.x0..o.x1).contains(&x) && (o.y0..o.y1).contains(&y))
    }

    /// Scene pixels for which `f` holds.
    fn count(&self, img: &Image, f: impl Fn([u8; 3]) -> bool) -> usize {
        self.mask(img, f).iter().filter(|m| **m).count()
    }

    /// The mask of `f` over the view (false on the overlays), row-major.
    fn mask(&self, img: &Image, f: impl Fn([u8; 3]) -> bool) -> Vec<bool> {
        let r = img.clip(self.view);
        let mut m = Vec::with_capacity(r.area() as usize);
        for y in r.y0..r.y1 {
            for x in r.x0..r.x1 {
                m.push(self.in_scene(x, y) && f(img.pixel(x as u32, y as u32)));
            }
        }
        m
    }
}

fn one(layout: &HashMap<String, Vec<PixelRect>>, name: &str) -> PixelRect {
    *layout
        .get(name)
        .and_then(|v| v.first())
        .unwrap_or_else(|| panic!("the layout probe has no {name:?}: {layout:?}"))
}

#[test]
fn editor_shows_the_sheet_and_follows_a_gesture_played_on_its_controls() {
    let _serial = serial();
    let t_start = Instant::now();
    let app_path = paths::standalone();
    require_tool("xdotool", "xdotool");
    let x = Xvfb::start(1280, 800).expect("Xvfb");
    let scratch = paths::scratch("editor_screenshot");
    let shots = paths::target_dir().join("ci-artifacts");
    let layout_file = scratch.join("layout.txt");
    let log = scratch.join("papier.log");
    let mut app = App {
        child: x
            .command(app_path.to_str().unwrap())
            .args([
                "--backend",
                "dummy",
                "--sample-rate",
                "48000",
                "--period-size",
                "512",
            ])
            .env("PAPIER_EDITOR_LAYOUT", &layout_file)
            .stdin(Stdio::null())
            .stdout(std::fs::File::create(&log).unwrap())
            .stderr(std::fs::File::create(scratch.join("papier.stderr")).unwrap())
            .spawn()
            .expect("start the standalone"),
        log,
    };
    let window = x
        .wait_for_window("Papier", PATIENCE)
        .unwrap_or_else(|e| panic!("{e}; log:\n{}", app.log()));

    // The layout probe writes once the first frame is laid out.
    let t0 = Instant::now();
    let mut layout = read_layout(&layout_file);
    while !layout.contains_key("view_map") && t0.elapsed() < PATIENCE {
        std::thread::sleep(Duration::from_millis(100));
        layout = read_layout(&layout_file);
    }
    let view = one(&layout, "view").shrink(2);
    assert!(view.area() > 200_000, "the 3D view is large: {view:?}");
    let scene = Scene {
        view,
        overlays: vec![
            one(&layout, "view_legend").shrink(-4),
            one(&layout, "view_map").shrink(-4),
        ],
    };

    // 1. The sheet is in the view (it arrives once the simulation publishes a frame).
    let start_png = shots.join("editor-start.png");
    let t0 = Instant::now();
    let (start, sheet_px) = loop {
        let img = Image::capture(&x, Some(window.id), &start_png).expect("screenshot");
        let n = scene.count(&img, is_sheet);
        if n >= MIN_SHEET_PX || t0.elapsed() > PATIENCE {
            break (img, n);
        }
        std::thread::sleep(Duration::from_millis(250));
    };
    assert!(
        sheet_px >= MIN_SHEET_PX,
        "sheet pixels in the view: {sheet_px} (< {MIN_SHEET_PX}); see {}",
        start_png.display()
    );
    assert_eq!(
        scene.count(&start, is_curved_front),
        0,
        "a fresh sheet lying on the table is flat"
    );

    // 2. Text was drawn: the title and the Hold label are ink on the dark panels.
    let (title_ink, title_glyphs) = ink(&start, one(&layout, "title"));
    assert!(
        title_ink >= 60 && title_glyphs >= 4,
        "title text: {title_ink} ink pixels, {title_glyphs} glyph runs"
    );
    let hold = one(&layout, "hold");
    let (hold_ink, _) = ink(&start, hold);
    assert!(hold_ink >= 20, "Hold label ink: {hold_ink}");
    let meters = one(&layout, "meters");
    let (meter_ink, meter_glyphs) = ink(&start, meters);
    assert!(
        meter_ink >= 400 && meter_glyphs >= 20,
        "meter labels and figures: {meter_ink} ink pixels, {meter_glyphs} runs"
    );

    // 3. A gesture on the editor's own controls: Hold on, grab the front edge, drag the XY
    //    pad to slide ≈ 0.45, lift ≈ 0.9.
    let pointer = Pointer {
        x: &x,
        origin: (i64::from(window.x), i64::from(window.y)),
    };
    pointer.click((hold.x0 + 8, hold.centre().1));
    pointer.click(one(&layout, "grab_front").centre());
    let pad = one(&layout, "xy_pad").shrink(10);
    let at = |fx: f64, fy: f64| {
        (
            pad.x0 + ((pad.x1 - pad.x0) as f64 * fx) as i64,
            pad.y1 - ((pad.y1 - pad.y0) as f64 * fy) as i64,
        )
    };
    pointer.drag(at(0.0, 0.0), at(0.45, 0.9), 12);
    // Out of the way, over the title bar's plain text (no hover highlight anywhere).
    let title = one(&layout, "title");
    pointer.move_to((title.x1 + 150, title.centre().1));

    // 4. The sheet follows: it moves, bends (curved region colour appears) and shows its
    //    held vertices.
    let before = scene.mask(&start, is_sheet);
    let png = shots.join("editor.png");
    let t0 = Instant::now();
    let (after, changed, curved, held) = loop {
        std::thread::sleep(Duration::from_millis(300));
        let img = Image::capture(&x, Some(window.id), &png).expect("screenshot");
        let mask = scene.mask(&img, is_sheet);
        let changed = mask.iter().zip(&before).filter(|(a, b)| a != b).count();
        let curved = scene.count(&img, is_curved_front);
        let held = scene.count(&img, is_handle_dot);
        if (changed > sheet_px / 5 && curved > 200 && held > 20) || t0.elapsed() > PATIENCE {
            break (img, changed, curved, held);
        }
    };
    assert!(
        app.child.try_wait().expect("wait").is_none(),
        "the standalone is still running; log:\n{}",
        app.log()
    );
    assert!(
        changed > sheet_px / 5,
        "the sheet on screen changed by only {changed} pixels (of {sheet_px}); see {}",
        png.display()
    );
    assert!(curved > 200, "curved-region pixels after lifting: {curved}");
    assert!(held > 20, "held-vertex dots: {held} pixels");
    assert!(scene.count(&after, is_sheet) >= MIN_SHEET_PX / 2);

    // 5. The phrase pad: its first button (C4, the page turn) held down plays the phrase — a
    //    fresh sheet whose right edge is taken and lifted over: the sheet on screen changes
    //    again, with held vertices, and the meters count the hit.
    let phrase = one(&layout, "phrase_first");
    assert!(
        phrase.y1 < i64::from(window.height) - 40 && phrase.area() > 200,
        "the phrase pad's first button is on screen: {phrase:?} in a {}x{} window",
        window.width,
        window.height
    );
    let lifted = scene.mask(&after, is_sheet);
    pointer.move_to(phrase.centre());
    pointer.xdotool(&["mousedown".into(), "1".into()]);
    std::thread::sleep(Duration::from_millis(400));
    pointer.xdotool(&["mouseup".into(), "1".into()]);
    pointer.move_to((title.x1 + 150, title.centre().1));
    let phrase_png = shots.join("editor-phrase.png");
    let t0 = Instant::now();
    let (moved, dots) = loop {
        std::thread::sleep(Duration::from_millis(150));
        let img = Image::capture(&x, Some(window.id), &phrase_png).expect("screenshot");
        let mask = scene.mask(&img, is_sheet);
        let moved = mask.iter().zip(&lifted).filter(|(a, b)| a != b).count();
        let dots = scene.count(&img, is_handle_dot);
        if (moved > sheet_px / 5 && dots > 20) || t0.elapsed() > PATIENCE {
            break (moved, dots);
        }
    };
    assert!(
        moved > sheet_px / 5 && dots > 20,
        "after the phrase pad: the sheet changed by {moved} pixels, held dots {dots}; see {}",
        phrase_png.display()
    );
    eprintln!(
        "editor screenshot: {}x{} window, sheet {sheet_px} px, changed {changed} px, curved \
         {curved} px, held dots {held} px, title ink {title_ink} px; {:.1} s; {}",
        window.width,
        window.height,
        t_start.elapsed().as_secs_f64(),
        png.display()
    );
    drop(app);
    // Keep the layout next to the screenshot for whoever looks at the artefacts.
    let _ = std::fs::copy(&layout_file, shots.join("editor-layout.txt"));
}
