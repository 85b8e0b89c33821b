//! The session report on real trials: every row's numbers are those of the repair that made
//! the repaired copy (its own summary, or the C3DFIX record it left), and a trial that cannot
//! be read is a row saying why.

use c3dfix::files::Destination;
use c3dfix::report::{report, report_trials, ReportOptions, TrialInput};
use c3dfix::targets::{plan, Destination as To};
use c3dfix::{RepairBrief, RepairOptions};
use std::path::{Path, PathBuf};

/// Every trial of `dir` repaired into `out` as `batch --out-dir` does (the library's one
/// repair of a file), with its summary.
fn repair_all(dir: &Path, out: &Path) -> Vec<(PathBuf, PathBuf, RepairBrief)> {
    let p = plan(&[dir.to_path_buf()], To::OutDir(out), None).unwrap();
    p.targets
        .iter()
        .map(|t| {
            t.prepare_output(false).unwrap();
            let dest = Destination {
                output: Some(t.output.clone()),
                ..Destination::default()
            };
            let done =
                c3dfix::files::repair(&t.input, &dest, &RepairOptions::default(), None).unwrap();
            (t.input.clone(), t.output.clone(), done.brief())
        })
        .collect()
}

/// The labelled markers' missing samples (an unlabelled point's absences are no marker's:
/// `repair::Unlabelled`'s common spellings are left out, as the repair leaves them).
fn missing(path: &Path) -> usize {
    let c = c3dfix::open(path).unwrap();
    let rule = repair::Unlabelled::common();
    c3dfix::gaps(&c, false)
        .iter()
        .filter(|g| !rule.is_unlabelled(&g.label))
        .map(|g| g.length)
        .sum()
}

#[test]
fn rows_equal_the_repairs_summaries_and_records_on_c3d_more() {
    let Some(dir) = testkit::c3d_more() else {
        return;
    };
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("repaired");
    let done = repair_all(&dir, &out);
    assert_eq!(done.len(), 20);
    // Made right after the repairs, from their summaries (`batch --report-html`).
    let inputs: Vec<TrialInput> = done
        .iter()
        .map(|(i, o, s)| TrialInput {
            input: i.clone(),
            repaired: Some(o.clone()),
            summary: Some(Ok(s.clone())),
        })
        .collect();
    let from_summaries = report_trials(&inputs, false);
    // Made later, from the folders (`report DIR --repaired OUT`): the records.
    let from_records = report(&ReportOptions {
        paths: vec![dir.clone()],
        repaired: Some(out.clone()),
        views: true,
    })
    .unwrap();
    let mut filled = 0;
    for (k, (input, output, brief)) in done.iter().enumerate() {
        let s = &brief.summary;
        let a = &from_summaries.trials[k];
        let b = &from_records.trials[k];
        let name = testkit::short(input);
        assert_eq!(a.file, input.display().to_string());
        assert_eq!(b.file, a.file, "{name}: rows in the plan's order");
        assert_eq!(a.repair_source, Some("summary"));
        assert_eq!(b.repair_source, Some("record"), "{name}");
        assert_eq!(a.markers, s.markers, "{name}");
        assert_eq!(a.filled, Some(s.filled), "{name}");
        assert_eq!(a.left, Some(s.left), "{name}");
        assert_eq!(a.left_because, s.left_because, "{name}");
        assert_eq!(a.spikes, Some(s.spikes), "{name}");
        assert_eq!(a.swaps_found, Some(brief.swap_list.len()), "{name}");
        assert_eq!(a.expected_error_mm_max, s.expected_error_mm_max, "{name}");
        let at_ends = brief
            .gap_list
            .iter()
            .filter(|g| g.reason.is_some() && g.at_trial_end)
            .count();
        assert_eq!(a.left_at_trial_end, at_ends, "{name}");
        // What the file records is what the repair said.
        for r in [a, b] {
            assert_eq!(r.filled, Some(s.filled), "{name}");
            assert_eq!(r.left, Some(s.left), "{name}");
            assert_eq!(r.left_because, s.left_because, "{name}");
            assert_eq!(r.left_at_trial_end, at_ends, "{name}");
            assert_eq!(r.missing_before, missing(input), "{name}");
            assert_eq!(r.missing_after, Some(missing(output)), "{name}");
            assert_eq!(r.gaps_before, s.gaps, "{name}: every gap is judged");
        }
        // Each filled gap is drawn as filled, and every sample still missing as missing.
        let drawn_missing: usize = b
            .pictures
            .coverage
            .iter()
            .flat_map(|c| &c.runs)
            .filter(|r| r.2 == 0)
            .map(|r| r.1 - r.0 + 1)
            .sum();
        assert_eq!(Some(drawn_missing), b.missing_after, "{name}");
        assert!(b.view.is_some(), "{name}");
        assert!(a.pictures.fills.len() <= 3);
        assert_eq!(a.pictures.fills.len(), s.filled.min(3), "{name}");
        filled += s.filled;
    }
    // The corpus' numbers, as `batch c3d-more --json` prints them (labelled markers only:
    // pyCGM's and the puppeteer's unlabelled points are no longer filled, issue 47).
    assert_eq!(filled, 655);
    assert_eq!(from_records.summary.filled, 655);
    assert_eq!(from_records.summary.left, 101);
    assert_eq!(from_records.summary.left_at_trial_end, 94);
    assert_eq!(from_summaries.summary.swaps_found, 3);
    assert_eq!(from_records.summary.trials, 20);
    assert_eq!(from_records.summary.unreadable, 0);
    // Missing after: the sum over the repaired copies; without them, not known (not 0).
    let after: usize = from_records
        .trials
        .iter()
        .filter_map(|r| r.missing_after)
        .sum();
    assert_eq!(from_records.summary.missing_after, Some(after));
    let alone = report(&ReportOptions {
        paths: vec![dir.clone()],
        repaired: None,
        views: false,
    })
    .unwrap();
    assert_eq!(alone.summary.missing_after, None);
    assert_eq!(
        alone.summary.missing_before,
        from_records.summary.missing_before
    );
    // The trial with four plates: its plates and events as `info` and `events` say.
    let hans = from_records
        .trials
        .iter()
        .find(|r| r.name == "HansUniVie__MuscleLength__test.c3d")
        .unwrap();
    assert_eq!(hans.plates.len(), 4);
    assert_eq!(hans.events.get("file"), Some(&9));
    assert_eq!(hans.pictures.forces.len(), 4);
    assert!(hans.gait.iter().any(|g| g.name == "Cadence"));
}

#[test]
fn an_unreadable_trial_is_a_row_saying_why() {
    let Some(dir) = testkit::c3d_more() else {
        return;
    };
    let tmp = tempfile::tempdir().unwrap();
    let good = dir.join("tsalemink__C3D-parser__AUC_CB_Dynamic0003.c3d");
    let bytes = std::fs::read(&good).unwrap();
    std::fs::copy(&good, tmp.path().join("a_good.c3d")).unwrap();
    std::fs::write(
        tmp.path().join("b_truncated.c3d"),
        &bytes[..bytes.len() / 3],
    )
    .unwrap();
    std::fs::write(tmp.path().join("c_not_c3d.c3d"), b"frame,x,y,z\n1,2,3,4\n").unwrap();
    let rep = report(&ReportOptions {
        paths: vec![tmp.path().to_path_buf()],
        ..ReportOptions::default()
    })
    .unwrap();
    assert_eq!(rep.trials.len(), 3);
    assert_eq!(rep.summary.unreadable, 2);
    assert!(rep.trials[0].error.is_none());
    assert_eq!(rep.trials[0].frames, 207);
    for r in &rep.trials[1..] {
        let e = r.error.as_deref().expect("an error");
        assert!(e.contains(&r.name), "the error names the file: {e}");
        assert!(r.problem.as_deref().unwrap().starts_with("cannot be read"));
        assert_eq!(r.frames, 0);
    }
    assert_eq!(rep.summary.worst[0].row, 1);
}

#[test]
fn a_trial_without_its_repaired_copy_says_so() {
    let Some(dir) = testkit::c3d_more() else {
        return;
    };
    let tmp = tempfile::tempdir().unwrap();
    let (input, copies) = (tmp.path().join("in"), tmp.path().join("out"));
    std::fs::create_dir_all(&input).unwrap();
    for n in [
        "tsalemink__C3D-parser__AUC_CB_Dynamic0003.c3d",
        "tsalemink__C3D-parser__RBWH_bfnd_w1.c3d",
    ] {
        std::fs::copy(dir.join(n), input.join(n)).unwrap();
    }
    let done = repair_all(&input, &copies);
    std::fs::remove_file(&done[1].1).unwrap();
    let rep = report(&ReportOptions {
        paths: vec![input.clone()],
        repaired: Some(copies.clone()),
        views: false,
    })
    .unwrap();
    assert_eq!(rep.trials[0].repair_source, Some("record"));
    assert_eq!(rep.trials[0].filled, Some(done[0].2.summary.filled));
    let r = &rep.trials[1];
    assert!(r.error.is_none());
    let e = r.repaired_error.as_deref().expect("the missing copy said");
    assert!(e.contains("RBWH_bfnd_w1.c3d"), "{e}");
    assert!(r.problem.as_deref().unwrap().starts_with("repaired copy:"));
    assert_eq!(rep.summary.worst[0].row, 1);
}
