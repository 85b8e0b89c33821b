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
    // Frames as the file numbers them.
    let (first, last) = (a.frame_number(5), a.frame_number(109));
    assert_eq!(first, 5 + a.first_frame());
    assert_eq!((m.first_frame, m.last_frame), (Some(first), Some(last)));
    // Within tolerance: nothing.
    assert!(c3d::diff::diff(&a, &b, 5.0).points.markers.len() == 1); // only the validity change
}

#[test]
fn minus_zero_is_zero() {
    let a = walk();
    let mut b = a.clone();
    let mut c = a.clone();
    let i = a.point_index("LTHI").unwrap();
    let k = b.points().index(7, i);
    b.points_mut().xyz[k][0] = 0.0;
    c.points_mut().xyz[k][0] = -0.0;
    assert!(c3d::diff::diff(&b, &c, 0.0).is_empty());
    c.parameters.get_mut("POINT", "RATE").unwrap().value = Value::Float(vec![-0.0]);
    b.parameters.get_mut("POINT", "RATE").unwrap().value = Value::Float(vec![0.0]);
    assert!(c3d::diff::diff(&b, &c, 0.0).is_empty());
}

fn corpus() -> Vec<std::path::PathBuf> {
    testkit::every_c3d_file()
}

/// The data difference between `a` and `a` converted as asked and read back (`None` when the
/// conversion is refused, e.g. data too large for integers).
fn round_trip(
    a: &c3d::C3d,
    processor: c3d::Processor,
    format: c3d::NumberFormat,
) -> Option<(c3d::C3d, Vec<String>)> {
    let bytes = a.converted(processor, format, None).ok()?.into_owned();
    let b = c3d::read(bytes).expect("a converted file reads back");
    let opts = c3d::diff::DiffOptions {
        tolerance: 0.0,
        data: true,
    };
    let d = c3d::diff::diff_with(a, &b, &opts);
    let mut what = Vec::new();
    if !d.is_empty() {
        what.push(serde_json::to_string(&d).unwrap_or_default());
    }
    Some((b, what))
}

#[test]
fn every_corpus_file_keeps_its_data_through_dec_and_float() {
    use c3d::{NumberFormat, Processor};
    use rayon::prelude::*;
    let files = corpus();
    if files.is_empty() {
        eprintln!("corpora absent (C3D_SAMPLES, C3D_EXTRA, C3D_MORE, C3D_FULLBODY): skipped");
        return;
    }
    let results: Vec<(String, usize, Vec<String>)> = files
        .par_iter()
        .filter_map(|f| {
            let a = c3d::read_file(f).ok()?;
            let mut trips = 0;
            let mut bad = Vec::new();
            let other = if a.processor() == Processor::Dec {
                Processor::Intel
            } else {
                Processor::Dec
            };
            // Intel (or SGI) → DEC → back, and DEC → Intel → back.
            if let Some((b, w)) = round_trip(&a, other, a.format()) {
                trips += 1;
                bad.extend(w);
                let back = b
                    .converted(a.processor(), a.format(), None)
                    .ok()?
                    .into_owned();
                let c = c3d::read(back).expect("reads back");
                let d = c3d::diff::diff_with(
                    &a,
                    &c,
                    &c3d::diff::DiffOptions {
                        tolerance: 0.0,
                        data: true,
                    },
                );
                trips += 1;
                if !d.is_empty() {
                    bad.push(serde_json::to_string(&d).unwrap_or_default());
                }
            }
            // Integers → floats → integers.
            if a.format() == NumberFormat::Integer {
                if let Some((b, w)) = round_trip(&a, a.processor(), NumberFormat::Float) {
                    trips += 1;
                    bad.extend(w);
                    if let Some((_, w)) = round_trip(&b, a.processor(), NumberFormat::Integer) {
                        trips += 1;
                        bad.extend(w);
                    }
                }
            }
            Some((testkit::short(f), trips, bad))
        })
        .collect();
    let bad: Vec<String> = results
        .iter()
        .filter(|r| !r.2.is_empty())
        .map(|r| format!("{}: {}", r.0, r.2.join(" | ")))
        .collect();
    let trips: usize = results.iter().map(|r| r.1).sum();
    assert!(bad.is_empty(), "{} files:\n{}", bad.len(), bad.join("\n"));
    assert!(results.len() >= 100, "{} files read", results.len());
    assert!(trips >= 2 * results.len(), "{trips} round trips");
}
