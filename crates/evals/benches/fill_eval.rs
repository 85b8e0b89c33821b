//! The fill evaluation in small (issue 10): `auto` against its peer `pca` on artificial
//! gaps of 10 and 40 frames (6 of each, one marker at a time) in a walking and a full-body
//! trial of the shared corpus. Each method's mean error is printed once before it is
//! timed, so one run shows what `auto`'s extra time buys. Under a minute in all.
//! Run: `cargo bench -p evals --bench fill_eval`. Without the corpus it says so and
//! measures nothing.

use evals::corpus;

use criterion::{criterion_group, criterion_main, Criterion};
use repair::{evaluate, EvalConfig, FillMethod};
use std::time::Duration;

/// (name, path under the c3d-samples corpus).
const TRIALS: [(&str, &str); 2] = [
    ("walk_newwalk", "sample_06/newwalk.c3d"),
    (
        "fullbody_jump",
        "sample_00/Motion Analysis Corporation/Sample_Jump2.c3d",
    ),
];

fn config(method: FillMethod) -> EvalConfig {
    EvalConfig {
        gap_lengths: vec![10, 40],
        gaps_per_length: 6,
        methods: vec![method],
        group: 1,
        seed: 1,
        ..EvalConfig::default()
    }
}

fn bench(c: &mut Criterion) {
    let Some(root) = testkit::c3d_samples() else {
        eprintln!(
            "fill_eval bench: c3d-samples corpus not found (set C3D_SAMPLES), nothing measured"
        );
        return;
    };
    let mut g = c.benchmark_group("fill_eval");
    g.sample_size(10)
        .warm_up_time(Duration::from_secs(1))
        .measurement_time(Duration::from_secs(5));
    for (name, rel) in TRIALS {
        let trial = match corpus::load(&root.join(rel)) {
            Ok(t) => t,
            Err(e) => {
                eprintln!("fill_eval bench: {rel}: {e}");
                continue;
            }
        };
        for method in [FillMethod::Pca, FillMethod::Auto] {
            let cfg = config(method);
            let label = format!("{method:?}").to_lowercase();
            match evaluate(&trial, &cfg) {
                Ok(ev) => {
                    let errors: Vec<String> = ev
                        .scores
                        .iter()
                        .map(|s| format!("{} frames {:.2} mm", s.gap_len, s.mean))
                        .collect();
                    eprintln!("{name} {label}: mean error {}", errors.join(", "));
                }
                Err(e) => {
                    eprintln!("fill_eval bench: {rel}: {e}");
                    continue;
                }
            }
            g.bench_function(format!("{name}/{label}"), |b| {
                b.iter(|| evaluate(&trial, &cfg).expect("evaluates"))
            });
        }
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
