//! Gait-cycle parameters of a trial after reading (the budget: 50 ms): from the
//! file's own events (Nexus trials of the corpora that carry them) and with the events
//! detected first (`auto`), and on the repository's synthetic walk (detected events) where
//! no corpus is around.
//!
//! `cargo bench -p c3dfix --bench gait_params` (C3D_SAMPLES, C3D_MORE as for the tests).

mod trials;

use c3dfix::{gait_parameters, EventOptions, GaitOptions};
use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};

fn gait(c: &mut Criterion) {
    let mut g = c.benchmark_group("gait_params");
    let more = [
        "HansUniVie__MuscleLength__test.c3d",
        "tsalemink__C3D-parser__RBWH_bfnd_w1.c3d",
    ];
    for trials::Trial { name, path, c3d } in trials::load(&["sample_11/2198928.c3d"], &more) {
        for (label, opts) in [
            ("file_events", GaitOptions::default()),
            (
                "detected",
                GaitOptions {
                    detect: Some(EventOptions::default()),
                    ..GaitOptions::default()
                },
            ),
        ] {
            // A trial without a complete cycle is no timing.
            if gait_parameters(&c3d, &opts, &path).is_err() {
                continue;
            }
            g.bench_with_input(BenchmarkId::new(label, &name), &c3d, |b, t| {
                b.iter(|| gait_parameters(t, &opts, &path))
            });
        }
    }
    g.finish();
}

criterion_group!(benches, gait);
criterion_main!(benches);
