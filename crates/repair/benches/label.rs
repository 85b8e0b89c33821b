//! Speed of labelling from a template (issue 47 item 4): a synthetic trial of 60 markers ×
//! 10 000 frames at 100 Hz, every trajectory cut into fragments of 0.4–1.5 s in rows of
//! their own (shuffled), labelled from the same body's first 1 000 frames. Goal: ≤ 2 s.
//! Run: `cargo bench -p repair --bench label`.

use criterion::{criterion_group, criterion_main, Criterion};
use repair::label::{label, LabelOptions};
use repair::synth::gait_like;
use repair::Trial;
use std::time::Duration;

/// Frames `a..` of `t`, each marker cut into pieces of 40–150 frames, every piece its own
/// row, rows shuffled by a fixed rule.
fn fragmented(t: &Trial, a: usize) -> Trial {
    let n = t.frames() - a;
    let mut rows: Vec<(usize, usize, usize)> = Vec::new();
    let mut s = 0x9e37_79b9_7f4a_7c15u64;
    let mut next = move || {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        s
    };
    for m in 0..t.markers() {
        let mut f = 0;
        while f < n {
            let len = (40 + next() % 110) as usize;
            let e = (f + len).min(n);
            rows.push((m, f, e));
            f = e;
        }
    }
    for i in (1..rows.len()).rev() {
        rows.swap(i, (next() % (i as u64 + 1)) as usize);
    }
    let (mut xyz, mut valid) = (Vec::new(), Vec::new());
    for &(m, lo, hi) in &rows {
        let mut x = vec![[0.0; 3]; n];
        let mut v = vec![false; n];
        for f in lo..hi {
            x[f] = t.xyz[m][a + f];
            v[f] = true;
        }
        xyz.push(x);
        valid.push(v);
    }
    Trial::new(t.rate_hz, xyz, valid).expect("shaped")
}

fn bench(c: &mut Criterion) {
    let all = gait_like(60, 8, 11_000, 100.0, 0.3, 42);
    let template = Trial::new(
        100.0,
        all.xyz.iter().map(|r| r[..1000].to_vec()).collect(),
        all.valid.iter().map(|r| r[..1000].to_vec()).collect(),
    )
    .expect("shaped");
    let trial = fragmented(&all, 1000);
    let given = vec![None; trial.markers()];
    let opts = LabelOptions::default();
    let mut g = c.benchmark_group("label");
    g.sample_size(10).measurement_time(Duration::from_secs(20));
    g.bench_function("60 markers × 10 000 frames, fragmented", |b| {
        b.iter(|| label(&template, 1.0, &trial, 1.0, &given, &opts).expect("labels"))
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
