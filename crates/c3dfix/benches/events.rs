//! Gait events of a trial after reading (the budget: 50 ms): `auto` (plates and
//! markers) and `kinematics` on the corpora's walking trials with plates and Nexus events,
//! and on the repository's synthetic walk (400 frames, no plates) where no corpus is around.
//!
//! `cargo bench -p c3dfix --bench events` (C3D_MORE etc. as for the tests).

use c3dfix::events::{detect_events, EventOptions, EventSource};
use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use std::path::PathBuf;

fn trials() -> Vec<PathBuf> {
    let mut v = vec![testkit::workspace_root().join("sample_c3d/walk_truth.c3d")];
    if let Some(more) = testkit::c3d_more() {
        for name in [
            "tsalemink__C3D-parser__RBWH_bfnd_w1.c3d",
            "HansUniVie__MuscleLength__test.c3d",
            "opensim-org__opensim-core__walking2.c3d",
        ] {
            v.push(more.join(name));
        }
    }
    v
}

fn events(c: &mut Criterion) {
    let mut g = c.benchmark_group("events");
    for path in trials() {
        let Ok(trial) = c3dfix::open(&path) else {
            continue;
        };
        let name = path
            .file_name()
            .map(|n| n.to_string_lossy().to_string())
            .unwrap_or_default();
        for from in [EventSource::Auto, EventSource::Kinematics] {
            let opts = EventOptions {
                from,
                ..EventOptions::default()
            };
            // A trial the detector refuses is no timing.
            if detect_events(&trial, &opts, &path).is_err() {
                continue;
            }
            g.bench_with_input(
                BenchmarkId::new(format!("{from:?}").to_lowercase(), &name),
                &trial,
                |b, t| b.iter(|| detect_events(t, &opts, &path)),
            );
        }
    }
    g.finish();
}

criterion_group!(benches, events);
criterion_main!(benches);
