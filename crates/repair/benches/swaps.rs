//! Speed of swap and jump finding (issue 34): a synthetic trial of 60 markers × 10 000
//! frames at 100 Hz with three swaps and a jump injected, against the time to read the same
//! trial from a C3D file (float, Intel) and decode its points.
//! Run: `cargo bench -p repair --bench swaps`.

use c3d::{Analog, C3d, Parameters, Points, Processor};
use criterion::{criterion_group, criterion_main, Criterion};
use repair::swaps::{find_swaps, SwapOptions};
use repair::synth::gait_like;
use repair::Trial;
use std::time::Duration;

fn trial() -> Trial {
    let mut t = gait_like(60, 8, 10_000, 100.0, 0.3, 42);
    // Two markers of one segment for 20 frames, of two segments for 100 frames and to
    // the end; one marker 30 mm off for 20 frames.
    for (a, b, lo, hi) in [(0, 8, 1000, 1019), (1, 2, 4000, 4099), (3, 4, 9000, 9999)] {
        for f in lo..=hi {
            let p = t.xyz[a][f];
            t.xyz[a][f] = t.xyz[b][f];
            t.xyz[b][f] = p;
        }
    }
    for f in 6000..6020 {
        t.xyz[5][f][0] += 30.0;
    }
    t
}

fn file(t: &Trial) -> Vec<u8> {
    let (nm, nf) = (t.markers(), t.frames());
    let mut pts = Points::new(nf, nm);
    for f in 0..nf {
        for m in 0..nm {
            let k = pts.index(f, m);
            let p = t.xyz[m][f];
            pts.xyz[k] = [p[0] as f32, p[1] as f32, p[2] as f32];
            pts.residual[k] = 0.5;
        }
    }
    let mut ps = Parameters::new();
    ps.set_f32("POINT", "RATE", 100.0).expect("rate");
    let labels: Vec<String> = (0..nm).map(|i| format!("M{i:02}")).collect();
    ps.set_strings("POINT", "LABELS", &labels).expect("labels");
    ps.set_strings("POINT", "UNITS", &["mm".to_string()])
        .expect("units");
    C3d::new(pts, Analog::new(nf, 0, 1), ps, Processor::Intel, -1.0)
        .to_bytes()
        .expect("encodes")
}

fn bench(c: &mut Criterion) {
    let t = trial();
    let dir = std::env::temp_dir().join(format!("c3dfix-swaps-bench-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let path = dir.join("swaps_60x10000.c3d");
    std::fs::write(&path, file(&t)).expect("writes the trial");
    let opts = SwapOptions::default();
    let mut g = c.benchmark_group("swaps");
    g.sample_size(10).measurement_time(Duration::from_secs(10));
    g.bench_function("read_60x10000", |b| {
        b.iter(|| {
            let c = c3d::read_file(&path).expect("reads");
            c.points().xyz.len()
        })
    });
    g.bench_function("find_60x10000", |b| {
        b.iter(|| find_swaps(&t, &opts).expect("finds").len())
    });
    g.finish();
    let _ = std::fs::remove_dir_all(&dir);
}

criterion_group!(benches, bench);
criterion_main!(benches);
