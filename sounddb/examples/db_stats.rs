//! Generates the three default databases and prints timings and sizes:
//! `cargo run -p sounddb --example db_stats` (add `--release` for release timings).
fn main() {
    for m in sounddb::generate::Material::ALL {
        let t = std::time::Instant::now();
        let db = sounddb::generate::generate(m);
        let gen_s = t.elapsed().as_secs_f64();
        let t = std::time::Instant::now();
        let pack = db.to_pack();
        let pack_s = t.elapsed().as_secs_f64();
        let secs: f64 = db
            .units
            .iter()
            .map(|u| u.samples.len() as f64 / 44100.0)
            .sum();
        println!(
            "{}: gen {gen_s:.2}s pack {pack_s:.2}s, {} units {:.1} s audio, pack {:.2} MiB",
            m.name(),
            db.units.len(),
            secs,
            pack.len() as f64 / 1048576.0
        );
        let t = std::time::Instant::now();
        let (back, w) = sounddb::Database::from_pack(&pack, "p").unwrap();
        println!(
            "  reload {:.2}s, {} warnings: {:?}",
            t.elapsed().as_secs_f64(),
            w.len(),
            w.iter().map(|w| w.to_string()).collect::<Vec<_>>()
        );
        let t = std::time::Instant::now();
        let p = sounddb::SoundDb::prepare(&back, 44100.0);
        println!(
            "  prepare44k {:.2}s mem {:.2} MB",
            t.elapsed().as_secs_f64(),
            p.memory_bytes() as f64 / 1e6
        );
        let t = std::time::Instant::now();
        let p = sounddb::SoundDb::prepare(&back, 48000.0);
        println!(
            "  prepare48k {:.2}s mem {:.2} MB",
            t.elapsed().as_secs_f64(),
            p.memory_bytes() as f64 / 1e6
        );
    }
}
