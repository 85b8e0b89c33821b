//! Swap and jump finding (issue 34): episodes injected into a synthetic trial and into a
//! corpus trial are found with their exact frames and undone bit for bit.

use repair::swaps::{find_swaps, learn_links, undo, Find, FindKind, SwapOptions};
use repair::synth::gait_like;
use repair::Trial;

fn exchange(t: &mut Trial, a: usize, b: usize, lo: usize, hi: usize) {
    for f in lo..=hi {
        let p = t.xyz[a][f];
        t.xyz[a][f] = t.xyz[b][f];
        t.xyz[b][f] = p;
        let v = t.valid[a][f];
        t.valid[a][f] = t.valid[b][f];
        t.valid[b][f] = v;
    }
}

#[test]
fn synthetic_swap_and_jump_are_found_exactly_and_undone() {
    let clean = gait_like(30, 8, 2000, 100.0, 0.3, 7);
    let mut t = clean.clone();
    // Markers 0 and 8 share the pelvis (round-robin over 8 segments).
    exchange(&mut t, 0, 8, 500, 519);
    for f in 1200..1220 {
        t.xyz[5][f][1] += 30.0;
    }
    let finds = find_swaps(&t, &SwapOptions::default()).unwrap();
    assert_eq!(finds.len(), 2, "{finds:?}");
    assert_eq!(finds[0].kind, FindKind::Swap);
    assert_eq!(finds[0].markers, vec![0, 8]);
    assert_eq!((finds[0].first, finds[0].last), (500, 519));
    assert!(
        finds[0].settled && finds[0].confidence > 0.9,
        "{:?}",
        finds[0]
    );
    assert_eq!(finds[1].kind, FindKind::Jump);
    assert_eq!(finds[1].markers, vec![5]);
    assert_eq!((finds[1].first, finds[1].last), (1200, 1219));
    assert!(finds[1].settled);

    let changed = undo(&mut t, &finds);
    assert_eq!(changed, 2 * 20 + 20);
    assert_eq!(t.xyz[0], clean.xyz[0]);
    assert_eq!(t.xyz[8], clean.xyz[8]);
    assert!((1200..1220).all(|f| !t.valid[5][f]));
    assert!(t.valid[5][1199] && t.valid[5][1220]);
    // The clean trial has nothing to find.
    assert!(find_swaps(&clean, &SwapOptions::default())
        .unwrap()
        .is_empty());
}

/// `TYPE-3.c3d` (AMTI sample, 28 markers) in mm with its own gaps.
fn type3() -> Option<Trial> {
    let Some(root) = testkit::c3d_samples() else {
        eprintln!("C3D_SAMPLES not set: skipped");
        return None;
    };
    let c = c3d::read_file(root.join("sample_10/TYPE-3.c3d")).unwrap();
    let k = c3d::mm_per_unit(&c.point_units());
    let p = c.points();
    let outputs = c.model_output_labels();
    let (mut xyz, mut valid) = (Vec::new(), Vec::new());
    for (i, l) in c.point_labels().iter().enumerate() {
        if outputs.contains(l) {
            continue;
        }
        xyz.push(
            p.trajectory(i)
                .iter()
                .map(|q| q.map(|v| v as f64 * k))
                .collect(),
        );
        valid.push(p.validity(i));
    }
    Some(Trial::new(c.point_rate() as f64, xyz, valid).unwrap())
}

#[test]
fn corpus_swap_between_linked_markers_is_found_and_undone_bit_for_bit() {
    let Some(clean) = type3() else { return };
    let opts = SwapOptions::default();
    // Untouched: nothing settled (the trial's own finds, if any, are only reported).
    let base = find_swaps(&clean, &opts).unwrap();
    assert!(base.iter().all(|x| !x.settled), "{base:?}");
    let links = learn_links(&clean, opts.max_link_spread_mm, opts.min_link_support, 8);
    // The first marker with a link, and its most rigid partner; 20 frames mid-trial where
    // both are seen.
    let (a, l) = links
        .iter()
        .enumerate()
        .find_map(|(m, ls)| ls.first().map(|l| (m, *l)))
        .unwrap();
    let b = l.other;
    let n = clean.frames();
    let lo = (n / 3..n - 30)
        .find(|&f| (f..f + 20).all(|g| clean.valid[a][g] && clean.valid[b][g]))
        .unwrap();
    let mut t = clean.clone();
    exchange(&mut t, a, b, lo, lo + 19);
    let x = &the_one_new_find(&t, &opts, &base);
    assert_eq!(x.kind, FindKind::Swap);
    assert_eq!(x.markers, vec![a.min(b), a.max(b)]);
    assert_eq!((x.first, x.last), (lo, lo + 19));
    assert!(x.settled, "{x:?}");
    undo(&mut t, std::slice::from_ref(x));
    assert_eq!(t, clean);
}

/// The finds on `t` that the untouched trial (`base`) does not have: exactly one, the
/// injected episode's.
fn the_one_new_find(t: &Trial, opts: &SwapOptions, base: &[Find]) -> Find {
    let finds: Vec<Find> = find_swaps(t, opts)
        .unwrap()
        .into_iter()
        .filter(|x| !base.contains(x))
        .collect();
    assert_eq!(finds.len(), 1, "{finds:?}");
    finds.into_iter().next().unwrap()
}

/// A window of `len` frames from a third into the trial where `a` and every partner in
/// `others` are seen, with 5 frames either side.
fn seen_window(t: &Trial, a: usize, others: &[usize], len: usize) -> Option<usize> {
    let n = t.frames();
    (n / 3..n.saturating_sub(len + 10)).find(|&f| {
        (f - 5..f + len + 5).all(|g| t.valid[a][g] && others.iter().all(|&o| t.valid[o][g]))
    })
}

/// Adds `off` to `a`'s samples over `lo..=hi`: its label on a point at a steady offset.
fn offset(t: &mut Trial, a: usize, lo: usize, hi: usize, off: [f64; 3]) {
    for f in lo..=hi {
        for (c, o) in off.iter().enumerate() {
            t.xyz[a][f][c] += o;
        }
    }
}

#[test]
fn corpus_jump_at_a_steady_offset_carries_the_offset_witness() {
    let Some(clean) = type3() else { return };
    let opts = SwapOptions::default();
    let base = find_swaps(&clean, &opts).unwrap();
    let links = learn_links(&clean, opts.max_link_spread_mm, opts.min_link_support, 8);
    // The first marker with four links or more, 30 frames where it and its partners are seen.
    let (a, lo) = (0..clean.markers())
        .filter(|&m| links[m].len() >= 4)
        .find_map(|m| {
            let others: Vec<usize> = links[m].iter().map(|l| l.other).collect();
            Some((m, seen_window(&clean, m, &others, 30)?))
        })
        .unwrap();
    let hi = lo + 29;
    let mut t = clean.clone();
    offset(&mut t, a, lo, hi, [21.0, -18.0, 12.0]);
    let x = &the_one_new_find(&t, &opts, &base);
    assert_eq!((x.kind, x.markers.clone()), (FindKind::Jump, vec![a]));
    assert_eq!((x.first, x.last), (lo, hi), "{x:?}");
    // The two leaps cancel exactly and the offset holds against the partners' motion.
    let share = x.evidence.offset_share.unwrap();
    assert!(share > 0.9, "{x:?}");
    assert!(x.settled, "{x:?}");

    // The same label drifting off and back over the span (a ramp up and down, no leap)
    // carries no witness: no find, or one without it.
    let mut t = clean.clone();
    for f in lo..=hi {
        let k = 1.0 - ((f - lo) as f64 - 14.5).abs() / 15.0;
        offset(&mut t, a, f, f, [21.0 * k, -18.0 * k, 12.0 * k]);
    }
    let drift: Vec<_> = find_swaps(&t, &opts)
        .unwrap()
        .into_iter()
        .filter(|x| !base.contains(x) && x.markers == [a])
        .collect();
    assert!(
        drift
            .iter()
            .all(|x| x.evidence.offset_share.unwrap_or(0.0) < 0.1),
        "{drift:?}"
    );
}

#[test]
fn corpus_jump_across_a_marker_with_three_links_is_found_whole_with_its_steady_offset() {
    let Some(clean) = type3() else { return };
    let opts = SwapOptions::default();
    let base = find_swaps(&clean, &opts).unwrap();
    let links = learn_links(&clean, opts.max_link_spread_mm, opts.min_link_support, 8);
    // A marker with two or three links, all under 300 mm (partners far along a limb
    // cannot say where its twist puts the marker), 25 frames where it and its partners are
    // seen.
    let (a, lo) = (0..clean.markers())
        .filter(|&m| (2..=3).contains(&links[m].len()) && links[m].iter().all(|l| l.d0_mm < 300.0))
        .find_map(|m| {
            let others: Vec<usize> = links[m].iter().map(|l| l.other).collect();
            Some((m, seen_window(&clean, m, &others, 25)?))
        })
        .unwrap();
    let hi = lo + 24;
    // 18 mm across its links (the direction least along them at the span's middle: the
    // least eigenvector of the sum of their unit vectors' outer products): their lengths
    // change by a few mm, near their tolerances: the links decide few of its frames.
    let mid = (lo + hi) / 2;
    let p = nalgebra::Vector3::from(clean.xyz[a][mid]);
    let mut m = nalgebra::Matrix3::zeros();
    for l in &links[a] {
        let u = (nalgebra::Vector3::from(clean.xyz[l.other][mid]) - p).normalize();
        m += u * u.transpose();
    }
    let eig = m.symmetric_eigen();
    let i = eig.eigenvalues.imin();
    let n = eig.eigenvectors.column(i).into_owned();
    let k = 18.0;
    let mut t = clean.clone();
    offset(&mut t, a, lo, hi, [n[0] * k, n[1] * k, n[2] * k]);
    let x = &the_one_new_find(&t, &opts, &base);
    assert_eq!((x.kind, x.markers.clone()), (FindKind::Jump, vec![a]));
    assert_eq!((x.first, x.last), (lo, hi), "{x:?}");
    assert!(x.evidence.frames_decided < 12, "{x:?}");
    assert!(x.settled, "{x:?}");
    assert!(x.evidence.offset_share.unwrap() > 0.8, "{x:?}");
}

/// A label that takes another marker's recorded point while that marker is missing (the
/// other's gap is exactly the span): its trajectory leaps onto where the other's would be
/// and leaps back as the other reappears. Found as a swap of the two over the span, so
/// that undoing it gives the point back to its marker and leaves the label a gap.
#[test]
fn corpus_label_on_a_missing_markers_point_is_found_over_its_gap_and_given_back() {
    let Some(clean) = type3() else { return };
    let opts = SwapOptions::default();
    let base = find_swaps(&clean, &opts).unwrap();
    let links = learn_links(&clean, opts.max_link_spread_mm, opts.min_link_support, 8);
    let (a, l) = links
        .iter()
        .enumerate()
        .find_map(|(m, ls)| ls.first().map(|l| (m, *l)))
        .unwrap();
    let b = l.other;
    let (lo, len) = (seen_window(&clean, a, &[b], 25).unwrap(), 25);
    let hi = lo + len - 1;
    let mut t = clean.clone();
    for f in lo..=hi {
        t.xyz[a][f] = t.xyz[b][f];
        t.valid[b][f] = false;
    }
    let x = &the_one_new_find(&t, &opts, &base);
    assert_eq!(x.kind, FindKind::Swap, "{x:?}");
    assert_eq!(x.markers, vec![a.min(b), a.max(b)]);
    assert_eq!((x.first, x.last), (lo, hi), "{x:?}");
    assert!(x.settled, "{x:?}");
    undo(&mut t, std::slice::from_ref(x));
    // B holds its recorded point again, A is a gap over the span, the rest as recorded.
    assert_eq!(t.xyz[b], clean.xyz[b]);
    assert_eq!(t.valid[b], clean.valid[b]);
    assert!((lo..=hi).all(|f| !t.valid[a][f]));
    assert!((0..clean.frames())
        .filter(|f| !(lo..=hi).contains(f))
        .all(|f| t.valid[a][f] == clean.valid[a][f] && t.xyz[a][f] == clean.xyz[a][f]));
}

/// A swap to the trial's end between a marker without links (lower index) and one with
/// links is judged through the linked marker's links, as when the marker without links
/// has the higher index: the exchanged samples mend the linked marker's links.
#[test]
fn synthetic_swap_of_a_marker_without_links_and_a_lower_index_is_settled_to_the_end() {
    let mut clean = gait_like(30, 8, 2000, 100.0, 0.3, 11);
    // Marker 0 wanders on its own path: no distance to any marker is kept.
    for f in 0..clean.frames() {
        let t = f as f64;
        clean.xyz[0][f] = [
            600.0 + 300.0 * (t / 59.0).sin(),
            200.0 * (t / 83.0).cos(),
            1000.0 + 150.0 * (t / 37.0).sin(),
        ];
    }
    let opts = SwapOptions::default();
    let links = learn_links(&clean, opts.max_link_spread_mm, opts.min_link_support, 8);
    assert!(links[0].is_empty() && links[9].len() >= 2);
    assert!(find_swaps(&clean, &opts).unwrap().is_empty());
    let mut t = clean.clone();
    exchange(&mut t, 0, 9, 1500, 1999);
    let finds = find_swaps(&t, &opts).unwrap();
    assert_eq!(finds.len(), 1, "{finds:?}");
    let x = &finds[0];
    assert_eq!((x.kind, x.markers.clone()), (FindKind::Swap, vec![0, 9]));
    assert_eq!((x.first, x.last), (1500, 1999), "{x:?}");
    assert!(x.settled && x.evidence.frames_decided > 400, "{x:?}");
    undo(&mut t, &finds);
    assert_eq!(t, clean);
}
