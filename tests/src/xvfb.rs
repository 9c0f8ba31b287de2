//! A private virtual X server (Xvfb) for the GUI tests, and the X command-line tools they use
//! (`xwininfo`, `xdotool`, `import`, `convert`; Debian packages `xvfb`, `x11-utils`,
//! `xdotool`, `imagemagick`, installed by `cargo xtask test` and `.ci/run`).
//!
//! [`Xvfb::start`] picks a free display number, starts the server and waits until it accepts
//! connections; dropping the [`Xvfb`] stops it when the test process has exited. Tools run with
//! `DISPLAY` set to it.

use std::path::Path;
use std::process::{Child, Command, Output, Stdio};
use std::time::{Duration, Instant};

/// A running Xvfb.
pub struct Xvfb {
    child: Child,
    /// Display number.
    pub number: u32,
}

/// Fails with a helpful message if a command-line tool is missing.
pub fn require_tool(tool: &str, package: &str) {
    let found = std::env::var_os("PATH")
        .map(|paths| std::env::split_paths(&paths).any(|d| d.join(tool).is_file()))
        .unwrap_or(false);
    assert!(
        found,
        "`{tool}` is missing; install the Debian package `{package}` (cargo xtask test does)"
    );
}

impl Xvfb {
    /// Starts a server with one `width`×`height`×24 screen.
    pub fn start(width: u32, height: u32) -> Result<Self, String> {
        require_tool("Xvfb", "xvfb");
        for number in 90..200 {
            let socket = format!("/tmp/.X11-unix/X{number}");
            if Path::new(&format!("/tmp/.X{number}-lock")).exists() || Path::new(&socket).exists() {
                continue;
            }
            let mut child = Command::new("Xvfb")
                .arg(format!(":{number}"))
                .args(["-screen", "0", &format!("{width}x{height}x24")])
                .args(["-nolisten", "tcp", "-noreset"])
                .stdin(Stdio::null())
                .stdout(Stdio::null())
                .stderr(Stdio::null())
                .spawn()
                .map_err(|e| format!("cannot start Xvfb: {e}"))?;
            let t0 = Instant::now();
            loop {
                if let Ok(Some(_)) = child.try_wait() {
                    break; // Lost the race for this number: try the next one.
                }
                // A client connection (through the socket file, or the abstract socket a
                // server started without root may be left with) means the server is ready.
                if x11rb::connect(Some(&format!(":{number}"))).is_ok() {
                    return Ok(Self { child, number });
                }
                if t0.elapsed() > Duration::from_secs(30) {
                    let _ = child.kill();
                    let _ = child.wait();
                    return Err(format!("Xvfb :{number} did not come up in 30 s"));
                }
                std::thread::sleep(Duration::from_millis(20));
            }
        }
        Err("no free X display number in 90..200".into())
    }

    /// The `DISPLAY` value.
    pub fn display(&self) -> String {
        format!(":{}", self.number)
    }

    /// A command with `DISPLAY` set to this server.
    pub fn command(&self, program: &str) -> Command {
        let mut c = Command::new(program);
        c.env("DISPLAY", self.display());
        c
    }

    /// Runs a tool on this display; its stdout on success.
    pub fn run(&self, program: &str, args: &[&str]) -> Result<String, String> {
        let out: Output = self
            .command(program)
            .args(args)
            .output()
            .map_err(|e| format!("{program}: {e}"))?;
        if !out.status.success() {
            return Err(format!(
                "{program} {}: {}{}",
                args.join(" "),
                String::from_utf8_lossy(&out.stdout),
                String::from_utf8_lossy(&out.stderr)
            ));
        }
        Ok(String::from_utf8_lossy(&out.stdout).into_owned())
    }
}

impl Drop for Xvfb {
    /// Stops the server once this test process has exited, not before: a library may keep an
    /// X connection open until the process ends (and Xlib ends a process whose server went
    /// away with exit status 1, turning a passed test into a failed binary). A small watcher
    /// waits for the process to go and then stops the server; if the watcher cannot be
    /// started, the server is stopped now.
    fn drop(&mut self) {
        let script = format!(
            "while kill -0 {} 2>/dev/null; do sleep 0.1; done; kill {} 2>/dev/null",
            std::process::id(),
            self.child.id()
        );
        let watcher = Command::new("sh")
            .args(["-c", &script])
            .stdin(Stdio::null())
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn();
        if watcher.is_err() {
            let _ = self.child.kill();
            let _ = self.child.wait();
        }
    }
}

/// A top-level window found by name, with its position on the screen.
#[derive(Clone, Debug, PartialEq)]
pub struct WindowInfo {
    /// X window id.
    pub id: u64,
    /// Left edge, pixels.
    pub x: i32,
    /// Top edge, pixels.
    pub y: i32,
    /// Width, pixels.
    pub width: u32,
    /// Height, pixels.
    pub height: u32,
}

fn field<T: std::str::FromStr>(text: &str, key: &str) -> Option<T> {
    text.lines()
        .find_map(|l| l.trim().strip_prefix(key))
        .and_then(|v| v.trim().parse().ok())
}

/// Parses `xwininfo -name …` output.
pub fn parse_xwininfo(text: &str) -> Option<WindowInfo> {
    let id_line = text.lines().find(|l| l.contains("Window id:"))?;
    let hex = id_line
        .split("Window id:")
        .nth(1)?
        .split_whitespace()
        .next()?;
    let id = u64::from_str_radix(hex.trim_start_matches("0x"), 16).ok()?;
    Some(WindowInfo {
        id,
        x: field(text, "Absolute upper-left X:")?,
        y: field(text, "Absolute upper-left Y:")?,
        width: field(text, "Width:")?,
        height: field(text, "Height:")?,
    })
}

impl Xvfb {
    /// Waits (up to `timeout`) for a window named `name` and returns where it is.
    pub fn wait_for_window(&self, name: &str, timeout: Duration) -> Result<WindowInfo, String> {
        require_tool("xwininfo", "x11-utils");
        let t0 = Instant::now();
        loop {
            if let Ok(text) = self.run("xwininfo", &["-name", name])
                && let Some(w) = parse_xwininfo(&text)
                && w.width > 1
            {
                return Ok(w);
            }
            if t0.elapsed() > timeout {
                return Err(format!("no window named {name:?} after {timeout:?}"));
            }
            std::thread::sleep(Duration::from_millis(100));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_xwininfo() {
        let text = "\nxwininfo: Window id: 0x200003 \"Papier\"\n\n  Absolute upper-left X:  0\n  \
                    Absolute upper-left Y:  12\n  Relative upper-left X:  0\n  Width: 1060\n  \
                    Height: 720\n";
        assert_eq!(
            parse_xwininfo(text),
            Some(WindowInfo {
                id: 0x200003,
                x: 0,
                y: 12,
                width: 1060,
                height: 720
            })
        );
        assert_eq!(parse_xwininfo("xwininfo: error"), None);
    }
}
