//! The lab's up from markers is one rule whether the samples are read chunk by chunk from a
//! file (`markers_up`, what `info` and the exports use) or held in memory (`points_up`, what
//! the viewer uses for BVH skeletons): both give the same direction on every corpus trial.

use c3dfix::axes::{markers_up, points_up};

/// The markers of `c` (model outputs left out) as points of their own.
fn markers_only(c: &c3d::C3d) -> c3d::Points {
    let keep = c3dfix::markers::marker_indices(c);
    let src = c.points();
    let mut p = c3d::Points::new(src.frames(), keep.len());
    for f in 0..src.frames() {
        for (j, &i) in keep.iter().enumerate() {
            let (from, to) = (src.index(f, i), p.index(f, j));
            p.xyz[to] = src.xyz[from];
            p.residual[to] = src.residual[from];
        }
    }
    p
}

#[test]
fn points_up_is_markers_up_on_every_corpus_trial() {
    let files = testkit::every_c3d_file();
    if files.is_empty() {
        testkit::skipped("axes: no corpus");
        return;
    }
    let mut seen = std::collections::BTreeMap::new();
    for f in &files {
        let Ok(c) = c3dfix::open(f) else { continue };
        let mm = c3d::mm_per_unit(&c.point_units()) as f32;
        let want = markers_up(&c);
        assert_eq!(
            points_up(&markers_only(&c), mm),
            want,
            "{}",
            testkit::short(f)
        );
        *seen
            .entry(want.map_or("none".to_string(), |d| d.to_string()))
            .or_insert(0) += 1;
    }
    // Most labs stand on +z; Y-up ones, lying or sideways subjects, and trials without two
    // valid markers in any frame ("none") are there too. HansUniVie's clinical gait trial
    // read +y while its 154 muscle lengths, bones and virtual points counted as markers; its
    // 26 markers stand on +z, as its plates and its POINT:Y_SCREEN (+Z) say.
    let counts: Vec<(&str, usize)> = seen.iter().map(|(k, &n)| (k.as_str(), n)).collect();
    assert_eq!(
        counts,
        [("+x", 4), ("+y", 10), ("+z", 89), ("-x", 2), ("none", 9)]
    );
}

#[test]
fn a_fullbody_trial_stands_on_z() {
    let Some(d) = testkit::c3d_fullbody() else {
        testkit::skipped("axes: c3d-fullbody not found");
        return;
    };
    let c = c3dfix::open(d.join("85_02.c3d")).unwrap();
    let up = points_up(&markers_only(&c), 1.0).unwrap();
    assert_eq!(up.to_string(), "+z");
}
