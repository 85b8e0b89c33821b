//! Which points are model outputs: the type lists (POINT:ANGLES, FORCES, …), every point
//! stored after the first listed one, and every segment's axes wherever stored
//! (`C3d::model_output_labels`). Checked on every corpus file: the points the rules add are
//! the Plug-in Gait writers' bone points, virtual markers, centre of mass and muscle lengths,
//! never a marker.

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

/// What a rule says of each corpus file, by file name, where it says anything.
type Found = BTreeMap<String, Vec<String>>;

/// Every corpus file and what `labels` says of it; `None` (a skip said) without the corpora.
fn per_file(labels: impl Fn(&c3d::C3d) -> Vec<String>) -> Option<(Vec<std::path::PathBuf>, Found)> {
    let files = testkit::every_c3d_file();
    if files.is_empty() {
        testkit::skipped("no corpus (C3D_SAMPLES, C3D_EXTRA, C3D_FULLBODY, C3D_MORE)");
        return None;
    }
    let mut found = BTreeMap::new();
    for f in &files {
        let Ok(c) = c3d::read_file(f) else { continue };
        let a = labels(&c);
        if !a.is_empty() {
            found.insert(name(f), a);
        }
    }
    Some((files, found))
}

#[test]
fn points_after_the_first_listed_output_are_outputs() {
    let Some((files, found)) = per_file(added) else {
        return;
    };
    let counts: Vec<(&str, usize)> = found.iter().map(|(k, v)| (k.as_str(), v.len())).collect();
    assert_eq!(
        counts,
        vec![
            // 36 bones after the first output, and 8 global and trunk axes among the markers
            ("2198928.c3d", 44),
            ("HansUniVie__MuscleLength__test.c3d", 154),
            // the axes alone: no output listed
            ("PhilD001__biomechZoo__ti003.c3d", 76),
            ("PlugInC3D.c3d", 36),
            ("PolygonC3D.c3d", 36),
            // the axes alone: a static trial
            ("btkdata_PiG_Calibration-FlatFoot-One.c3d", 76),
            ("btkdata_parameterOverflow.c3d", 30),
            // the centre of mass after the first output, 76 bones among the markers
            ("cadop__pyCGM__Movement_trial.c3d", 78),
            ("gait-pig.c3d", 36),
            ("martinfelis__puppeteer__testdata.c3d", 76),
            ("sub_labels.c3d", 36),
            // 36 bones stored before the markers
            ("tsalemink__C3D-parser__FMC_MH0222_BP15.c3d", 36),
            ("tsalemink__C3D-parser__RBWH_bfnd_w1.c3d", 38),
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
    assert!(pig.iter().all(|l| is_axis_label(l)));
    assert_eq!(
        found["cadop__pyCGM__Movement_trial.c3d"][..2],
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

/// A bone point's label: a segment's three letters and O, A, L or P (origin, anterior,
/// lateral, proximal), or another model's axis points (o_, x_, y_, z_ and a segment's name).
fn is_axis_label(l: &str) -> bool {
    let b = l.rsplit(':').next().unwrap_or(l);
    let pig = b.len() == 4 && ["O", "A", "L", "P"].iter().any(|s| b.ends_with(s));
    let named = ["o_", "x_", "y_", "z_"].iter().any(|s| b.starts_with(s));
    pig || named
}

#[test]
fn segment_axes_are_found_by_their_geometry_wherever_stored() {
    let Some((_, found)) = per_file(|c| {
        let l = c.layout();
        let quantum = if l.float {
            0.0
        } else {
            f64::from(l.point_scale)
        };
        let labels = c.point_labels();
        let axes: Vec<String> = c3d::segment_axes(c.points(), quantum)
            .into_iter()
            .map(|i| labels[i].clone())
            .collect();
        // The bones the geometry leaves to the order rule: the left foot of one Plug-in
        // Gait version, whose axes are 6° off square (cosine 0.10), in the four files that
        // version wrote (each a copy of one subject's trial).
        let mut left: Vec<String> = c
            .model_output_labels()
            .into_iter()
            .filter(|l| is_axis_label(l) && !axes.contains(l))
            .map(|l| l.rsplit(':').next().unwrap_or(&l).to_string())
            .filter(|b| {
                b.len() == 4 && b.ends_with(['O', 'A', 'L', 'P']) && b.starts_with(['L', 'R', 'P'])
            })
            // HansUniVie's hip and knee joint points, named like bones, are not axes
            .filter(|b| b.as_str() != "HIPL" && b.as_str() != "KNEL")
            .collect();
        left.sort();
        if !axes.is_empty() && !left.is_empty() {
            assert_eq!(left, ["LFOA", "LFOL", "LFOP"], "{axes:?}");
        }
        axes
    }) else {
        return;
    };
    // Every point the geometry finds is a segment's axes by its label too (the labels are
    // read here only to check the rule, which never reads them), in integer files (steps of
    // 0.08–0.11 mm) as in float ones; no marker of any corpus file, cluster or skin, passes.
    for (file, axes) in &found {
        for l in axes {
            assert!(is_axis_label(l), "{file}: {l}");
        }
    }
    let counts: Vec<(&str, usize)> = found.iter().map(|(k, v)| (k.as_str(), v.len())).collect();
    assert_eq!(
        counts,
        vec![
            ("2198928.c3d", 44),
            ("HansUniVie__MuscleLength__test.c3d", 36),
            ("PhilD001__biomechZoo__ti003.c3d", 76),
            ("PlugInC3D.c3d", 33),
            ("PolygonC3D.c3d", 33),
            ("btkdata_PiG_Calibration-FlatFoot-One.c3d", 76),
            ("cadop__pyCGM__Movement_trial.c3d", 76),
            ("gait-pig.c3d", 33),
            ("martinfelis__puppeteer__testdata.c3d", 76),
            ("sub_labels.c3d", 33),
            ("tsalemink__C3D-parser__FMC_MH0222_BP15.c3d", 36),
            ("tsalemink__C3D-parser__RBWH_bfnd_w1.c3d", 36),
        ]
    );
    // ART's tracked bodies store an origin and two axis points each: not a segment's three
    // axes, so they stay the trial's points (they are its only data).
    assert!(!found
        .keys()
        .any(|k| k.contains("ART") || k.contains("arthuman")));
}
