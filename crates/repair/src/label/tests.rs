use super::*;
use crate::rng::SplitMix64;
use crate::synth::gait_like;

/// Frames `a..b` of `t`, each marker cut into pieces of 40–150 frames, every piece its own
/// row, rows in a shuffled order; returns the trial and each row's true marker.
fn fragmented(t: &Trial, a: usize, b: usize, seed: u64) -> (Trial, Vec<usize>) {
    let mut rng = SplitMix64::new(seed);
    let n = b - a;
    let mut rows: Vec<(usize, usize, usize)> = Vec::new();
    for m in 0..t.markers() {
        let mut f = 0;
        while f < n {
            let len = rng.range(40, 150).min(n - f);
            rows.push((m, f, f + len));
            f += len;
        }
    }
    for i in (1..rows.len()).rev() {
        rows.swap(i, rng.range(0, i + 1));
    }
    let mut xyz = Vec::new();
    let mut valid = Vec::new();
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
    let truth = rows.iter().map(|r| r.0).collect();
    (Trial::new(t.rate_hz, xyz, valid).unwrap(), truth)
}

fn window(t: &Trial, a: usize, b: usize) -> Trial {
    Trial::new(
        t.rate_hz,
        t.xyz.iter().map(|r| r[a..b].to_vec()).collect(),
        t.valid.iter().map(|r| r[a..b].to_vec()).collect(),
    )
    .unwrap()
}

#[test]
fn a_fragmented_trial_is_labelled_from_its_first_seconds() {
    let t = gait_like(32, 8, 900, 100.0, 0.3, 7);
    let template = window(&t, 0, 300);
    let (trial, truth) = fragmented(&t, 300, 900, 11);
    let given = vec![None; trial.markers()];
    let out = label(
        &template,
        1.0,
        &trial,
        1.0,
        &given,
        &LabelOptions::default(),
    )
    .unwrap();
    assert!(out.seeded);
    let (mut right, mut wrong, mut left) = (0, 0, 0);
    for a in &out.fragments {
        match a.label {
            Some(m) if m == truth[a.fragment.row] => right += a.fragment.len(),
            Some(_) => wrong += a.fragment.len(),
            None => left += a.fragment.len(),
        }
    }
    assert_eq!(wrong, 0, "{right} right, {left} left");
    assert!(
        right as f64 >= 0.99 * (right + left) as f64,
        "{right} right, {left} left"
    );
}

#[test]
fn a_ghost_stays_unlabelled_and_given_labels_are_kept() {
    let t = gait_like(24, 8, 600, 100.0, 0.3, 3);
    let template = window(&t, 0, 200);
    let (mut trial, truth) = fragmented(&t, 200, 600, 5);
    // A ghost 40 mm off marker 0's true place for 100 frames.
    let n = trial.frames();
    let mut x = vec![[0.0; 3]; n];
    let mut v = vec![false; n];
    for f in 100..200 {
        let p = t.xyz[0][200 + f];
        x[f] = [p[0] + 40.0, p[1], p[2]];
        v[f] = true;
    }
    trial.xyz.push(x);
    trial.valid.push(v);
    let mut given: Vec<Option<usize>> = truth.iter().map(|&m| (m % 3 == 0).then_some(m)).collect();
    given.push(None);
    let out = label(
        &template,
        1.0,
        &trial,
        1.0,
        &given,
        &LabelOptions::default(),
    )
    .unwrap();
    assert!(!out.seeded);
    let ghost = trial.markers() - 1;
    for a in &out.fragments {
        if a.fragment.row == ghost {
            assert_eq!(a.label, None, "{a:?}");
        } else if a.fragment.len() < 3 {
            // Too short to judge unless the trial labelled it.
            assert!(
                a.label.is_none() || a.label == Some(truth[a.fragment.row]),
                "{a:?}"
            );
        } else {
            assert_eq!(a.label, Some(truth[a.fragment.row]), "{a:?}");
        }
        if a.given.is_some() {
            assert_eq!(a.outcome, Outcome::Kept);
        }
    }
    // The same answer again.
    let again = label(
        &template,
        1.0,
        &trial,
        1.0,
        &given,
        &LabelOptions::default(),
    )
    .unwrap();
    assert_eq!(again, out);
}

#[test]
fn bad_input_is_an_error_not_a_panic() {
    let t = gait_like(6, 2, 50, 100.0, 0.3, 1);
    let empty = Trial::new(100.0, vec![vec![[0.0; 3]; 5]; 2], vec![vec![false; 5]; 2]).unwrap();
    let opts = LabelOptions::default();
    assert_eq!(
        label(&empty, 1.0, &t, 1.0, &[None; 6], &opts),
        Err(LabelError::EmptyTemplate(2))
    );
    assert!(matches!(
        label(&t, 1.0, &t, 1.0, &[None; 5], &opts),
        Err(LabelError::Shape { .. })
    ));
    assert!(matches!(
        label(
            &t,
            1.0,
            &t,
            1.0,
            &[Some(9), None, None, None, None, None],
            &opts
        ),
        Err(LabelError::Given { row: 0, .. })
    ));
    assert!(matches!(
        label(&t, f64::NAN, &t, 1.0, &[None; 6], &opts),
        Err(LabelError::Scale { .. })
    ));
    // NaN samples and a one-frame trial: answers, no panic.
    let mut nan = t.clone();
    nan.xyz[2][10] = [f64::NAN, 0.0, 0.0];
    assert!(label(&t, 1.0, &nan, 1.0, &[None; 6], &opts).is_ok());
    let one = window(&t, 0, 1);
    assert!(label(&one, 1.0, &one, 1.0, &[None; 6], &opts).is_ok());
}

#[test]
fn the_answer_is_the_same_on_one_thread_or_several_and_with_seed_runs() {
    let t = gait_like(30, 8, 1500, 100.0, 0.3, 21);
    let template = window(&t, 0, 300);
    let (trial, _) = fragmented(&t, 300, 1500, 23);
    let given = vec![None; trial.markers()];
    for chain in [1, 4] {
        let opts = LabelOptions {
            seed_chain: chain,
            ..LabelOptions::default()
        };
        let on = |threads: usize| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap()
                .install(|| label(&template, 1.0, &trial, 1.0, &given, &opts).unwrap())
        };
        let one = on(1);
        assert!(one.seeded);
        assert_eq!(on(3), one, "seed_chain {chain}");
    }
}

/// Frames `a..b` of `t` with every coordinate times `s`: the same motion on a body `s`
/// times as large.
fn scaled(t: &Trial, s: f64) -> Trial {
    Trial::new(
        t.rate_hz,
        t.xyz
            .iter()
            .map(|r| r.iter().map(|p| p.map(|v| v * s)).collect())
            .collect(),
        t.valid.clone(),
    )
    .unwrap()
}

#[test]
fn a_template_of_a_larger_body_is_fitted_to_the_trial() {
    let t = gait_like(32, 8, 900, 100.0, 0.3, 7);
    // The template's body 12 % larger than the trial's.
    let template = scaled(&window(&t, 0, 300), 1.12);
    let (trial, truth) = fragmented(&t, 300, 900, 11);
    let given = vec![None; trial.markers()];
    let tally = |out: &Labelling| {
        let (mut right, mut wrong) = (0, 0);
        for a in &out.fragments {
            match a.label {
                Some(m) if m == truth[a.fragment.row] => right += a.fragment.len(),
                Some(_) => wrong += a.fragment.len(),
                None => {}
            }
        }
        (right, wrong)
    };
    let total: usize = trial.valid.iter().flatten().filter(|&&v| v).count();
    let fitted = LabelOptions {
        fit_scale: true,
        ..LabelOptions::default()
    };
    let out = label(&template, 1.0, &trial, 1.0, &given, &fitted).unwrap();
    assert!((out.scale - 1.0 / 1.12).abs() < 0.01, "scale {}", out.scale);
    let (right, wrong) = tally(&out);
    assert_eq!(wrong, 0, "{right} right of {total}");
    assert!(
        right as f64 >= 0.99 * total as f64,
        "{right} right of {total}"
    );
    // Without the fit the distances are 12 % off, beyond their tolerances.
    let plain = label(
        &template,
        1.0,
        &trial,
        1.0,
        &given,
        &LabelOptions::default(),
    )
    .unwrap();
    assert_eq!(plain.scale, 1.0);
    let (right, _) = tally(&plain);
    assert!(
        (right as f64) < 0.5 * total as f64,
        "{right} right of {total}"
    );
}

#[test]
fn two_neighbours_labelled_exchanged_are_left_unlabelled() {
    // Markers 0 and 8 lie on one segment; the trial's labels exchange them and keep every
    // other marker right: the exchanged pair fits better than the labels given, so both
    // are left unlabelled, and no rightly labelled neighbour is.
    let t = gait_like(24, 8, 600, 100.0, 0.3, 3);
    let opts = LabelOptions::default();
    let model = model::Model::learn(&window(&t, 0, 200), &opts);
    assert!(model.nb[0].iter().any(|n| n.other == 8));
    let pc = fragments::Pieces::cut(&window(&t, 200, 600), 1.0, 1e9);
    assert_eq!(pc.frags.len(), 24);
    let mut out: Vec<FragmentLabel> = pc
        .frags
        .iter()
        .map(|&fragment| {
            let m = match fragment.row {
                0 => 8,
                8 => 0,
                r => r,
            };
            FragmentLabel {
                fragment,
                label: Some(m),
                given: None,
                outcome: Outcome::Labelled,
                checked: 10,
                votes: 10,
            }
        })
        .collect();
    exchanges(&model, &pc, &mut out, &opts);
    for a in &out {
        match a.fragment.row {
            0 | 8 => assert!(
                matches!(
                    a.outcome,
                    Outcome::Unlabelled {
                        reason: Reason::Exchangeable { .. }
                    }
                ) && a.label.is_none(),
                "{a:?}"
            ),
            r => assert_eq!(a.label, Some(r), "{a:?}"),
        }
    }
}
