use super::*;

/// Five markers of one rigid body walking along x and turning slowly, 300 frames at 100 Hz.
fn body() -> Trial {
    let offsets = [
        [0.0, 0.0, 0.0],
        [120.0, 0.0, 10.0],
        [0.0, 90.0, -20.0],
        [60.0, 40.0, 80.0],
        [-50.0, 70.0, 30.0],
    ];
    let xyz = offsets
        .iter()
        .map(|o| {
            (0..300)
                .map(|f| {
                    let t = f as f64 / 100.0;
                    let (s, c) = (0.4 * t).sin_cos();
                    [
                        1000.0 * t + c * o[0] - s * o[1],
                        200.0 + s * o[0] + c * o[1],
                        900.0 + o[2] + 20.0 * (3.0 * t).sin(),
                    ]
                })
                .collect()
        })
        .collect();
    Trial::new(100.0, xyz, vec![vec![true; 300]; 5]).unwrap()
}

/// Cut frames `a..=b` of `marker` out into a new unlabelled trajectory.
fn cut(t: &mut Trial, marker: usize, a: usize, b: usize) -> Trial {
    let n = t.frames();
    let mut xyz = vec![[0.0; 3]; n];
    let mut valid = vec![false; n];
    for f in a..=b {
        xyz[f] = t.xyz[marker][f];
        valid[f] = true;
        t.valid[marker][f] = false;
    }
    Trial::new(t.rate_hz, vec![xyz], vec![valid]).unwrap()
}

fn push(u: &mut Trial, xyz: Vec<[f64; 3]>, valid: Vec<bool>) {
    u.xyz.push(xyz);
    u.valid.push(valid);
}

#[test]
fn a_cut_fragment_goes_back_to_its_marker_past_a_ghost_and_a_reflection() {
    let mut t = body();
    let mut u = cut(&mut t, 0, 100, 140);
    // A ghost 30 mm off marker 1 over the same frames, and a still reflection.
    let ghost: Vec<[f64; 3]> = t.xyz[1].iter().map(|p| [p[0], p[1] + 30.0, p[2]]).collect();
    let mut gv = vec![false; 300];
    gv[90..160].iter_mut().for_each(|v| *v = true);
    push(&mut u, ghost, gv);
    push(&mut u, vec![[1200.0, 250.0, 905.0]; 300], vec![true; 300]);
    let r = find_reclaims(&t, &u, 1.0, &ReclaimOptions::default());
    assert_eq!(r.moves.len(), 1, "{r:?}");
    let m = r.moves[0];
    assert_eq!(
        (m.piece.marker, m.piece.source, m.piece.first, m.piece.last),
        (0, 0, 100, 140)
    );
    assert_eq!(m.fit.verdict, Verdict::Fits);
    assert!(m.fit.rms_mm < 1e-6, "{:?}", m.fit);
    assert!(r.unsettled.is_empty(), "{:?}", r.unsettled);
}

#[test]
fn two_copies_of_the_marker_leave_it_unsettled() {
    let mut t = body();
    let mut u = cut(&mut t, 2, 50, 70);
    let (x, v) = (u.xyz[0].clone(), u.valid[0].clone());
    push(&mut u, x, v);
    let r = find_reclaims(&t, &u, 1.0, &ReclaimOptions::default());
    assert!(r.moves.is_empty(), "{r:?}");
    assert_eq!(r.unsettled.len(), 2);
    assert!(matches!(r.unsettled[0].why, Why::Ambiguous { .. }));
}

#[test]
fn no_candidates_one_frame_and_nan_change_nothing() {
    let t = body();
    let none = Trial::new(100.0, vec![], vec![]).unwrap();
    assert_eq!(
        find_reclaims(&t, &none, 1.0, &ReclaimOptions::default()),
        Reclaims::default()
    );
    let one = Trial::new(100.0, vec![vec![[1.0; 3]]], vec![vec![false]]).unwrap();
    let u1 = Trial::new(100.0, vec![vec![[1.0; 3]]], vec![vec![true]]).unwrap();
    let r = find_reclaims(&one, &u1, 1.0, &ReclaimOptions::default());
    assert!(r.moves.is_empty() && r.unsettled.is_empty());
    // A fragment whose samples are NaN is no candidate.
    let mut t = body();
    let mut u = cut(&mut t, 0, 100, 140);
    u.xyz[0].iter_mut().for_each(|p| *p = [f64::NAN; 3]);
    let r = find_reclaims(&t, &u, 1.0, &ReclaimOptions::default());
    assert!(r.moves.is_empty() && r.unsettled.is_empty(), "{r:?}");
    // Frames that differ between the trials: nothing to judge.
    let short = Trial::new(100.0, vec![vec![[0.0; 3]; 3]], vec![vec![true; 3]]).unwrap();
    assert_eq!(
        find_reclaims(&body(), &short, 1.0, &ReclaimOptions::default()),
        Reclaims::default()
    );
}

#[test]
fn units_are_turned_to_millimetres() {
    let mut t = body();
    for row in &mut t.xyz {
        row.iter_mut().for_each(|p| *p = p.map(|v| v / 1000.0));
    }
    let u = cut(&mut t, 3, 200, 260);
    let r = find_reclaims(&t, &u, 1000.0, &ReclaimOptions::default());
    assert_eq!(r.moves.len(), 1, "{r:?}");
    assert_eq!((r.moves[0].piece.first, r.moves[0].piece.last), (200, 260));
}
