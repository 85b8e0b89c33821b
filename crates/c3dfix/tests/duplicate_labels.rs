//! A trial whose labels repeat (two subjects without prefixes, a marker set that names a
//! cluster's markers alike) is repaired as one whose labels do not (issue 45 item 8): the
//! swap stage, the fills and the file's record speak of points by their number, never by
//! their label, so a swap is undone exactly whatever the labels say.

use c3dfix::{RepairOptions, SwapsMode};

/// The points of `c` whose label is `l`'s twin: every label given to two points, point
/// `i` taking the label of point `i − i % 2`.
fn labels_twice(c: &mut c3d::C3d) {
    let labels = c.point_labels();
    let twice: Vec<String> = (0..labels.len())
        .map(|i| labels[i - i % 2].clone())
        .collect();
    c.parameters
        .set_strings("POINT", "LABELS", &twice)
        .expect("the labels are rewritten");
}

/// Every point's samples, as written: coordinates and residuals, bit for bit.
fn samples(c: &c3d::C3d) -> Vec<(Vec<[u32; 3]>, Vec<u32>)> {
    let p = c.points();
    (0..c.point_labels().len())
        .map(|i| {
            (
                p.trajectory(i)
                    .iter()
                    .map(|q| [q[0].to_bits(), q[1].to_bits(), q[2].to_bits()])
                    .collect(),
                p.residuals(i).iter().map(|r| r.to_bits()).collect(),
            )
        })
        .collect()
}

/// `nick_freeform_001.c3d` (c3d-more, keenon) carries a settled swap of Nick01:LIWR and
/// Nick01:LOHAND from its first frame to frame 200 (see `swap_finds.rs`). With every label
/// given to two points, `repair --swaps fix` makes the same exchange and the same fills:
/// every point's samples come out bit for bit as with the file's own labels, and the
/// exchanged stretch is the swap's.
#[test]
fn a_settled_swap_is_undone_exactly_where_every_label_names_two_points() {
    let Some(dir) = testkit::c3d_more() else {
        testkit::skipped("C3D_MORE absent");
        return;
    };
    let path = dir.join("keenon__nimblephysics__nick_freeform_001.c3d");
    let original = c3d::read_file(&path).expect("the trial reads");
    let opts = RepairOptions {
        swaps: SwapsMode::Fix,
        ..RepairOptions::default()
    };
    let repaired = |mut c: c3d::C3d| {
        let r = c3dfix::repair(&mut c, &opts, &path).expect("the trial is repaired");
        (c, r.report())
    };
    let (plain, plain_report) = repaired(original.clone());
    let mut twice = original.clone();
    labels_twice(&mut twice);
    assert!(
        twice
            .point_labels()
            .iter()
            .filter(|l| **l == "Nick01:LIWR")
            .count()
            == 2
            || twice
                .point_labels()
                .iter()
                .filter(|l| **l == "Nick01:LOHAND")
                .count()
                == 2
    );
    let (dup, dup_report) = repaired(twice);

    // The swap was found and exchanged in both.
    let exchanged = |r: &serde_json::Value| -> Vec<(u64, u64)> {
        r["swaps"]
            .as_array()
            .unwrap()
            .iter()
            .filter(|s| s["kind"] == "swap" && s["settled"] == true)
            .map(|s| {
                (
                    s["first_frame"].as_u64().unwrap(),
                    s["last_frame"].as_u64().unwrap(),
                )
            })
            .collect()
    };
    let e = exchanged(&plain_report);
    assert!(e.contains(&(original.frame_number(0) as u64, 200)), "{e:?}");
    assert_eq!(e, exchanged(&dup_report));
    assert_eq!(
        plain_report["summary"]["filled"], dup_report["summary"]["filled"],
        "the same gaps filled"
    );

    // Bit for bit the same samples in every point.
    let (a, b) = (samples(&plain), samples(&dup));
    assert_eq!(a.len(), b.len());
    let differ: Vec<usize> = (0..a.len()).filter(|&i| a[i] != b[i]).collect();
    assert!(differ.is_empty(), "points {differ:?} differ");
    // And the swap was undone: the repaired file's samples are not the original's.
    assert_ne!(samples(&original), a);
}
