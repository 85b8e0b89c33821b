//! `c3dfix::label` on real trials (issue 47 item 2): labels stripped from a c3d-labs trial
//! put back from another trial of the same subject, real unlabelled points moved bit for
//! bit, reruns and bad input.

use c3dfix::label_stage::{FragmentOutcome, LabelSettings, LabelStatus};
use std::path::{Path, PathBuf};

fn labs(name: &str) -> Option<PathBuf> {
    let dir = testkit::c3d_labs()?;
    Some(dir.join(name))
}

const SLDJ03: &str = "psbiomech__lasem-data-processing__FAILT01_SLDJ03.c3d";
const SLDJ05: &str = "psbiomech__lasem-data-processing__FAILT01_SLDJ05.c3d";

/// `c` with every label of its markers (not its model outputs) replaced by `*N`.
fn stripped(c: &mut c3d::C3d) -> Vec<String> {
    let labels = c.point_labels();
    let markers = c3dfix::markers::marker_indices(c);
    let mut new = labels.clone();
    for (k, &p) in markers.iter().enumerate() {
        new[p] = format!("*{}", k + 1);
    }
    c.parameters
        .set_strings("POINT", "LABELS", &new)
        .expect("labels fit");
    labels
}

#[test]
fn a_stripped_drop_jump_is_labelled_from_another_jump_of_the_subject() {
    let (Some(trial), Some(template)) = (labs(SLDJ03), labs(SLDJ05)) else {
        return testkit::skipped("c3d-labs not found");
    };
    let mut c = c3d::read_file(&trial).unwrap();
    let t = c3d::read_file(&template).unwrap();
    let truth = stripped(&mut c);
    let r = c3dfix::label(&mut c, &trial, &t, &template, &LabelSettings::default()).unwrap();
    assert_eq!(r.status, LabelStatus::Labelled);
    assert!(r.seeded);
    let after = c.point_labels();
    let markers = c3dfix::markers::marker_indices(&c);
    let (mut right, mut wrong, mut left) = (0, 0, 0);
    for &p in &markers {
        if after[p].starts_with('*') {
            left += 1;
        } else if after[p].trim() == truth[p].trim() {
            right += 1;
        } else {
            wrong += 1;
            eprintln!("point {p}: {} labelled {}", truth[p], after[p]);
        }
    }
    eprintln!(
        "{right} right, {wrong} wrong, {left} left of {}",
        markers.len()
    );
    assert_eq!(wrong, 0);
    assert_eq!(right, 46, "{right} of {} markers", markers.len());
    // Whole trajectories: renamed in place, no sample moved.
    assert_eq!(r.renamed.len(), right);
    // The output is an ordinary labelled C3D, and labelling it again changes nothing.
    let bytes = c.encoded().unwrap().into_owned();
    let mut again = c3d::read(bytes.clone()).unwrap();
    let r2 = c3dfix::label(&mut again, &trial, &t, &template, &LabelSettings::default()).unwrap();
    assert_eq!(r2.status, LabelStatus::AlreadyLabelled);
    assert_eq!(again.encoded().unwrap().as_ref(), &bytes[..]);
}

#[test]
fn real_unlabelled_points_move_into_their_markers_bit_for_bit() {
    let dir = match testkit::c3d_labs() {
        Some(d) => d,
        None => return testkit::skipped("c3d-labs not found"),
    };
    let trial = dir.join("RehabEngGroup__MOtoNMS__Fast_Walking.c3d");
    let template = dir.join("RehabEngGroup__MOtoNMS__Cross_-_Overs_2.c3d");
    let before = c3d::read_file(&trial).unwrap();
    let mut c = before.clone();
    let t = c3d::read_file(&template).unwrap();
    let r = c3dfix::label(&mut c, &trial, &t, &template, &LabelSettings::default()).unwrap();
    assert_eq!(
        (r.template_markers, r.in_common, r.unlabelled_points),
        (51, 51, 29)
    );
    assert!(!r.seeded);
    assert!(r.moved_samples > 0 && r.renamed.is_empty());
    let (p0, p1) = (before.points(), c.points());
    let labels = before.point_labels();
    let index = |l: &str| labels.iter().position(|x| x.trim() == l).unwrap();
    let mut checked = 0;
    for f in &r.fragments {
        if !matches!(f.outcome, FragmentOutcome::Labelled { .. }) {
            continue;
        }
        let (from, to) = (index(&f.point), index(&f.written_to));
        let first = f.first_frame - c.first_frame();
        for k in first..first + (f.last_frame - f.first_frame + 1) {
            let (a, b) = (p0.index(k, from), p1.index(k, to));
            assert_eq!(p0.xyz[a].map(f32::to_bits), p1.xyz[b].map(f32::to_bits));
            assert_eq!(p0.residual[a].to_bits(), p1.residual[b].to_bits());
            assert_eq!(p0.camera_mask[a], p1.camera_mask[b]);
            // The marker had a gap there, and the unlabelled point is missing now.
            assert!(!p0.is_valid(k, to) && !p1.is_valid(k, from));
            checked += 1;
        }
    }
    assert_eq!(checked, r.labelled_samples);
    // Every parameter but the labels and the record is kept.
    for g in before.parameters.groups() {
        if g.name != "C3DFIX" {
            assert!(c.parameters.group(&g.name).is_some());
        }
    }
}

#[test]
fn a_trial_with_nothing_unlabelled_is_left_byte_for_byte() {
    let (Some(trial), Some(template)) = (labs(SLDJ03), labs(SLDJ05)) else {
        return testkit::skipped("c3d-labs not found");
    };
    let mut c = c3d::read_file(&trial).unwrap();
    let t = c3d::read_file(&template).unwrap();
    let r = c3dfix::label(&mut c, &trial, &t, &template, &LabelSettings::default()).unwrap();
    assert_eq!(r.status, LabelStatus::NothingUnlabelled);
    assert_eq!(
        c.encoded().unwrap().as_ref(),
        &std::fs::read(&trial).unwrap()[..]
    );
}

fn error_of(trial: &Path, c: &mut c3d::C3d, t: &c3d::C3d, tp: &Path) -> String {
    c3dfix::label(c, trial, t, tp, &LabelSettings::default())
        .unwrap_err()
        .to_string()
}

#[test]
fn another_marker_set_and_duplicate_labels_are_errors_naming_them() {
    let (Some(trial), Some(template), Some(walk)) = (
        labs(SLDJ03),
        labs(SLDJ05),
        labs("RehabEngGroup__MOtoNMS__Walking1.c3d"),
    ) else {
        return testkit::skipped("c3d-labs not found");
    };
    let w = c3d::read_file(&walk).unwrap();
    let mut c = c3d::read_file(&trial).unwrap();
    // Give the trial one unlabelled point so that the marker sets are compared.
    let mut labels = c.point_labels();
    labels[0] = "*1".into();
    c.parameters
        .set_strings("POINT", "LABELS", &labels)
        .unwrap();
    let e = error_of(&trial, &mut c.clone(), &w, &walk);
    assert!(
        e.contains("another marker set") || e.contains("no marker in common"),
        "{e}"
    );
    assert!(e.contains("Walking1"), "{e}");
    // Two template points of one name.
    let mut t = c3d::read_file(&template).unwrap();
    let mut tl = t.point_labels();
    tl[1] = tl[2].clone();
    t.parameters.set_strings("POINT", "LABELS", &tl).unwrap();
    let e = error_of(&trial, &mut c, &t, &template);
    assert!(
        e.contains("two points are labelled") && e.contains(tl[2].trim()),
        "{e}"
    );
}

/// A partly labelled trial (issue 47 item 3): the UWA fast walk's real unlabelled points go
/// into a labelled marker's gap only where reclaiming's path check at the gap's ends
/// accepts them. Before that check `label` moved 6275 samples there (564 of them the ones
/// `reclaim` settles, none onto another marker than reclaim's); now 942, the same 564
/// among them, and every moved stretch is one reclaiming judges on the marker's path.
#[test]
fn a_partly_labelled_walk_moves_only_what_the_path_at_the_gap_ends_accepts() {
    let Some(dir) = testkit::c3d_labs() else {
        return testkit::skipped("c3d-labs not found");
    };
    let trial = dir.join("RehabEngGroup__MOtoNMS__Fast_Walking.c3d");
    let template = dir.join("RehabEngGroup__MOtoNMS__Cross_-_Overs_2.c3d");
    let mut c = c3d::read_file(&trial).unwrap();
    let t = c3d::read_file(&template).unwrap();
    let r = c3dfix::label(&mut c, &trial, &t, &template, &LabelSettings::default()).unwrap();
    let off_path: usize = r
        .fragments
        .iter()
        .filter(|f| {
            matches!(
                &f.outcome,
                FragmentOutcome::Unlabelled {
                    why: c3dfix::label_stage::Unlabelled::OffPath { .. }
                }
            )
        })
        .map(|f| f.samples)
        .sum();
    // 5 333 off the path before the exchange check, which now leaves 175 of those samples
    // unlabelled first (`exchangeable`); the samples moved are the same.
    assert_eq!((r.labelled_samples, off_path), (942, 5158));
    // What reclaim settles, `label` moves to the same marker.
    let before = c3d::read_file(&trial).unwrap();
    let settled = c3dfix::reclaim(&before, &trial, &repair::Unlabelled::common(), false).unwrap();
    assert_eq!(
        settled.settled.iter().map(|s| s.samples).sum::<usize>(),
        797
    );
    let moved: std::collections::HashSet<(String, String, usize)> = r
        .fragments
        .iter()
        .filter(|f| matches!(f.outcome, FragmentOutcome::Labelled { .. }))
        .flat_map(|f| {
            (f.first_frame..=f.last_frame).map(|k| (f.written_to.clone(), f.point.clone(), k))
        })
        .collect();
    let mut agree = 0;
    for s in &settled.settled {
        for k in s.first_frame..=s.last_frame {
            agree += usize::from(moved.contains(&(s.marker.clone(), s.source.clone(), k)));
        }
    }
    assert_eq!(agree, 564);
}
