//! Force platforms against the independent reference (`tests/reference/force_plates.py`,
//! written from the C3D manual alone, its output committed as `force_plates.json`): every
//! plate of every corpus file that has plates, at the reference's check samples.

use c3dfix::{force_platforms, ForceOptions, ForcePlatforms};
use serde_json::Value;
use std::path::PathBuf;

fn reference() -> Value {
    let path = testkit::workspace_root().join("tests/reference/force_plates.json");
    let text = std::fs::read_to_string(&path).expect("tests/reference/force_plates.json");
    serde_json::from_str(&text).expect("reference JSON")
}

/// The corpus file a reference key ("c3d-more/x.c3d") names, or `None` (said) when that
/// corpus is absent outside CI.
fn corpus_file(key: &str) -> Option<PathBuf> {
    let (corpus, rest) = key.split_once('/')?;
    let dir = match corpus {
        "c3d-samples" => testkit::c3d_samples(),
        "c3d-extra" => testkit::c3d_extra(),
        "c3d-fullbody" => testkit::c3d_fullbody(),
        "c3d-more" => testkit::c3d_more(),
        _ => None,
    }?;
    Some(dir.join(rest))
}

fn v3(v: &Value) -> Option<[f64; 3]> {
    let a = v.as_array()?;
    let f = |i: usize| a.get(i).and_then(Value::as_f64);
    Some([f(0)?, f(1)?, f(2)?])
}

/// Largest |difference| between ours and the reference's vectors at the check samples,
/// relative to `scale` (the quantity's largest magnitude on the plate): the reference is
/// rounded to 6 significant digits (half a unit of the sixth digit is 5e-6 of a value), so
/// agreement is expected within 6e-6 of the scale.
fn worst(ours: &[[f64; 3]], theirs: &Value, check: &[usize]) -> (f64, usize) {
    let mut w = (0.0f64, 0);
    for (j, &s) in check.iter().enumerate() {
        let Some(t) = v3(&theirs[j]) else { continue };
        let o = ours[s];
        for k in 0..3 {
            let d = (o[k] - t[k]).abs();
            if d > w.0 {
                w = (d, s);
            }
        }
    }
    w
}

fn magnitude(v: &[[f64; 3]]) -> f64 {
    v.iter()
        .flatten()
        .filter(|x| x.is_finite())
        .fold(0.0f64, |m, x| m.max(x.abs()))
}

#[test]
fn every_corpus_plate_equals_the_reference() {
    let r = reference();
    let files = r.as_object().expect("files");
    let (mut plates, mut samples, mut skipped) = (0, 0, 0);
    for (key, entry) in files {
        let Some(path) = corpus_file(key) else {
            skipped += 1;
            continue;
        };
        if entry.get("error").is_some() {
            // Files the reference cannot read (no C3D; ANALOG:SCALE or OFFSET shorter than
            // ANALOG:USED): ours reads what it can and never panics.
            if let Ok(c) = c3dfix::open(&path) {
                let _ = force_platforms(&c, &ForceOptions::default()).expect("options");
            }
            continue;
        }
        let c = c3dfix::open(&path).unwrap_or_else(|e| panic!("{key}: {e}"));
        // The reference reads the channels as stored: no unloaded level removed.
        let ours: ForcePlatforms = force_platforms(&c, &raw()).expect("raw options");
        for rp in entry["plates"].as_array().expect("plates") {
            let index = rp["index"].as_u64().expect("index") as usize;
            let mine = ours.platforms.iter().find(|p| p.index == index);
            if rp.get("error").is_some() || rp.get("refused").is_some() {
                assert!(
                    mine.is_none(),
                    "{key} plate {index}: the reference refuses it ({}), we computed it",
                    rp["error"]
                );
                assert!(
                    ours.warnings.iter().any(|w| w.plate == index),
                    "{key} plate {index}: left out without a warning"
                );
                continue;
            }
            let p = mine.unwrap_or_else(|| {
                panic!(
                    "{key} plate {index}: computed by the reference, not by us ({:?})",
                    ours.warnings
                )
            });
            plates += 1;
            samples += check_plate(key, index, p, rp);
        }
    }
    if skipped > 0 {
        eprintln!("{skipped} reference files skipped: corpus absent");
    }
    eprintln!("{plates} plates, {samples} check samples equal to the reference");
    assert!(
        skipped > 0 || plates >= 150,
        "only {plates} plates compared"
    );
}

/// One plate of ours against the reference's reading of it: type, samples, origin, and
/// force, moment, COP and free moment at the reference's check samples; returns how many
/// samples were checked.
fn check_plate(key: &str, index: usize, p: &c3dfix::Platform, rp: &serde_json::Value) -> usize {
    assert_eq!(p.kind as i64, rp["type"].as_i64().expect("type"), "{key}");
    assert_eq!(
        p.force.len(),
        rp["samples"].as_u64().expect("n") as usize,
        "{key}"
    );
    assert_eq!(
        p.origin_corrected,
        rp["origin_corrected"].as_bool().expect("corrected"),
        "{key} plate {index}"
    );
    let origin = v3(&rp["origin"]).expect("origin");
    assert!(
        p.origin
            .iter()
            .zip(origin)
            .all(|(a, b)| (a - b).abs() < 1e-4),
        "{key} plate {index}: origin {:?} against {origin:?}",
        p.origin
    );
    let check: Vec<usize> = rp["check"]
        .as_array()
        .expect("check")
        .iter()
        .map(|v| v.as_u64().expect("index") as usize)
        .collect();
    let kistler = rp.get("cop_poly").is_some();
    let cop_ref = if kistler {
        &rp["cop_poly"]["cop_corrected"]
    } else {
        &rp["cop"]
    };
    let size = {
        let c = p.corners;
        let d = |a: [f64; 3], b: [f64; 3]| {
            ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
        };
        d(c[0], c[2]).max(d(c[1], c[3]))
    };
    for (name, ours_v, theirs, scale) in [
        ("force", &p.force, &rp["force"], magnitude(&p.force)),
        ("moment", &p.moment, &rp["moment"], magnitude(&p.moment)),
        ("cop", &p.cop, cop_ref, magnitude(&p.cop).max(size)),
        (
            "free_moment",
            &p.free_moment,
            &rp["free_moment"],
            magnitude(&p.moment),
        ),
    ] {
        if name == "free_moment" && kistler {
            // The reference's free moment is about the uncorrected COP.
            continue;
        }
        let (d, at) = worst(ours_v, theirs, &check);
        assert!(
            d <= 6e-6 * scale.max(1e-9) + 1e-9,
            "{key} plate {index} {name}: off by {d} at sample {at} (scale {scale})"
        );
    }
    // Where one says a COP and the other none, the push is at the threshold.
    for (j, &s) in check.iter().enumerate() {
        let theirs_none = cop_ref[j][0].is_null();
        let ours_none = p.cop[s][0].is_nan();
        if theirs_none != ours_none {
            assert!(
                (p.push[s] - 10.0).abs() < 1e-3,
                "{key} plate {index} sample {s}: COP defined by one reading only (push {})",
                p.push[s]
            );
        }
    }
    check.len()
}

/// The options that keep the channels as stored (no unloaded level removed).
fn raw() -> ForceOptions {
    ForceOptions {
        zero_baseline: false,
        ..ForceOptions::default()
    }
}

fn sample(rel: &str) -> Option<c3d::C3d> {
    let dir = testkit::c3d_samples()?;
    Some(c3dfix::open(dir.join(rel)).expect(rel))
}

/// The push at or above which the COP must lie on the plate.
const LOADED_N: f64 = 100.0;

/// The share of loaded samples whose COP is on the plate (within 1 mm of its edges).
fn on_plate(p: &c3dfix::Platform) -> (usize, usize) {
    let c = p.corners;
    let sub = |a: [f64; 3], b: [f64; 3]| [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
    let dot = |a: [f64; 3], b: [f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    let unit = |a: [f64; 3]| {
        let n = dot(a, a).sqrt();
        [a[0] / n, a[1] / n, a[2] / n]
    };
    let ex = unit(sub(
        [c[0][0] + c[3][0], c[0][1] + c[3][1], c[0][2] + c[3][2]],
        [c[1][0] + c[2][0], c[1][1] + c[2][1], c[1][2] + c[2][2]],
    ));
    let ey = unit(sub(
        [c[0][0] + c[1][0], c[0][1] + c[1][1], c[0][2] + c[1][2]],
        [c[2][0] + c[3][0], c[2][1] + c[3][1], c[2][2] + c[3][2]],
    ));
    let hx = dot(sub(c[0], p.centre), ex).abs();
    let hy = dot(sub(c[0], p.centre), ey).abs();
    let (mut loaded, mut on) = (0, 0);
    for (n, cop) in p.push.iter().zip(&p.cop) {
        if *n >= LOADED_N {
            loaded += 1;
            let r = sub(*cop, p.centre);
            if dot(r, ex).abs() <= hx + 1.0 && dot(r, ey).abs() <= hy + 1.0 {
                on += 1;
            }
        }
    }
    (on, loaded)
}

/// sample_10 holds one recording stored as plate type 2 (forces and moments) and as type 4
/// (the same raw counts through the plate's 6 × 6 calibration matrix): both must give the
/// same forces and COP, to within the cross-talk the matrix corrects.
#[test]
fn type_2_and_type_4_of_one_recording_agree() {
    let (Some(t2), Some(t4)) = (
        sample("sample_10/TYPE-2a.c3d"),
        sample("sample_10/TYPE-4a.c3d"),
    ) else {
        return;
    };
    let opts = ForceOptions::default();
    let (a, b) = (
        force_platforms(&t2, &opts).expect("type 2"),
        force_platforms(&t4, &opts).expect("type 4"),
    );
    assert_eq!(a.platforms.len(), 2);
    assert_eq!(b.platforms.len(), 2);
    for (p2, p4) in a.platforms.iter().zip(&b.platforms) {
        assert_eq!((p2.kind, p4.kind), (2, 4));
        let mut force = 0.0f64;
        let mut cops = Vec::new();
        for s in 0..p2.force.len() {
            for k in 0..3 {
                force = force.max((p2.force[s][k] - p4.force[s][k]).abs());
            }
            if p2.push[s] >= LOADED_N && p4.push[s] >= LOADED_N {
                let d = (0..3)
                    .map(|k| (p2.cop[s][k] - p4.cop[s][k]).powi(2))
                    .sum::<f64>()
                    .sqrt();
                cops.push(d);
            }
        }
        cops.sort_by(f64::total_cmp);
        let median = cops[cops.len() / 2];
        let max = cops[cops.len() - 1];
        // Peak |Fz| 521 and 583 N: 2 N is 0.4 % of it, the matrix's off-diagonal terms.
        assert!(
            force < 2.0,
            "plate {}: forces differ by {force} N",
            p2.index
        );
        assert!(
            median < 1.5 && max < 2.0,
            "plate {}: COP differs by {median} mm (median), {max} mm (largest)",
            p2.index
        );
        assert!(cops.len() > 400, "{} loaded samples", cops.len());
    }
}

/// On loaded samples the COP lies on the plate: on every corpus plate whose channels hold
/// data, with each file's ZERO baseline subtracted as a lab would. The exceptions are short:
/// loading and unloading transients at plate edges (a heel strike), where the COP of
/// 0.3 % of the samples leaves the plate by up to 68 mm.
#[test]
fn the_centre_of_pressure_lies_on_the_plate() {
    let mut dirs = Vec::new();
    dirs.extend(testkit::c3d_samples());
    dirs.extend(testkit::c3d_extra());
    dirs.extend(testkit::c3d_more());
    let opts = ForceOptions::default();
    let (mut on, mut loaded, mut plates) = (0, 0, 0);
    for dir in dirs {
        for f in testkit::files_with_ext(&dir, "c3d") {
            let Ok(c) = c3dfix::open(&f) else { continue };
            let fp = force_platforms(&c, &opts).expect("options");
            for p in &fp.platforms {
                let silent = fp.warnings.iter().any(|w| {
                    w.plate == p.index && w.message.contains("holds one value throughout")
                });
                let (o, l) = on_plate(p);
                if l == 0 {
                    continue;
                }
                if silent {
                    // btkdata_parameterOverflow: moment channels that recorded nothing, said
                    // in a warning; its COP is not a measurement.
                    continue;
                }
                plates += 1;
                // 94 %: `cadop…Movement_trial` plate 2 carries a staircase (680 of 719
                // samples on the plate, its quiet level of 11 N removed).
                assert!(
                    o as f64 >= 0.94 * l as f64,
                    "{} plate {}: COP on the plate at {o} of {l} loaded samples",
                    testkit::short(&f),
                    p.index
                );
                on += o;
                loaded += l;
            }
        }
    }
    if loaded > 0 {
        let share = on as f64 / loaded as f64;
        eprintln!("{plates} plates: COP on the plate at {on} of {loaded} loaded samples");
        assert!(
            share >= 0.998,
            "COP on the plate at {share} of loaded samples"
        );
        assert!(plates >= 100, "{plates} loaded plates");
    }
}

/// Bit for bit, NaN included.
fn same(a: &[[f64; 3]], b: &[[f64; 3]]) -> bool {
    a.len() == b.len()
        && a.iter()
            .flatten()
            .zip(b.iter().flatten())
            .all(|(x, y)| x.to_bits() == y.to_bits())
}

/// Bad plates, made from a real two-plate file: each gets a warning naming the plate and
/// the parameter, the other plate is still computed (and unchanged), nothing panics.
#[test]
fn a_bad_plate_is_left_out_and_named() {
    let Some(good) = sample("sample_10/TYPE-4a.c3d") else {
        return;
    };
    // Raw values: the NaN samples below fall in FORCE_PLATFORM:ZERO's frames, which would
    // move the baseline to the quiet stretch; what is checked here is the reading.
    let opts = raw();
    let base = force_platforms(&good, &opts).expect("plates");
    assert_eq!(base.platforms.len(), 2);
    let float = |v: Vec<f32>| c3d::Value::Float(v);
    let corners = good
        .param("FORCE_PLATFORM", "CORNERS")
        .expect("corners")
        .as_f32s();
    type Edit = Box<dyn Fn(&mut c3d::C3d)>;
    let cases: Vec<(&str, usize, &str, Edit)> = vec![
        (
            "a CHANNEL beyond the analog channels",
            2,
            "FORCE_PLATFORM:CHANNEL",
            Box::new(|c: &mut c3d::C3d| {
                let ch: Vec<i16> = vec![1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 99];
                c.parameters
                    .set("FORCE_PLATFORM", "CHANNEL", vec![6, 2], c3d::Value::Int(ch))
                    .expect("set");
            }),
        ),
        (
            "CORNERS of the wrong size",
            2,
            "FORCE_PLATFORM:CORNERS",
            Box::new({
                let one = corners[..12].to_vec();
                move |c: &mut c3d::C3d| {
                    c.parameters
                        .set(
                            "FORCE_PLATFORM",
                            "CORNERS",
                            vec![3, 4, 1],
                            float(one.clone()),
                        )
                        .expect("set");
                }
            }),
        ),
        (
            "a plate of zero area",
            2,
            "FORCE_PLATFORM:CORNERS",
            Box::new({
                let mut flat = corners.clone();
                for k in 12..24 {
                    flat[k] = flat[12 + k % 3];
                }
                move |c: &mut c3d::C3d| {
                    c.parameters
                        .set(
                            "FORCE_PLATFORM",
                            "CORNERS",
                            vec![3, 4, 2],
                            float(flat.clone()),
                        )
                        .expect("set");
                }
            }),
        ),
        (
            "a type-4 plate with no CAL_MATRIX",
            2,
            "FORCE_PLATFORM:CAL_MATRIX",
            Box::new(|c: &mut c3d::C3d| {
                c.parameters.remove("FORCE_PLATFORM", "CAL_MATRIX");
                c.parameters
                    .set(
                        "FORCE_PLATFORM",
                        "TYPE",
                        vec![2],
                        c3d::Value::Int(vec![2, 4]),
                    )
                    .expect("set");
            }),
        ),
        (
            "an unsupported type",
            2,
            "FORCE_PLATFORM:TYPE",
            Box::new(|c: &mut c3d::C3d| {
                c.parameters
                    .set(
                        "FORCE_PLATFORM",
                        "TYPE",
                        vec![2],
                        c3d::Value::Int(vec![4, 7]),
                    )
                    .expect("set");
            }),
        ),
    ];
    for (what, plate, parameter, edit) in cases {
        let mut c = good.clone();
        edit(&mut c);
        let fp = force_platforms(&c, &opts).expect("plates");
        assert!(
            fp.warnings
                .iter()
                .any(|w| w.plate == plate && w.parameter == parameter),
            "{what}: no warning on plate {plate} {parameter}: {:?}",
            fp.warnings
        );
        assert!(
            fp.platforms.iter().all(|p| p.index != plate),
            "{what}: plate {plate} computed"
        );
        let other = fp
            .platforms
            .iter()
            .find(|p| p.index == 1)
            .unwrap_or_else(|| panic!("{what}: plate 1 not computed"));
        if what != "a type-4 plate with no CAL_MATRIX" {
            assert!(same(&other.force, &base.platforms[0].force), "{what}");
            assert!(same(&other.cop, &base.platforms[0].cop), "{what}");
        }
    }
}

/// NaN in the analog data: those samples of that plate have no force; a warning says how
/// many; the rest of the plate and the other plate are as before.
#[test]
fn nan_analog_samples_are_counted_and_the_rest_kept() {
    let Some(good) = sample("sample_10/TYPE-4a.c3d") else {
        return;
    };
    let opts = raw();
    let base = force_platforms(&good, &opts).expect("plates");
    let mut c = good.clone();
    let nch = c.analog().channels();
    for s in 100..110 {
        c.analog_mut().raw[s * nch + 8] = f32::NAN; // plate 2's Fz
    }
    let fp = force_platforms(&c, &opts).expect("plates");
    assert!(fp
        .warnings
        .iter()
        .any(|w| w.plate == 2 && w.message.contains("10 samples that are not finite")));
    let p2 = &fp.platforms[1];
    assert!(p2.force[105][0].is_nan() && p2.force[99][0].is_finite());
    assert_eq!(p2.force[2000], base.platforms[1].force[2000]);
    assert!(same(&fp.platforms[0].force, &base.platforms[0].force));
}

/// FORCE_PLATFORM:ZERO subtracted by default where it names an unloaded stretch: the frames
/// it names then average to no load; said when applied, kept raw on request.
#[test]
fn the_zero_baseline_is_the_default_and_said() {
    let Some(c) = sample("sample_10/TYPE-2a.c3d") else {
        return;
    };
    let off = force_platforms(&c, &raw()).expect("plates");
    assert!(off.platforms.iter().all(|p| p.baseline.is_none()));
    let on = force_platforms(&c, &ForceOptions::default()).expect("plates");
    let spf = on.samples_per_frame;
    for p in &on.platforms {
        let b = p.baseline.expect("a baseline");
        assert_eq!(b.source, c3dfix::BaselineSource::Zero);
        assert_eq!((b.first_frame, b.last_frame), (1, 10));
        assert_eq!((b.first_sample, b.last_sample), (0, 10 * spf - 1));
        let n = 10 * spf;
        for k in 0..3 {
            let mean = p.force[..n].iter().map(|f| f[k]).sum::<f64>() / n as f64;
            assert!(mean.abs() < 1e-9, "plate {} mean {mean}", p.index);
        }
    }
    // The baseline moved the force by the mean it removed, nothing else.
    let d = on.platforms[0].force[2000][2] - off.platforms[0].force[2000][2];
    let m = off.platforms[0].force[..10 * spf]
        .iter()
        .map(|f| f[2])
        .sum::<f64>()
        / (10 * spf) as f64;
    assert!((d + m).abs() < 1e-9, "{d} {m}");
}

/// A low-pass filter of the channels, as for markers: it smooths, it keeps the signal, and
/// its spec is checked against the analog rate.
#[test]
fn a_low_pass_filter_smooths_the_channels() {
    let Some(c) = sample("sample_10/TYPE-2a.c3d") else {
        return;
    };
    let raw = force_platforms(&c, &ForceOptions::default()).expect("plates");
    let lp = force_platforms(
        &c,
        &ForceOptions {
            lowpass: Some("butterworth:4:20".parse().unwrap()),
            ..ForceOptions::default()
        },
    )
    .expect("plates");
    let roughness = |p: &c3dfix::Platform| {
        p.force
            .windows(3)
            .map(|w| (w[0][2] - 2.0 * w[1][2] + w[2][2]).abs())
            .sum::<f64>()
    };
    for (a, b) in raw.platforms.iter().zip(&lp.platforms) {
        assert_eq!(b.filtered.as_deref(), Some("butterworth:4:20"));
        assert!(roughness(b) < 0.2 * roughness(a));
        assert!((a.peak_force - b.peak_force).abs() < 0.05 * a.peak_force);
    }
    let bad = force_platforms(
        &c,
        &ForceOptions {
            lowpass: Some("butterworth:4:600".parse().unwrap()),
            ..ForceOptions::default()
        },
    );
    assert!(
        bad.is_err(),
        "a cutoff above half the analog rate (480 Hz) is refused"
    );
}

/// Damaged FORCE_PLATFORM and ANALOG parameters (bytes of the parameter section of real
/// plate files overwritten at random, 400 times each): the plates compute or are left out
/// with warnings, never a panic.
#[test]
fn damaged_plate_parameters_never_panic() {
    let mut files = Vec::new();
    if let Some(d) = testkit::c3d_samples() {
        files.push(d.join("sample_10/TYPE-3.c3d"));
        files.push(d.join("sample_10/TYPE-4a.c3d"));
    }
    if let Some(d) = testkit::c3d_more() {
        files.push(d.join("qualisys__cgm2-web-report-uploader__FunctionalKnee_GaitFB2.c3d"));
        files.push(d.join("pyomeca__ezc3d-testFiles__FP_Type1.c3d"));
    }
    // SplitMix64, seeded: the same damage every run.
    let mut state = 0x5EED_F00D_u64;
    let mut next = move || {
        state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = state;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    };
    let (mut read, mut computed) = (0, 0);
    for f in files {
        let bytes = std::fs::read(&f).expect("corpus file");
        let start = (bytes[0] as usize).saturating_sub(1) * 512;
        let end = (start + bytes[start + 2] as usize * 512).min(bytes.len());
        for _ in 0..400 {
            let mut b = bytes.clone();
            for _ in 0..1 + next() % 4 {
                let at = start + 4 + (next() as usize) % (end - start - 4);
                b[at] = next() as u8;
            }
            let Ok(c) = c3d::read(b) else { continue };
            read += 1;
            let fp = force_platforms(&c, &ForceOptions::default()).expect("options");
            computed += fp.platforms.len();
            serde_json::to_string(&fp).expect("serialises");
        }
    }
    eprintln!("{read} damaged files read, {computed} plates computed");
}
