//! Hostile edits of a saved sheet's JSON, shared by `tests/save_restore.rs`
//! (`random_json_mutations_never_panic`) and the lab's `fuzz-restore` (the same, longer:
//! `cargo run --release -p papier-lab -- fuzz-restore`, which includes this file).

use rand::RngExt;
use serde_json::Value;

/// Edits one random leaf of `v`: a hostile value (10³⁰⁰, −1, 0, 2⁶⁴ − 1, 2³¹, 0.5, text or
/// null), a plausible neighbour of a number (±1, sign-flipped, ×1.001), or an array truncated
/// or with a member duplicated.
pub fn mutate(v: &mut Value, rng: &mut rand_pcg::Pcg32) {
    match v {
        Value::Object(m) if !m.is_empty() => {
            let k = rng.random_range(0..m.len());
            let key = m.keys().nth(k).unwrap().clone();
            mutate(m.get_mut(&key).unwrap(), rng);
        }
        Value::Array(a) if !a.is_empty() => match rng.random_range(0..8u32) {
            0 => {
                let n = rng.random_range(0..a.len());
                a.truncate(n);
            }
            1 => {
                let i = rng.random_range(0..a.len());
                let x = a[i].clone();
                a.push(x);
            }
            _ => {
                let i = rng.random_range(0..a.len());
                mutate(&mut a[i], rng);
            }
        },
        Value::Number(n) if rng.random_range(0..2u32) == 0 => {
            // A plausible neighbour: nudged, sign-flipped or scaled.
            let x = n.as_f64().unwrap_or(0.0);
            let y = match rng.random_range(0..4u32) {
                0 => x + 1.0,
                1 => -x,
                2 => x * 1.001,
                _ => x - 1.0,
            };
            *v = if n.is_u64() && y >= 0.0 && y.fract() == 0.0 {
                Value::from(y as u64)
            } else {
                Value::from(y)
            };
        }
        _ => {
            *v = match rng.random_range(0..8u32) {
                0 => Value::from(1e300),
                1 => Value::from(-1),
                2 => Value::from(0),
                3 => Value::from(u64::MAX),
                4 => Value::from("x"),
                5 => Value::from(0.5),
                6 => Value::from(1u32 << 31),
                _ => Value::Null,
            };
        }
    }
}
