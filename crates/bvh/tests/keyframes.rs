//! Keyframe reduction on motions where the right answer is known, and optimal against greedy
//! on the real files.

use bvh::error_metric::{Effectors, Evaluator};
use bvh::interp::{Interp, Interpolator};
use bvh::keyframes::optimal::Cap;
use bvh::keyframes::{greedy, optimal, KeyframeError, Target};

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
        let o = optimal::reduce(&eval, Target::Keys(6), Cap::None).expect("optimal");
        assert_eq!(o.keys, BREAKPOINTS, "optimal {mode:?}");
        assert!(o.total_error < 1e-12);
        // With one key fewer, some breakpoint must go and the error becomes positive.
        let o5 = optimal::reduce(&eval, Target::Keys(5), Cap::Auto).expect("optimal");
        assert!(o5.total_error > 1e-3, "{}", o5.total_error);
        // An error bound of zero (up to rounding) needs exactly the breakpoints too.
        let gb = greedy::reduce(&eval, Target::MaxError(1e-6)).expect("greedy");
        assert_eq!(gb.keys, BREAKPOINTS, "greedy bound {mode:?}");
        let ob = optimal::reduce(&eval, Target::MaxError(1e-6), Cap::Auto).expect("optimal");
        assert_eq!(ob.keys, BREAKPOINTS, "optimal bound {mode:?}");
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
    assert!(optimal::reduce(&eval, Target::MaxError(f64::NAN), Cap::None).is_err());
    // Four segments of at most 5 frames cannot cover 40 frames.
    assert!(optimal::reduce(&eval, Target::Keys(5), Cap::Frames(5)).is_err());
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
    let o = optimal::reduce(&eval, Target::Keys(5), Cap::Auto);
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
            for i in 0..j {
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
            let o = optimal::reduce(&eval, Target::Keys(keys), Cap::None).expect("optimal");
            assert_eq!(g.keys.len(), keys);
            assert_eq!(o.keys.len(), keys);
            assert_eq!((o.keys[0], o.keys[keys - 1]), (0, b.motion.frames() - 1));
            assert!(
                o.total_error <= g.total_error * (1.0 + 1e-9) + 1e-12,
                "{file} {mode:?}: optimal {} > greedy {}",
                o.total_error,
                g.total_error
            );
            let auto = optimal::reduce(&eval, Target::Keys(keys), Cap::Auto).expect("capped");
            assert!(
                auto.total_error <= g.total_error * (1.0 + 1e-9) + 1e-12,
                "{file} {mode:?}"
            );
            assert!(
                auto.total_error >= o.total_error * (1.0 - 1e-9),
                "{file} {mode:?}"
            );
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
