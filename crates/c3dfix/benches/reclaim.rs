//! What the reclaim stage adds to a repair (issue 47: at most 10 %): the library's repair
//! of c3d-labs trials with `reclaim: Off` and with the default `Report`, in the same run, and
//! their ratio. The three MOtoNMS trials carry 29–36 unlabelled points beside their
//! markers' gaps; MOtoNMS' `Walking1` and BMC's gait trial have none (the stage returns
//! before reading anything).
//!
//! `cargo bench -p c3dfix --bench reclaim` (corpora as for the tests). Each trial is
//! repaired in memory from a fresh copy (the copy not timed), so reading and writing the
//! file are left out: the ratio is of the repair alone, stricter than the command's.
//! After criterion's figures (wall time), a line per trial gives the ratio of the medians of
//! 25 runs of each, taken in turn so that the machine's load falls on both alike, in the
//! process's CPU time (what `perf stat -e task-clock` counts) and in wall time.

use c3dfix::{repair, ReclaimMode, RepairOptions};
use criterion::{criterion_group, criterion_main, BatchSize, BenchmarkId, Criterion};
use std::hint::black_box;
use std::path::Path;
use std::time::{Duration, Instant};

const TRIALS: [&str; 5] = [
    "RehabEngGroup__MOtoNMS__Fast_Walking.c3d",
    "RehabEngGroup__MOtoNMS__Cross_-_Overs_2.c3d",
    "RehabEngGroup__MOtoNMS__Running_1.c3d",
    "RehabEngGroup__MOtoNMS__Walking1.c3d",
    "BMClab__BMC__Gait.c3d",
];

fn trials() -> Vec<(&'static str, c3d::C3d)> {
    let Some(dir) = testkit::c3d_labs() else {
        return Vec::new();
    };
    TRIALS
        .iter()
        .filter_map(|&name| {
            let c = c3dfix::open(dir.join(name)).ok()?;
            Some((name.trim_end_matches(".c3d"), c))
        })
        .collect()
}

fn options(reclaim: ReclaimMode) -> RepairOptions {
    RepairOptions {
        reclaim,
        ..RepairOptions::default()
    }
}

/// The process's CPU time (every thread's, as `perf stat -e task-clock` counts it): on a
/// machine others load, a repair's wall time says more of them than of it.
fn cpu_time() -> Duration {
    let mut t = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: `t` is a valid timespec for the call to fill.
    let ok = unsafe { libc::clock_gettime(libc::CLOCK_PROCESS_CPUTIME_ID, &mut t) } == 0;
    assert!(ok, "clock_gettime(CLOCK_PROCESS_CPUTIME_ID) failed");
    Duration::new(t.tv_sec as u64, t.tv_nsec as u32)
}

/// One repair of a fresh copy of `trial`: its wall time and CPU time.
fn run(trial: &c3d::C3d, opts: &RepairOptions) -> (Duration, Duration) {
    let mut c = trial.clone();
    let (t, cpu) = (Instant::now(), cpu_time());
    black_box(repair(&mut c, opts, Path::new("bench.c3d")).expect("repair"));
    (t.elapsed(), cpu_time() - cpu)
}

fn median(v: impl Iterator<Item = Duration>) -> Duration {
    let mut v: Vec<Duration> = v.collect();
    v.sort();
    v[v.len() / 2]
}

fn bench(c: &mut Criterion) {
    let modes = [("off", ReclaimMode::Off), ("report", ReclaimMode::Report)];
    let trials = trials();
    let mut g = c.benchmark_group("repair_reclaim");
    g.measurement_time(Duration::from_secs(4)).sample_size(20);
    for (name, trial) in &trials {
        for (label, mode) in modes {
            let opts = options(mode);
            g.bench_with_input(BenchmarkId::new(label, name), trial, |b, t| {
                b.iter_batched_ref(
                    || t.clone(),
                    |c| repair(black_box(c), &opts, Path::new("bench.c3d")).expect("repair"),
                    BatchSize::LargeInput,
                )
            });
        }
    }
    g.finish();
    for (name, trial) in &trials {
        let (off, report) = (options(ReclaimMode::Off), options(ReclaimMode::Report));
        let (mut a, mut b) = (Vec::new(), Vec::new());
        for _ in 0..25 {
            a.push(run(trial, &off));
            b.push(run(trial, &report));
        }
        let ms = |d: Duration| d.as_secs_f64() * 1e3;
        let wall = (median(a.iter().map(|x| x.0)), median(b.iter().map(|x| x.0)));
        let cpu = (median(a.iter().map(|x| x.1)), median(b.iter().map(|x| x.1)));
        eprintln!(
            "reclaim report / off  {name}: cpu {:.2} / {:.2} ms = {:.3}, wall {:.2} / {:.2} ms = {:.3}",
            ms(cpu.1),
            ms(cpu.0),
            ms(cpu.1) / ms(cpu.0),
            ms(wall.1),
            ms(wall.0),
            ms(wall.1) / ms(wall.0)
        );
    }
}

criterion_group!(benches, bench);
criterion_main!(benches);
