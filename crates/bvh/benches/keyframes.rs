//! Keyframe reduction on the 2752-frame CMU file (31 joints): greedy (its full removal run,
//! what `--method greedy` costs), and the optimal method with its default search (which runs
//! greedy too) at several key counts, in the same run so their ratio can be read directly.
//! Skips (with a message) when the shared corpus is absent. Run with
//! `cargo bench -p bvh --bench keyframes`.

use bvh::error_metric::{Effectors, Evaluator};
use bvh::interp::{Interp, Interpolator};
use bvh::keyframes::optimal::Options;
use bvh::keyframes::{greedy, optimal, Target};
use criterion::{criterion_group, criterion_main, Criterion};

fn keyframes(c: &mut Criterion) {
    let Some(dir) = testkit::bvh_samples() else {
        return;
    };
    let Ok(b) = bvh::read(&dir.join("fairmotion_cmu_01_01.bvh")) else {
        eprintln!("skipping: CMU file unreadable");
        return;
    };
    let mut g = c.benchmark_group("cmu_01_01");
    g.sample_size(10);
    for mode in [Interp::Quat, Interp::Euler] {
        let eval = Evaluator::new(Interpolator::new(&b, mode), Effectors::EndSites);
        g.bench_function(format!("greedy_{}", mode.name()), |bench| {
            bench.iter(|| greedy::run(&eval))
        });
        let counts: &[usize] = match mode {
            Interp::Quat => &[20, 100, 400, 1000],
            Interp::Euler => &[20],
        };
        for &keys in counts {
            g.bench_function(format!("optimal_{}_{keys}_keys", mode.name()), |bench| {
                bench.iter(|| optimal::reduce(&eval, Target::Keys(keys), Options::default()))
            });
        }
    }
    g.finish();
}

criterion_group!(benches, keyframes);
criterion_main!(benches);
