//! Repair speed on a synthetic trial of 100 markers × 10 000 frames with 5 % of samples in
//! gaps of 2–30 frames: each fill method alone, and the whole pipeline (Hampel spikes,
//! auto fill, 4th-order 6 Hz Butterworth).
//! Run: `cargo bench -p repair -- pipeline` (or `-- fill/` for the methods).

use criterion::{criterion_group, criterion_main, BatchSize, Criterion};
use repair::synth::{gait_like, knock_out};
use repair::{
    repair_trial, FillMethod, FillOptions, FilterSpec, RepairConfig, SpikeOptions, Trial,
};
use std::time::Duration;

fn trial() -> Trial {
    let mut t = gait_like(100, 8, 10_000, 100.0, 0.3, 42);
    knock_out(&mut t, 0.05, 2, 30, 43);
    t
}

fn bench(c: &mut Criterion) {
    let t = trial();
    let mut g = c.benchmark_group("fill");
    g.sample_size(10).measurement_time(Duration::from_secs(10));
    for m in [
        FillMethod::Linear,
        FillMethod::Lagrange5,
        FillMethod::Spline,
        FillMethod::Rigid,
        FillMethod::Pattern,
        FillMethod::Pca,
        FillMethod::Kalman,
        FillMethod::Auto,
    ] {
        let fill = FillOptions {
            method: m,
            ..FillOptions::default()
        };
        let cfg = RepairConfig::new(None, fill, None).expect("valid config");
        g.bench_function(format!("{m:?}").to_lowercase(), |b| {
            b.iter_batched(
                || t.clone(),
                |mut x| repair_trial(&mut x, &cfg).expect("repairs"),
                BatchSize::LargeInput,
            )
        });
    }
    g.finish();

    let cfg = RepairConfig::new(
        Some(SpikeOptions::default()),
        FillOptions::default(),
        Some(FilterSpec::Butterworth {
            order: 4,
            cutoff_hz: 6.0,
        }),
    )
    .expect("valid config");
    let mut g = c.benchmark_group("pipeline");
    g.sample_size(10).measurement_time(Duration::from_secs(15));
    g.bench_function("spikes+auto+butter4_100x10000", |b| {
        b.iter_batched(
            || t.clone(),
            |mut x| repair_trial(&mut x, &cfg).expect("repairs"),
            BatchSize::LargeInput,
        )
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
