//! Time the stages of reading a file: `cargo run --release -p c3d --example time_read FILE`.
use std::time::Instant;
fn main() {
    let Some(path) = std::env::args().nth(1) else {
        eprintln!("usage: time_read FILE");
        std::process::exit(2);
    };
    for _ in 0..3 {
        let t = Instant::now();
        let bytes = match std::fs::read(&path) {
            Ok(b) => b,
            Err(e) => {
                eprintln!("{path}: {e}");
                std::process::exit(2);
            }
        };
        let t_read = t.elapsed();
        let t = Instant::now();
        let c = c3d::read(bytes);
        let t_parse = t.elapsed();
        let frames = c.map(|c| c.points().frames()).unwrap_or(0);
        let t = Instant::now();
        let whole = c3d::read_file(&path).map(|c| c.points().frames());
        let t_whole = t.elapsed();
        println!(
            "fs::read {t_read:?}  parse+decode {t_parse:?}  ({frames} frames); read_file {t_whole:?} ({})",
            whole.map_or_else(|e| e.to_string(), |f| format!("{f} frames"))
        );
    }
}
