//! Screenshots of X windows as RGB images: captured with ImageMagick's `import` (saved as PNG
//! for people and CI artefacts) and decoded through `convert … ppm:-` (a trivial format to
//! read), so the tests need no image crate.

use std::path::Path;

use crate::xvfb::{Xvfb, require_tool};

/// An 8-bit RGB image.
#[derive(Clone, Debug, PartialEq)]
pub struct Image {
    /// Width, pixels.
    pub width: u32,
    /// Height, pixels.
    pub height: u32,
    /// Row-major RGB bytes.
    pub rgb: Vec<u8>,
}

/// A pixel rectangle `[x0, x1) × [y0, y1)`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PixelRect {
    /// Left, inclusive.
    pub x0: i64,
    /// Top, inclusive.
    pub y0: i64,
    /// Right, exclusive.
    pub x1: i64,
    /// Bottom, exclusive.
    pub y1: i64,
}

impl PixelRect {
    /// Width × height.
    pub fn area(&self) -> i64 {
        (self.x1 - self.x0).max(0) * (self.y1 - self.y0).max(0)
    }

    /// The centre.
    pub fn centre(&self) -> (i64, i64) {
        ((self.x0 + self.x1) / 2, (self.y0 + self.y1) / 2)
    }

    /// Shrunk by `m` pixels on every side.
    pub fn shrink(&self, m: i64) -> Self {
        Self {
            x0: self.x0 + m,
            y0: self.y0 + m,
            x1: self.x1 - m,
            y1: self.y1 - m,
        }
    }
}

/// Parses a binary PPM (P6, maxval 255).
pub fn parse_ppm(bytes: &[u8]) -> Result<Image, String> {
    let mut fields = Vec::new();
    let mut i = 0;
    while fields.len() < 4 {
        while i < bytes.len() && bytes[i].is_ascii_whitespace() {
            i += 1;
        }
        if i < bytes.len() && bytes[i] == b'#' {
            while i < bytes.len() && bytes[i] != b'\n' {
                i += 1;
            }
            continue;
        }
        let start = i;
        while i < bytes.len() && !bytes[i].is_ascii_whitespace() {
            i += 1;
        }
        if start == i {
            return Err("truncated PPM header".into());
        }
        fields.push(String::from_utf8_lossy(&bytes[start..i]).into_owned());
    }
    i += 1; // the single whitespace after maxval
    if fields[0] != "P6" || fields[3] != "255" {
        return Err(format!("not an 8-bit P6 PPM: {fields:?}"));
    }
    let width: u32 = fields[1].parse().map_err(|_| "bad width")?;
    let height: u32 = fields[2].parse().map_err(|_| "bad height")?;
    let n = (width * height * 3) as usize;
    let rgb = bytes.get(i..i + n).ok_or("truncated PPM data")?.to_vec();
    Ok(Image { width, height, rgb })
}

impl Image {
    /// Decodes an image file with ImageMagick.
    pub fn load(path: &Path) -> Result<Self, String> {
        require_tool("convert", "imagemagick");
        let out = std::process::Command::new("convert")
            .arg(path)
            .args(["-depth", "8", "ppm:-"])
            .output()
            .map_err(|e| format!("convert: {e}"))?;
        if !out.status.success() {
            return Err(String::from_utf8_lossy(&out.stderr).into_owned());
        }
        parse_ppm(&out.stdout)
    }

    /// Captures window `id` (or the root window) of `x` to a PNG at `png` and decodes it.
    pub fn capture(x: &Xvfb, window: Option<u64>, png: &Path) -> Result<Self, String> {
        require_tool("import", "imagemagick");
        if let Some(dir) = png.parent() {
            std::fs::create_dir_all(dir).map_err(|e| e.to_string())?;
        }
        let target = window.map_or("root".to_owned(), |id| format!("0x{id:x}"));
        x.run("import", &["-window", &target, &png.to_string_lossy()])?;
        Self::load(png)
    }

    /// The pixel at (x, y).
    pub fn pixel(&self, x: u32, y: u32) -> [u8; 3] {
        let i = ((y * self.width + x) * 3) as usize;
        [self.rgb[i], self.rgb[i + 1], self.rgb[i + 2]]
    }

    /// `r` clipped to the image.
    pub fn clip(&self, r: PixelRect) -> PixelRect {
        PixelRect {
            x0: r.x0.clamp(0, i64::from(self.width)),
            y0: r.y0.clamp(0, i64::from(self.height)),
            x1: r.x1.clamp(0, i64::from(self.width)),
            y1: r.y1.clamp(0, i64::from(self.height)),
        }
    }

    /// Pixels of `r` for which `f` holds.
    pub fn count(&self, r: PixelRect, f: impl Fn([u8; 3]) -> bool) -> usize {
        let r = self.clip(r);
        let mut n = 0;
        for y in r.y0..r.y1 {
            for x in r.x0..r.x1 {
                if f(self.pixel(x as u32, y as u32)) {
                    n += 1;
                }
            }
        }
        n
    }

    /// The mask of `f` over `r`, row-major.
    pub fn mask(&self, r: PixelRect, f: impl Fn([u8; 3]) -> bool) -> Vec<bool> {
        let r = self.clip(r);
        let mut m = Vec::with_capacity(r.area() as usize);
        for y in r.y0..r.y1 {
            for x in r.x0..r.x1 {
                m.push(f(self.pixel(x as u32, y as u32)));
            }
        }
        m
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ppm_round_trip() {
        let mut bytes = b"P6\n# comment\n2 1\n255\n".to_vec();
        bytes.extend_from_slice(&[1, 2, 3, 4, 5, 6]);
        let img = parse_ppm(&bytes).unwrap();
        assert_eq!((img.width, img.height), (2, 1));
        assert_eq!(img.pixel(1, 0), [4, 5, 6]);
        let all = PixelRect {
            x0: -5,
            y0: 0,
            x1: 10,
            y1: 10,
        };
        assert_eq!(img.count(all, |p| p[0] > 0), 2);
        assert!(parse_ppm(b"P3\n1 1\n255\n").is_err());
        assert!(parse_ppm(b"P6\n2 2\n255\n\x01").is_err());
    }
}
