//! `diff` finds each kind of change, and nothing else.

use c3d::{Record, Value};

fn walk() -> c3d::C3d {
    c3d::read_file(testkit::workspace_root().join("sample_c3d/walk_float.c3d")).unwrap()
}

#[test]
fn identical_files_have_no_differences() {
    let a = walk();
    assert!(c3d::diff::diff(&a, &a.clone(), 0.0).is_empty());
}

#[test]
fn parameter_changes_are_classified() {
    let a = walk();
    let mut b = a.clone();
    b.parameters.get_mut("POINT", "RATE").unwrap().value = Value::Float(vec![120.0]);
    b.parameters.get_mut("POINT", "UNITS").unwrap().locked = true;
    b.parameters.get_mut("POINT", "LABELS").unwrap().description = "marker names".into();
    b.parameters.remove("SUBJECTS", "USES_PREFIXES");
    b.parameters.set_i16("VENDOR", "FLAG", 1).unwrap();
    let d = c3d::diff::diff(&a, &b, 0.0);
    let got: Vec<(String, String)> = d
        .parameters
        .iter()
        .map(|p| (p.name.clone(), p.change.clone()))
        .collect();
    for want in [
        ("POINT:RATE", "value"),
        ("POINT:UNITS", "locked"),
        ("POINT:LABELS", "description"),
        ("SUBJECTS:USES_PREFIXES", "removed"),
        ("VENDOR", "added"),
        ("VENDOR:FLAG", "added"),
    ] {
        assert!(
            got.contains(&(want.0.into(), want.1.into())),
            "{want:?} not in {got:?}"
        );
    }
    assert_eq!(got.len(), 6, "{got:?}");
    assert!(!d.parameters_reordered);

    let mut c = a.clone();
    let last = c.parameters.records.pop().unwrap();
    c.parameters.records.insert(1, last);
    assert!(matches!(c.parameters.records[0], Record::Group(_)));
    let d = c3d::diff::diff(&a, &c, 0.0);
    assert!(d.parameters_reordered && d.parameters.is_empty());
}

#[test]
fn point_changes_are_counted_per_marker() {
    let a = walk();
    let mut b = a.clone();
    let i = a.point_index("LTHI").unwrap();
    for f in 100..110 {
        let k = b.points().index(f, i);
        b.points_mut().xyz[k][2] += 3.0;
    }
    let k = b.points().index(5, i);
    b.points_mut().residual[k] = -1.0;
    let d = c3d::diff::diff(&a, &b, 0.5);
    assert_eq!(d.points.markers.len(), 1);
    let m = &d.points.markers[0];
    assert_eq!(m.label, "LTHI");
    assert_eq!(m.frames_changed, 11);
    assert_eq!(m.became_invalid, 1);
    assert!((m.max_displacement - 3.0).abs() < 1e-3);
    assert_eq!((m.first_frame, m.last_frame), (Some(5), Some(109)));
    // Within tolerance: nothing.
    assert!(c3d::diff::diff(&a, &b, 5.0).points.markers.len() == 1); // only the validity change
}
