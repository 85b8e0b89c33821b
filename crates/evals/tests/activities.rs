//! Each corpus trial's activity, read by rule from its corpus's README (see
//! `corpus::activity`, which `fill_eval --activities` reports the expected errors by): the
//! rule must name what the README says, on the real READMEs.

use evals::corpus::{activity, FILES};

/// Every listed trial of `corpus` with its activity (README from `root`).
fn activities(root: &std::path::Path, corpus: &str) -> Vec<(&'static str, &'static str)> {
    let readme = std::fs::read_to_string(root.join("README.md")).ok();
    FILES
        .iter()
        .filter(|f| f.2 == corpus)
        .map(|f| (f.3, activity(readme.as_deref(), f.3, f.0)))
        .collect()
}

fn of<'a>(v: &[(&str, &'a str)], file: &str) -> &'a str {
    v.iter()
        .find(|x| x.0 == file)
        .map(|x| x.1)
        .unwrap_or_else(|| panic!("{file} is not in the corpus list"))
}

#[test]
fn c3d_more_activities_come_from_its_readme_column() {
    let Some(root) = testkit::c3d_more() else {
        return;
    };
    let v = activities(&root, "more");
    assert_eq!(v.len(), 20);
    assert_eq!(of(&v, "keenon__nimblephysics__JA1Gait35.c3d"), "running");
    assert_eq!(of(&v, "keenon__nimblephysics__squat.c3d"), "squats");
    assert_eq!(
        of(&v, "opensim-org__opensim-core__doubleLegLanding.c3d"),
        "landing"
    );
    assert_eq!(of(&v, "cadop__pyCGM__Movement_trial.c3d"), "stairs");
    // "ice-hockey shot, Plug-in Gait + stick": the sport, not the marker set's gait.
    assert_eq!(of(&v, "PhilD001__biomechZoo__ti003.c3d"), "sports");
    assert_eq!(of(&v, "keenon__nimblephysics__cmu_02_05.c3d"), "sports");
    assert_eq!(
        of(&v, "keenon__nimblephysics__nick_freeform_001.c3d"),
        "free movement"
    );
    let walking = v.iter().filter(|x| x.1 == "walking").count();
    assert_eq!(walking, 11, "{v:?}");
}

#[test]
fn full_body_sequences_without_a_named_activity_stay_unnamed() {
    let Some(root) = testkit::c3d_fullbody() else {
        return;
    };
    let v = activities(&root, "fullbody");
    // The README names the numediart trial's activity, not the CMU ones'.
    assert_eq!(of(&v, "03_rolling.c3d"), "rolling on the floor");
    for cmu in ["85_02.c3d", "85_12.c3d", "135_02.c3d"] {
        assert_eq!(of(&v, cmu), "other full body");
    }
}

#[test]
fn sample_trials_fall_back_on_their_file_names_and_set() {
    let Some(root) = testkit::c3d_samples() else {
        return;
    };
    let v = activities(&root, "samples");
    assert_eq!(of(&v, "sample_34/Basketball.c3d"), "sports");
    assert_eq!(of(&v, "sample_13/Dance1.c3d"), "dance");
    assert_eq!(
        of(&v, "sample_00/Motion Analysis Corporation/Sample_Jump2.c3d"),
        "jumping"
    );
    assert_eq!(of(&v, "sample_09/PlugInC3D.c3d"), "walking");
    assert_eq!(of(&v, "sample_34/AlbertoREAL.c3d"), "other full body");
}

#[test]
fn c3d_labs_activities_come_from_its_readme_column() {
    let Some(root) = testkit::c3d_labs() else {
        return;
    };
    let v = activities(&root, "labs");
    assert_eq!(v.len(), 21);
    assert_eq!(
        of(&v, "psbiomech__lasem-data-processing__FAILT01_SLDJ03.c3d"),
        "jumping"
    );
    assert_eq!(
        of(&v, "RehabEngGroup__MOtoNMS__Cross_-_Overs_2.c3d"),
        "cutting"
    );
    assert_eq!(
        of(&v, "basgoncalves__msk_modelling_python__sprint_1.c3d"),
        "running"
    );
    assert_eq!(
        of(&v, "vaila-multimodaltoolbox__vaila__C3D_to_CSV_01.c3d"),
        "sit-to-stand"
    );
    assert_eq!(of(&v, "pyomeca__pyomeca__markers_analogs.c3d"), "lifting");
    // "walking (likely treadmill/overground, 8.7 s)": walking, though its row names no gait.
    assert_eq!(
        of(&v, "RealTimeBiomechanics__rtosim__walking_1.c3d"),
        "walking"
    );
    let count = |a: &str| v.iter().filter(|x| x.1 == a).count();
    assert_eq!(
        (count("walking"), count("running"), count("lifting")),
        (8, 5, 2),
        "{v:?}"
    );
}
