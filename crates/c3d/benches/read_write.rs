//! Read+decode and rewrite throughput: c3dfix against c3dio in the same run, on the corpus
//! files over 300 KB and on the generated 100 000-frame, 100-marker trial
//! (`examples/common/big_trial.rs`). Reading here includes decoding every point and analog
//! sample, as c3dio's load does.
//!
//! `cargo bench -p c3d --bench read_write` (C3D_SAMPLES as for the tests).

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use std::hint::black_box;
use std::time::Duration;

#[path = "../examples/common/big_trial.rs"]
mod big_trial;

fn generated() -> Vec<u8> {
    big_trial::big_trial().expect("generate the 100k-frame trial")
}

/// (name, path, bytes) of every input; both libraries read from the file, as users do.
fn inputs() -> Vec<(String, std::path::PathBuf, Vec<u8>)> {
    let mut v = Vec::new();
    let samples = testkit::c3d_samples();
    let extra = testkit::c3d_extra();
    let mut files = Vec::new();
    for d in [samples, extra].into_iter().flatten() {
        files.extend(testkit::files_with_ext(&d, "c3d"));
    }
    for f in files {
        let Ok(b) = std::fs::read(&f) else { continue };
        // Only files both libraries read are compared.
        if b.len() > 300_000 && c3d::read(b.clone()).is_ok() && c3dio::C3d::from_bytes(&b).is_ok() {
            let name = f
                .file_name()
                .map_or_else(String::new, |n| n.to_string_lossy().into_owned());
            v.push((name, f, b));
        }
    }
    let tmp = std::env::temp_dir().join("c3dfix_bench_generated_100k_x_100.c3d");
    let g = generated();
    std::fs::write(&tmp, &g).expect("write the generated trial");
    v.push(("generated_100k_x_100.c3d".into(), tmp, g));
    v
}

fn bench(c: &mut Criterion) {
    let files = inputs();
    let mut g = c.benchmark_group("read");
    g.measurement_time(Duration::from_secs(2))
        .warm_up_time(Duration::from_millis(300))
        .sample_size(10);
    for (name, path, bytes) in &files {
        g.throughput(Throughput::Bytes(bytes.len() as u64));
        g.bench_with_input(BenchmarkId::new("c3dfix", name), path, |b, path| {
            b.iter(|| {
                black_box(c3d::read_file(path).map(|c| c.points().frames() + c.analog().raw.len()))
            })
        });
        g.bench_with_input(BenchmarkId::new("c3dio", name), path, |b, path| {
            b.iter(|| {
                black_box(
                    c3dio::C3d::load_path(path.clone())
                        .map(|c| c.points.points.rows())
                        .ok(),
                )
            })
        });
    }
    g.finish();
    let mut g = c.benchmark_group("rewrite");
    g.measurement_time(Duration::from_secs(2))
        .warm_up_time(Duration::from_millis(300))
        .sample_size(10);
    for (name, _, bytes) in &files {
        let Ok(file) = c3d::read(bytes.clone()) else {
            continue;
        };
        g.throughput(Throughput::Bytes(bytes.len() as u64));
        g.bench_function(BenchmarkId::new("c3dfix", name), |b| {
            b.iter(|| black_box(file.to_bytes().map(|v| v.len())))
        });
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
