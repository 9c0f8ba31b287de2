//! # Layout probe: where the editor's controls are, for GUI tests
//!
//! A test that drives the editor with synthetic mouse input (`tests/tests/editor_screenshot.rs`
//! runs the standalone under Xvfb and clicks with `xdotool`) needs to know where the controls
//! are. When the environment variable [`LAYOUT_ENV`] names a file when the window opens, the
//! editor writes the rectangles of its main controls there whenever they move, one per line:
//!
//! ```text
//! pixels_per_point 1
//! xy_pad 612 96 768 252          # name x0 y0 x1 y1, physical pixels in the window
//! grab_front 842 214 ...
//! ```
//!
//! The file is replaced atomically (written next to it, then renamed). Without the variable
//! the probe does nothing.

use std::fmt::Write as _;
use std::path::PathBuf;

use egui::Rect;

/// Environment variable naming the layout file.
pub const LAYOUT_ENV: &str = "PAPIER_EDITOR_LAYOUT";

/// Collects named rectangles during a frame and writes them out when they changed.
#[derive(Debug, Default)]
pub struct LayoutProbe {
    path: Option<PathBuf>,
    rects: Vec<(&'static str, Rect)>,
    written: String,
}

impl LayoutProbe {
    /// A probe writing to the file named by [`LAYOUT_ENV`], if set.
    pub fn from_env() -> Self {
        Self {
            path: std::env::var_os(LAYOUT_ENV).map(PathBuf::from),
            ..Self::default()
        }
    }

    /// Is the probe writing anywhere?
    pub fn active(&self) -> bool {
        self.path.is_some()
    }

    /// Starts a frame.
    pub fn begin(&mut self) {
        self.rects.clear();
    }

    /// Records a rectangle (logical pixels).
    pub fn record(&mut self, name: &'static str, rect: Rect) {
        if self.active() {
            self.rects.push((name, rect));
        }
    }

    /// The file's text for the recorded rectangles.
    pub fn render(&self, pixels_per_point: f32) -> String {
        let mut s = format!("pixels_per_point {pixels_per_point}\n");
        for (name, r) in &self.rects {
            let p = |v: f32| (v * pixels_per_point).round() as i64;
            let _ = writeln!(
                s,
                "{name} {} {} {} {}",
                p(r.left()),
                p(r.top()),
                p(r.right()),
                p(r.bottom())
            );
        }
        s
    }

    /// Ends a frame: writes the file if anything moved.
    pub fn end(&mut self, pixels_per_point: f32) {
        let Some(path) = &self.path else {
            return;
        };
        let text = self.render(pixels_per_point);
        if text == self.written {
            return;
        }
        let tmp = path.with_extension("tmp");
        if std::fs::write(&tmp, &text).is_ok() && std::fs::rename(&tmp, path).is_ok() {
            self.written = text;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use egui::{pos2, vec2};

    #[test]
    fn renders_physical_pixels() {
        let mut p = LayoutProbe {
            path: Some(PathBuf::from("unused")),
            ..LayoutProbe::default()
        };
        p.begin();
        p.record(
            "xy_pad",
            Rect::from_min_size(pos2(10.0, 20.5), vec2(100.0, 50.0)),
        );
        assert_eq!(p.render(2.0), "pixels_per_point 2\nxy_pad 20 41 220 141\n");
    }

    #[test]
    fn inactive_probe_records_nothing() {
        let mut p = LayoutProbe::default();
        p.record("x", Rect::ZERO);
        assert!(p.rects.is_empty());
        p.end(1.0);
    }

    #[test]
    fn writes_only_when_the_layout_changes() {
        let dir = std::env::temp_dir().join(format!("papier-probe-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let file = dir.join("layout.txt");
        let mut p = LayoutProbe {
            path: Some(file.clone()),
            ..LayoutProbe::default()
        };
        p.begin();
        p.record("a", Rect::from_min_size(pos2(0.0, 0.0), vec2(1.0, 1.0)));
        p.end(1.0);
        assert_eq!(
            std::fs::read_to_string(&file).unwrap(),
            "pixels_per_point 1\na 0 0 1 1\n"
        );
        std::fs::remove_file(&file).unwrap();
        p.begin();
        p.record("a", Rect::from_min_size(pos2(0.0, 0.0), vec2(1.0, 1.0)));
        p.end(1.0);
        assert!(!file.exists(), "unchanged layout is not rewritten");
        let _ = std::fs::remove_dir_all(&dir);
    }
}
