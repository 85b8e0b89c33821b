//! Which points are model outputs: the type lists (POINT:ANGLES, FORCES, …) and every point
//! stored after the first listed one (`C3d::model_output_labels`). Checked on every corpus
//! file: the points the rule adds are the Plug-in Gait writers' bone points, virtual
//! markers, centre of mass and muscle lengths, never a marker.

use std::collections::BTreeMap;

/// Points the type lists leave out but the order rule makes outputs, per file.
fn added(c: &c3d::C3d) -> Vec<String> {
    let listed: Vec<String> = c3d::MODEL_OUTPUT_TYPES
        .iter()
        .flat_map(|p| c.parameters.get_strings("POINT", p).unwrap_or_default())
        .collect();
    c.model_output_labels()
        .into_iter()
        .filter(|l| !listed.contains(l))
        .collect()
}

/// The file's name (the corpora's names are unique).
fn name(f: &std::path::Path) -> String {
    f.file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default()
}

#[test]
fn points_after_the_first_listed_output_are_outputs() {
    let files = testkit::every_c3d_file();
    if files.is_empty() {
        testkit::skipped("no corpus (C3D_SAMPLES, C3D_EXTRA, C3D_FULLBODY, C3D_MORE)");
        return;
    }
    let mut found = BTreeMap::new();
    for f in &files {
        let Ok(c) = c3d::read_file(f) else { continue };
        let a = added(&c);
        if !a.is_empty() {
            found.insert(name(f), a);
        }
    }
    let counts: Vec<(&str, usize)> = found.iter().map(|(k, v)| (k.as_str(), v.len())).collect();
    assert_eq!(
        counts,
        vec![
            ("2198928.c3d", 36),
            ("HansUniVie__MuscleLength__test.c3d", 154),
            ("PlugInC3D.c3d", 36),
            ("PolygonC3D.c3d", 36),
            ("btkdata_parameterOverflow.c3d", 30),
            ("cadop__pyCGM__Movement_trial.c3d", 2),
            ("gait-pig.c3d", 36),
            ("sub_labels.c3d", 36),
            ("tsalemink__C3D-parser__RBWH_bfnd_w1.c3d", 2),
        ]
    );
    // What they are: bone points (segment origin, proximal, anterior, lateral), the centre
    // of mass, and HansUniVie's virtual markers and muscle lengths.
    let bare = |l: &str| l.rsplit(':').next().unwrap_or(l).to_string();
    let pig = &found["2198928.c3d"];
    assert_eq!(
        pig[..4].iter().map(|l| bare(l)).collect::<Vec<_>>(),
        ["PELO", "PELP", "PELA", "PELL"]
    );
    assert!(pig.iter().all(|l| {
        let b = bare(l);
        b.len() == 4 && ["O", "P", "A", "L"].iter().any(|s| b.ends_with(s))
    }));
    assert_eq!(
        found["cadop__pyCGM__Movement_trial.c3d"],
        ["CentreOfMass", "CentreOfMassFloor"]
    );
    let hans = &found["HansUniVie__MuscleLength__test.c3d"];
    for l in [
        "PELO",
        "RTOL",
        "HIPL",
        "RASIv",
        "Rglut_min2",
        "Lsoleus",
        "Lext_dig",
    ] {
        assert!(hans.iter().any(|h| h == l), "{l} not an output");
    }
    // Markers stay markers: the last marker before each file's first output.
    for (file, marker) in [
        ("HansUniVie__MuscleLength__test.c3d", "LUL1"),
        ("2198928.c3d", "RTOE"),
    ] {
        let path = files.iter().find(|f| name(f) == file).unwrap();
        let c = c3d::read_file(path).unwrap();
        assert!(
            !c.model_output_labels().iter().any(|l| l == marker),
            "{file}: {marker}"
        );
    }
}
