//! Keyframe reduction on motions where the right answer is known, and optimal against greedy
//! on the real files.

use bvh::error_metric::{Effectors, Evaluator};
use bvh::interp::{Interp, Interpolator};
use bvh::keyframes::optimal::{Options, Strategy};
use bvh::keyframes::{greedy, optimal, KeyframeError, Target};

/// Options for one strategy, no gap cap.
fn with(strategy: Strategy) -> Options {
    Options {
        max_segment: None,
        strategy,
    }
}

/// A root moving along a piecewise-linear path (breakpoints at frames 7, 20 and 31 of 41) and
/// one joint whose Z angle is piecewise linear with a breakpoint at frame 13.
fn piecewise_linear() -> bvh::Bvh {
    let mut text = String::from(
        "HIERARCHY\nROOT root\n{\n OFFSET 0 0 0\n CHANNELS 6 Xposition Yposition Zposition Zrotation Yrotation Xrotation\n JOINT arm\n {\n  OFFSET 0 10 0\n  CHANNELS 3 Zrotation Yrotation Xrotation\n  End Site\n  {\n   OFFSET 5 0 0\n  }\n }\n}\nMOTION\nFrames: 41\nFrame Time: 0.1\n",
    );
    for f in 0..41 {
        let t = f as f64;
        let x = if f <= 7 {
            t
        } else if f <= 20 {
            7.0 + 3.0 * (t - 7.0)
        } else if f <= 31 {
            46.0 - 2.0 * (t - 20.0)
        } else {
            24.0
        };
        let angle = if f <= 13 {
            2.0 * t
        } else {
            26.0 - 1.5 * (t - 13.0)
        };
        text.push_str(&format!("{x} 1 2 0 0 0 {angle} 0 0\n"));
    }
    bvh::parse(&text).expect("synthetic file parses")
}

const BREAKPOINTS: [usize; 6] = [0, 7, 13, 20, 31, 40];

#[test]
fn greedy_and_optimal_find_exactly_the_breakpoints() {
    let b = piecewise_linear();
    for mode in [Interp::Euler, Interp::Quat] {
        let eval = Evaluator::new(Interpolator::new(&b, mode), Effectors::EndSites);
        let g = greedy::reduce(&eval, Target::Keys(6)).expect("greedy");
        assert_eq!(g.keys, BREAKPOINTS, "greedy {mode:?}");
        assert!(g.total_error < 1e-12, "{}", g.total_error);
        for strategy in [Strategy::Exhaustive, Strategy::CoarseToFine] {
            let o = optimal::reduce(&eval, Target::Keys(6), with(strategy)).expect("optimal");
            assert_eq!(o.keys, BREAKPOINTS, "optimal {mode:?} {strategy:?}");
            assert!(o.total_error < 1e-12);
            // With one key fewer, some breakpoint must go and the error becomes positive.
            let o5 = optimal::reduce(&eval, Target::Keys(5), with(strategy)).expect("optimal");
            assert!(o5.total_error > 1e-3, "{}", o5.total_error);
            // An error bound of zero (up to rounding) needs exactly the breakpoints too.
            let bound = Target::MaxError(1e-6);
            let ob = optimal::reduce(&eval, bound, with(strategy)).expect("optimal");
            assert_eq!(ob.keys, BREAKPOINTS, "optimal bound {mode:?} {strategy:?}");
        }
        let gb = greedy::reduce(&eval, Target::MaxError(1e-6)).expect("greedy");
        assert_eq!(gb.keys, BREAKPOINTS, "greedy bound {mode:?}");
    }
}

#[test]
fn greedy_curve_is_flat_until_a_breakpoint_goes() {
    let b = piecewise_linear();
    let eval = Evaluator::new(Interpolator::new(&b, Interp::Quat), Effectors::AllJoints);
    let run = greedy::run(&eval);
    assert_eq!(run.removed.len(), 39);
    let curve = run.curve();
    assert_eq!(curve.len(), 40);
    assert!(curve[41 - 6].1 < 1e-12);
    assert!(curve[41 - 5].1 > 1e-3);
}

#[test]
fn bad_targets_are_errors() {
    let b = piecewise_linear();
    let eval = Evaluator::new(Interpolator::new(&b, Interp::Euler), Effectors::EndSites);
    assert!(greedy::reduce(&eval, Target::Keys(1)).is_err());
    assert!(greedy::reduce(&eval, Target::Keys(42)).is_err());
    let options = Options::default();
    assert!(optimal::reduce(&eval, Target::MaxError(f64::NAN), options).is_err());
    // Four segments of at most 5 frames cannot cover 40 frames.
    let capped = Options {
        max_segment: Some(5),
        ..options
    };
    assert_eq!(
        optimal::reduce(&eval, Target::Keys(5), capped),
        Err(KeyframeError::SegmentCapTooSmall {
            max_segment: 5,
            frames: 41,
            keys: 5
        })
    );
    // A cap beyond any gap is no cap, whatever its size.
    let huge = Options {
        max_segment: Some(usize::MAX),
        ..options
    };
    assert!(optimal::reduce(&eval, Target::Keys(5), huge).is_ok());
}

/// Values no motion has: the first offending value is named, for every way in.
#[test]
fn absurd_and_non_finite_values_are_errors_naming_where() {
    let mut b = piecewise_linear();
    // Frame 3, joint `arm`, its first channel (Zrotation): column 6.
    b.motion.values[3 * 9 + 6] = 1e200;
    let eval = Evaluator::new(Interpolator::new(&b, Interp::Quat), Effectors::EndSites);
    let want = KeyframeError::AbsurdValue {
        place: "MOTION frame 3, joint `arm`, Zrotation".into(),
        value: 1e200,
    };
    assert_eq!(bvh::keyframes::check_values(&b), Err(want.clone()));
    assert_eq!(greedy::reduce(&eval, Target::Keys(5)), Err(want.clone()));
    let o = optimal::reduce(&eval, Target::Keys(5), Options::default());
    assert_eq!(o, Err(want.clone()));
    assert!(want.to_string().contains("1e200"), "{want}");
    // The limit itself is accepted; NaN and infinities never are.
    b.motion.values[3 * 9 + 6] = -bvh::keyframes::MAX_ABS_VALUE;
    assert_eq!(bvh::keyframes::check_values(&b), Ok(()));
    for v in [f64::NAN, f64::INFINITY, -f64::INFINITY] {
        b.motion.values[0] = v;
        assert!(matches!(
            bvh::keyframes::check_values(&b),
            Err(KeyframeError::AbsurdValue { ref place, .. }) if place == "MOTION frame 0, joint `root`, Xposition"
        ));
    }
    b.motion.values[0] = 0.0;
    b.skeleton.joints[1].end_site = Some([0.0, 2e9, 0.0]);
    assert_eq!(
        bvh::keyframes::check_values(&b),
        Err(KeyframeError::AbsurdValue {
            place: "End Site OFFSET of joint `arm`".into(),
            value: 2e9
        })
    );
    b.skeleton.joints[1].offset = [f64::NAN, 0.0, 0.0];
    assert!(matches!(
        bvh::keyframes::check_values(&b),
        Err(KeyframeError::AbsurdValue { ref place, .. }) if place == "OFFSET of joint `arm`"
    ));
}

/// The straightforward O(n²) per-key-count DP with exact segment costs: the oracle for the
/// pruned one.
fn brute_force(eval: &Evaluator, k: usize) -> f64 {
    brute_force_capped(eval, k, usize::MAX)
}

/// [`brute_force`] over key sets whose gaps are at most `cap` frames.
fn brute_force_capped(eval: &Evaluator, k: usize, cap: usize) -> f64 {
    let n = eval.frames();
    let mut s = bvh::error_metric::Scratch::default();
    let mut cost = vec![vec![0.0; n]; n];
    for (i, row) in cost.iter_mut().enumerate() {
        for (j, c) in row.iter_mut().enumerate().skip(i + 1) {
            *c = eval.segment_cost(i, j, f64::INFINITY, &mut s);
        }
    }
    let mut d = vec![f64::INFINITY; n];
    d[0] = 0.0;
    for _ in 1..k {
        let mut nd = vec![f64::INFINITY; n];
        for j in 1..n {
            for i in j.saturating_sub(cap)..j {
                nd[j] = f64::min(nd[j], d[i] + cost[i][j]);
            }
        }
        d = nd;
    }
    d[n - 1]
}

#[test]
fn optimal_matches_brute_force_and_beats_greedy_on_real_files() {
    let Some(dir) = testkit::bvh_samples() else {
        return;
    };
    for (file, keys) in [
        ("fairmotion_sinusoidal.bvh", 12),
        ("bvhtoolbox_walk01.bvh", 20),
        ("bandai_dataset-2_wave-left-hand_active_011.bvh", 6),
        ("fairmotion_pfnn_hierarchy.bvh", 10),
    ] {
        let b = bvh::read(&dir.join(file)).expect("parses");
        for mode in [Interp::Euler, Interp::Quat] {
            let eval = Evaluator::new(Interpolator::new(&b, mode), Effectors::EndSites);
            let g = greedy::reduce(&eval, Target::Keys(keys)).expect("greedy");
            let run = greedy::run(&eval);
            let search =
                optimal::search(&eval, &run, Target::Keys(keys), with(Strategy::Exhaustive))
                    .expect("optimal");
            assert!(search.exact);
            let o = search.reduction;
            assert_eq!(g.keys.len(), keys);
            assert_eq!(o.keys.len(), keys);
            assert_eq!((o.keys[0], o.keys[keys - 1]), (0, b.motion.frames() - 1));
            assert!(
                o.total_error <= g.total_error * (1.0 + 1e-9) + 1e-12,
                "{file} {mode:?}: optimal {} > greedy {}",
                o.total_error,
                g.total_error
            );
            // The default picks the exhaustive search on motions this short.
            let auto = optimal::search(&eval, &run, Target::Keys(keys), Options::default())
                .expect("default");
            assert!(auto.exact, "{file} {mode:?}");
            assert_eq!(auto.reduction, o, "{file} {mode:?}");
            let bf = brute_force(&eval, keys);
            assert!(
                (o.total_error - bf).abs() <= 1e-9 * (1.0 + bf),
                "{file} {mode:?}: optimal {} vs brute force {bf}",
                o.total_error
            );
        }
    }
}

/// The incremental segment walk used by both algorithms agrees with evaluating every frame
/// from scratch (the straightforward oracle), on real files and both interpolations.
#[test]
fn incremental_segment_cost_matches_frame_by_frame() {
    let Some(dir) = testkit::bvh_samples() else {
        return;
    };
    for file in [
        "bvhtoolbox_walk01.bvh",
        "bandai_dataset-1_bow_active_001.bvh",
        "fairmotion_sinusoidal.bvh",
    ] {
        let b = bvh::read(&dir.join(file)).expect("parses");
        let n = b.motion.frames();
        for mode in [Interp::Euler, Interp::Quat] {
            for which in [Effectors::EndSites, Effectors::AllJoints] {
                let eval = Evaluator::new(Interpolator::new(&b, mode), which);
                let mut s = bvh::error_metric::Scratch::default();
                for (a, len) in [(0, 2), (0, 3), (3, 17), (10, 60), (0, n - 1), (n - 40, 39)] {
                    let bb = a + len;
                    let walk = eval.segment_cost(a, bb, f64::INFINITY, &mut s);
                    let direct: f64 = (a + 1..bb)
                        .map(|t| eval.frame_error(a, bb, t, &mut s))
                        .sum();
                    assert!(
                        (walk - direct).abs() <= 1e-9 * (1.0 + direct),
                        "{file} {mode:?} {which:?} {a}..{bb}: {walk} vs {direct}"
                    );
                }
            }
        }
    }
}

const ALL_FILES: [&str; 7] = [
    "fairmotion_cmu_01_01.bvh",
    "fairmotion_sinusoidal.bvh",
    "fairmotion_pfnn_hierarchy.bvh",
    "bvhpython_test_freebvh.bvh",
    "bvhtoolbox_walk01.bvh",
    "bandai_dataset-1_bow_active_001.bvh",
    "bandai_dataset-2_wave-left-hand_active_011.bvh",
];

/// What the optimal method promises when it is not exhaustive: never more error than greedy for
/// a key count, never more keys for an error bound; checked on every shared file, with the
/// coarse-to-fine search forced even where the default would search exhaustively. On the short
/// files the exhaustive optimum is a floor it cannot go below.
#[test]
fn coarse_to_fine_is_never_worse_than_greedy_on_every_file() {
    let Some(dir) = testkit::bvh_samples() else {
        return;
    };
    for file in ALL_FILES {
        let b = bvh::read(&dir.join(file)).expect("parses");
        let n = b.motion.frames();
        let long = n > 1000;
        for mode in [Interp::Quat, Interp::Euler] {
            let eval = Evaluator::new(Interpolator::new(&b, mode), Effectors::EndSites);
            let run = greedy::run(&eval);
            let key_counts = match long {
                true => vec![20],
                false => vec![3, 4, (n / 10).max(3), 20.min(n - 1)],
            };
            for k in key_counts {
                let target = Target::Keys(k);
                let g = greedy::pick(&run, &eval, target);
                let c = optimal::search(&eval, &run, target, with(Strategy::CoarseToFine))
                    .expect("coarse to fine");
                assert!(!c.exact && c.step >= 2, "{file} {mode:?} {k}");
                assert_eq!(c.reduction.keys.len(), k);
                assert_eq!((c.reduction.keys[0], c.reduction.keys[k - 1]), (0, n - 1));
                assert!(
                    c.reduction.total_error <= g.total_error,
                    "{file} {mode:?} {k}: {} > greedy {}",
                    c.reduction.total_error,
                    g.total_error
                );
                let rebuilt: f64 = eval.frame_errors(&c.reduction.keys).iter().sum();
                assert!((rebuilt - c.reduction.total_error).abs() <= 1e-9 * (1.0 + rebuilt));
                if !long {
                    let e = optimal::search(&eval, &run, target, with(Strategy::Exhaustive))
                        .expect("exhaustive");
                    assert!(
                        c.reduction.total_error >= e.reduction.total_error * (1.0 - 1e-9),
                        "{file} {mode:?} {k}: below the optimum"
                    );
                }
            }
            let rms = bvh::keyframes::rms(
                &eval,
                greedy::pick(&run, &eval, Target::Keys(4)).total_error,
            );
            let target = Target::MaxError(rms);
            let g = greedy::pick(&run, &eval, target);
            let c = optimal::search(&eval, &run, target, with(Strategy::CoarseToFine))
                .expect("coarse to fine");
            assert!(c.reduction.keys.len() <= g.keys.len(), "{file} {mode:?}");
            let bound = bvh::keyframes::total_bound(&eval, rms);
            assert!(
                c.reduction.total_error <= bound * (1.0 + 1e-9),
                "{file} {mode:?}"
            );
        }
    }
}

/// 20 keys on the CMU file, the case that made the exhaustive search impractical: the default
/// search is coarse-to-fine there, and it finds a key set better than the exhaustive optimum
/// among gaps of at most 514 frames (the former default's restriction), whose error,
/// 142628.85, comes from `c3dfix keyframes fairmotion_cmu_01_01.bvh --keys 20 --method optimal
/// --exact --max-segment 514` (a minute and a half). Greedy's error is 195543.81.
#[test]
fn optimal_twenty_keys_on_the_cmu_file_beats_the_capped_optimum() {
    let Some(dir) = testkit::bvh_samples() else {
        return;
    };
    let b = bvh::read(&dir.join("fairmotion_cmu_01_01.bvh")).expect("parses");
    let eval = Evaluator::new(Interpolator::new(&b, Interp::Quat), Effectors::EndSites);
    let run = greedy::run(&eval);
    let g = greedy::pick(&run, &eval, Target::Keys(20));
    assert!(
        (g.total_error - 195543.81).abs() < 0.01,
        "{}",
        g.total_error
    );
    let o = optimal::search(&eval, &run, Target::Keys(20), Options::default()).expect("optimal");
    assert!(!o.exact);
    assert_eq!(o.step, 9);
    assert!(
        o.reduction.total_error < 142628.85,
        "{}",
        o.reduction.total_error
    );
    // A gap far beyond 514 frames is what makes it better.
    let longest = o.reduction.keys.windows(2).map(|w| w[1] - w[0]).max();
    assert!(longest > Some(514), "{:?}", o.reduction.keys);
}

/// The sampled cost of the grid search is the stride times the errors of the sampled frames.
#[test]
fn sampled_segment_cost_sums_every_stride_th_frame() {
    let Some(dir) = testkit::bvh_samples() else {
        return;
    };
    let b = bvh::read(&dir.join("bvhtoolbox_walk01.bvh")).expect("parses");
    for mode in [Interp::Euler, Interp::Quat] {
        let eval = Evaluator::new(Interpolator::new(&b, mode), Effectors::AllJoints);
        let mut s = bvh::error_metric::Scratch::default();
        for (a, bb, stride) in [
            (0, 100, 7),
            (3, 17, 2),
            (10, 60, 5),
            (20, 22, 3),
            (5, 50, 1),
        ] {
            let sampled = eval.sampled_segment_cost(a, bb, stride, f64::INFINITY, &mut s);
            let direct: f64 = (a + stride..bb)
                .step_by(stride)
                .map(|t| stride as f64 * eval.frame_error(a, bb, t, &mut s))
                .sum();
            assert!(
                (sampled - direct).abs() <= 1e-9 * (1.0 + direct),
                "{mode:?} {a}..{bb} every {stride}: {sampled} vs {direct}"
            );
        }
    }
}

/// A gap cap binds even when greedy's keys break it: both searches keep every gap within it,
/// and the exhaustive one finds the capped optimum.
#[test]
fn gap_cap_is_respected_even_when_greedy_breaks_it() {
    let Some(dir) = testkit::bvh_samples() else {
        return;
    };
    let b = bvh::read(&dir.join("bvhtoolbox_walk01.bvh")).expect("parses");
    let eval = Evaluator::new(Interpolator::new(&b, Interp::Quat), Effectors::EndSites);
    let run = greedy::run(&eval);
    let g = greedy::pick(&run, &eval, Target::Keys(5));
    let cap = 40;
    assert!(g.keys.windows(2).any(|w| w[1] - w[0] > cap), "{:?}", g.keys);
    let want = brute_force_capped(&eval, 5, cap);
    for strategy in [Strategy::Exhaustive, Strategy::CoarseToFine] {
        let options = Options {
            max_segment: Some(cap),
            strategy,
        };
        let o = optimal::search(&eval, &run, Target::Keys(5), options).expect("optimal");
        let r = &o.reduction;
        assert!(
            r.keys.windows(2).all(|w| w[1] - w[0] <= cap),
            "{strategy:?} {:?}",
            r.keys
        );
        assert!(r.total_error >= want * (1.0 - 1e-9), "{strategy:?}");
        if strategy == Strategy::Exhaustive {
            assert!(o.exact);
            assert!(
                (r.total_error - want).abs() <= 1e-9 * (1.0 + want),
                "{}",
                r.total_error
            );
        }
    }
}
