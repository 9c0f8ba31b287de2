//! Seeded random gesture performances that end held still: the family the rest tests and the
//! lab's `rest-family` play (a trend that holds on one scene is not a trend).
//!
//! Each performance, from its seed: a sheet of a random size and paper; one to three grabs
//! (back, front, left, right edge, four corners) taken at 0.2 s with a random grip; one to four
//! of crumple, slide, lift, twist and a shake burst, each ramped from rest to a random value
//! (a shake back to rest) over 0.5–2.5 s, starting at 0.3–1.5 s; then nothing changes for
//! `hold_s`. The performance is a script ([`Performance::toml`]), so a failing one can be
//! written out and played again (`papier-render --script`, `papier-lab rest-probe`).

use rand::{RngExt, SeedableRng};
use sim_core::script::Script;

/// One performance of the family.
pub struct Performance {
    /// Its seed.
    pub seed: u64,
    /// The script, as TOML.
    pub toml: String,
    /// When the last gesture stops changing, seconds.
    pub last_change_s: f64,
}

impl Performance {
    /// The script.
    pub fn script(&self) -> Script {
        Script::parse(&self.toml).expect("a family performance parses")
    }
}

/// The performance of `seed`, held still for `hold_s` after its last change.
pub fn performance(seed: u64, hold_s: f64) -> Performance {
    let mut rng = rand_pcg::Pcg32::seed_from_u64(0x5e57_0000 ^ seed);
    let size = ["a4", "a5", "a6", "sq10"][rng.random_range(0..4)];
    let material = ["printer", "tracing", "banknote"][rng.random_range(0..3)];
    let mut toml = format!(
        "# rest family, seed {seed}\nversion = 1\n\n[set]\nsize = \"{size}\"\n\
         material = \"{material}\"\nseed = {}\n",
        seed % 65_536
    );
    let mut slots = vec!["back", "front", "left", "right", "corners"];
    let grabs = rng.random_range(1..=3);
    for _ in 0..grabs {
        let slot = slots.remove(rng.random_range(0..slots.len()));
        let velocity: f64 = rng.random_range(0.3..1.0);
        toml += &format!("\n[[grab]]\nslot = \"{slot}\"\non_s = 0.2\nvelocity = {velocity:.3}\n");
    }
    let mut gestures = vec!["crumple", "slide", "lift", "twist", "shake"];
    let n = rng.random_range(1..=4);
    let mut last_change_s: f64 = 0.2;
    for _ in 0..n {
        let g = gestures.remove(rng.random_range(0..gestures.len()));
        let t0: f64 = rng.random_range(0.3..1.5);
        let t1 = t0 + rng.random_range(0.5..2.5);
        last_change_s = last_change_s.max(t1);
        match g {
            "shake" => {
                let depth: f64 = rng.random_range(0.2..1.0);
                let rate: f64 = rng.random_range(0.5..8.0);
                toml += &format!(
                    "\n[[lane]]\nid = \"shake_rate_hz\"\ninterp = \"step\"\n\
                     points = [[0.0, {rate:.3}]]\n\n[[lane]]\nid = \"shake_depth\"\n\
                     interp = \"linear\"\npoints = [[{t0:.3}, 0.0], [{:.3}, {depth:.3}], \
                     [{t1:.3}, 0.0]]\n",
                    0.5 * (t0 + t1)
                );
            }
            _ => {
                let v: f64 = if g == "twist" {
                    rng.random_range(-1.0..1.0)
                } else {
                    rng.random_range(0.1..1.0)
                };
                toml += &format!(
                    "\n[[lane]]\nid = \"{g}\"\ninterp = \"linear\"\n\
                     points = [[{t0:.3}, 0.0], [{t1:.3}, {v:.3}]]\n"
                );
            }
        }
    }
    toml = toml.replacen(
        "version = 1\n",
        &format!("version = 1\nduration_s = {:.3}\n", last_change_s + hold_s),
        1,
    );
    Performance {
        seed,
        toml,
        last_change_s,
    }
}
