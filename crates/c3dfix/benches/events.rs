//! Gait events of a trial after reading (the budget: 50 ms): `auto` (plates and
//! markers) and `kinematics` on the corpora's walking trials with plates and Nexus events,
//! and on the repository's synthetic walk (400 frames, no plates) where no corpus is around.
//!
//! `cargo bench -p c3dfix --bench events` (C3D_MORE etc. as for the tests).

mod trials;

use c3dfix::events::{detect_events, EventOptions, EventSource};
use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};

fn events(c: &mut Criterion) {
    let mut g = c.benchmark_group("events");
    let more = [
        "tsalemink__C3D-parser__RBWH_bfnd_w1.c3d",
        "HansUniVie__MuscleLength__test.c3d",
        "opensim-org__opensim-core__walking2.c3d",
    ];
    for trials::Trial { name, path, c3d } in trials::load(&[], &more) {
        for from in [EventSource::Auto, EventSource::Kinematics] {
            let opts = EventOptions {
                from,
                ..EventOptions::default()
            };
            // A trial the detector refuses is no timing.
            if detect_events(&c3d, &opts, &path).is_err() {
                continue;
            }
            g.bench_with_input(
                BenchmarkId::new(format!("{from:?}").to_lowercase(), &name),
                &c3d,
                |b, t| b.iter(|| detect_events(t, &opts, &path)),
            );
        }
    }
    g.finish();
}

criterion_group!(benches, events);
criterion_main!(benches);
