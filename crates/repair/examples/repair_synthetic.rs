//! Times one full repair of the benchmark's synthetic trial and prints a summary:
//! `cargo run --release -p repair --example repair_synthetic`.

use repair::synth::{gait_like, knock_out};
use repair::{repair_trial, FillOptions, FilterSpec, RepairConfig, SpikeOptions};
use std::time::Instant;

fn main() {
    let mut t = gait_like(100, 8, 10_000, 100.0, 0.3, 42);
    let knocked = knock_out(&mut t, 0.05, 2, 30, 43);
    let cfg = RepairConfig::new(
        Some(SpikeOptions::default()),
        FillOptions::default(),
        Some(FilterSpec::Butterworth {
            order: 4,
            cutoff_hz: 6.0,
        }),
    )
    .expect("valid config");
    let only: Vec<String> = std::env::args().skip(1).collect();
    for m in ["linear", "spline", "rigid", "pattern", "pca", "auto"] {
        if !only.is_empty() && !only.iter().any(|o| o == m) {
            continue;
        }
        let fill = FillOptions {
            method: repair::FillMethod::from_name(m).expect("known"),
            ..FillOptions::default()
        };
        let c = RepairConfig::new(None, fill, None).expect("valid config");
        let mut x = t.clone();
        let start = Instant::now();
        let r = repair_trial(&mut x, &c).expect("repairs");
        println!(
            "fill {m}: {:.3} s ({} unfilled)",
            start.elapsed().as_secs_f64(),
            r.unfilled().count()
        );
        let mut reasons = std::collections::BTreeMap::new();
        for g in r.unfilled() {
            *reasons.entry(format!("{:?}", g.outcome)).or_insert(0) += 1;
        }
        for (k, v) in reasons {
            println!("  {v} × {k}");
        }
    }
    if !only.is_empty() && !only.iter().any(|o| o == "pipeline") {
        return;
    }
    let start = Instant::now();
    let r = repair_trial(&mut t, &cfg).expect("repairs");
    let took = start.elapsed();
    println!(
        "{} samples knocked out, {} gaps ({} unfilled), {} spikes, {} segments: {:.3} s",
        knocked,
        r.gaps.len(),
        r.unfilled().count(),
        r.spikes.len(),
        r.segments.len(),
        took.as_secs_f64()
    );
}
