//! What the unloaded level costs: every plate of a trial computed with the default options
//! (the baseline found and removed, which computes each plate's push once more) and with the
//! raw values (`zero_baseline: false`), on three corpus trials: `sample_17`'s 14 Kistler
//! plates (27 s), `walking2`'s two AMTI plates (no ZERO: the quiet stretch is searched) and
//! `TYPE-2a` (FORCE_PLATFORM:ZERO).
//!
//! `cargo bench -p c3dfix --bench platforms` (corpora as for the tests).

use c3dfix::{force_platforms, ForceOptions};
use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use std::hint::black_box;
use std::time::Duration;

fn trials() -> Vec<(&'static str, c3d::C3d)> {
    let mut v = Vec::new();
    let mut add = |name: &'static str, dir: Option<std::path::PathBuf>, rel: &str| {
        if let Some(d) = dir {
            if let Ok(c) = c3dfix::open(d.join(rel)) {
                v.push((name, c));
            }
        }
    };
    add(
        "sample_17",
        testkit::c3d_samples(),
        "sample_17/128analogchannels.c3d",
    );
    add(
        "walking2",
        testkit::c3d_more(),
        "opensim-org__opensim-core__walking2.c3d",
    );
    add("TYPE-2a", testkit::c3d_samples(), "sample_10/TYPE-2a.c3d");
    v
}

fn bench(c: &mut Criterion) {
    let mut g = c.benchmark_group("force_platforms");
    g.measurement_time(Duration::from_secs(5)).sample_size(20);
    let raw = ForceOptions {
        zero_baseline: false,
        ..ForceOptions::default()
    };
    for (name, trial) in trials() {
        for (opts, label) in [(&raw, "raw"), (&ForceOptions::default(), "baseline")] {
            g.bench_with_input(BenchmarkId::new(label, name), &trial, |b, t| {
                b.iter(|| force_platforms(black_box(t), opts).expect("plates"))
            });
        }
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
