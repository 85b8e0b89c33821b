//! The same trial in several processor and number formats must give the same values; and
//! conversions and edits must keep them.

use c3d::{NumberFormat, Processor};
use std::path::PathBuf;

fn sample(rel: &str) -> Option<PathBuf> {
    Some(testkit::c3d_samples()?.join(rel))
}

/// Max |a − b| over valid samples (both valid), and whether validity agrees everywhere.
fn compare_points(a: &c3d::C3d, b: &c3d::C3d) -> (f32, usize) {
    let (pa, pb) = (a.points(), b.points());
    assert_eq!((pa.frames(), pa.count()), (pb.frames(), pb.count()));
    let mut max = 0f32;
    let mut validity_diff = 0;
    for k in 0..pa.xyz.len() {
        let (va, vb) = (pa.residual[k] >= 0.0, pb.residual[k] >= 0.0);
        if va != vb {
            validity_diff += 1;
        }
        if va && vb {
            for i in 0..3 {
                max = max.max((pa.xyz[k][i] - pb.xyz[k][i]).abs());
            }
        }
    }
    (max, validity_diff)
}

fn max_analog_diff(a: &c3d::C3d, b: &c3d::C3d) -> f32 {
    let (x, y) = (a.analog_physical(), b.analog_physical());
    assert_eq!(x.len(), y.len());
    x.iter()
        .zip(&y)
        .map(|(p, q)| (p - q).abs())
        .fold(0.0, f32::max)
}

#[test]
fn eb015_in_six_formats_agree() {
    let Some(dir) = sample("sample_01") else {
        return;
    };
    let names = [
        "Eb015pi", "Eb015pr", "Eb015vi", "Eb015vr", "Eb015si", "Eb015sr",
    ];
    let files: Vec<_> = names
        .iter()
        .map(|n| c3d::read_file(dir.join(format!("{n}.c3d"))).unwrap())
        .collect();
    let expect = [
        (Processor::Intel, NumberFormat::Integer),
        (Processor::Intel, NumberFormat::Float),
        (Processor::Dec, NumberFormat::Integer),
        (Processor::Dec, NumberFormat::Float),
        (Processor::Sgi, NumberFormat::Integer),
        (Processor::Sgi, NumberFormat::Float),
    ];
    for (f, (p, fmt)) in files.iter().zip(expect) {
        assert_eq!((f.processor(), f.format()), (p, fmt));
        assert_eq!(f.points().frames(), 450);
        assert_eq!(f.points().count(), 26);
        assert_eq!(f.analog().channels(), 16);
        assert_eq!(f.point_rate(), 50.0);
        assert_eq!(f.analog_rate(), 200.0);
        assert_eq!(f.header_events().len(), 3);
    }
    // Integer data is quantized by POINT:SCALE (0.0833); float copies agree to half a step.
    let half_step = 0.0833 / 2.0 + 1e-3;
    for f in &files[1..] {
        let (d, v) = compare_points(&files[0], f);
        assert_eq!(v, 0, "validity differs");
        assert!(d <= half_step, "max coordinate difference {d}");
        assert!(max_analog_diff(&files[0], f) < 1e-3);
    }
    // Same number format: identical values regardless of processor.
    for (i, j) in [(0, 2), (0, 4), (1, 3), (1, 5)] {
        assert_eq!(
            compare_points(&files[i], &files[j]),
            (0.0, 0),
            "{} vs {}",
            names[i],
            names[j]
        );
    }
    // A known value: the first label and a coordinate seen in every copy.
    assert_eq!(files[0].point_labels()[0], "RFT1");
}

#[test]
fn sample02_six_formats_agree() {
    let Some(dir) = sample("sample_02") else {
        return;
    };
    let names = [
        "pc_int", "pc_real", "dec_int", "dec_real", "sgi_int", "sgi_real",
    ];
    let files: Vec<_> = names
        .iter()
        .map(|n| c3d::read_file(dir.join(format!("{n}.c3d"))).unwrap())
        .collect();
    for f in &files {
        assert_eq!((f.points().frames(), f.points().count()), (89, 36));
    }
    // The corpus README: residuals and camera masks are not consistent between the copies, so
    // compare coordinates where both copies have the point.
    // The integer copies were made by truncation, not rounding: up to one full step apart.
    let step = 0.28118187 + 1e-3;
    for f in &files[1..] {
        let (d, _) = compare_points(&files[0], f);
        assert!(d <= step, "max coordinate difference {d}");
        assert!(max_analog_diff(&files[0], f) < 1e-3);
    }
}

#[test]
fn sample08_sections_at_other_offsets_give_identical_data() {
    let Some(dir) = sample("sample_08") else {
        return;
    };
    let base = c3d::read_file(dir.join("EB015PI.c3d")).unwrap();
    for n in ["TESTAPI", "TESTBPI", "TESTCPI", "TESTDPI"] {
        let f = c3d::read_file(dir.join(format!("{n}.c3d"))).unwrap();
        assert_eq!(f.points().xyz, base.points().xyz, "{n}");
        assert_eq!(f.points().residual, base.points().residual, "{n}");
        assert_eq!(f.analog().raw, base.analog().raw, "{n}");
        assert_eq!(f.point_labels(), base.point_labels(), "{n}");
    }
}

#[test]
fn dec_to_intel_to_dec_preserves_values() {
    let Some(dir) = sample("sample_01") else {
        return;
    };
    for name in ["Eb015vi.c3d", "Eb015vr.c3d"] {
        let dec = c3d::read_file(dir.join(name)).unwrap();
        let fmt = dec.format();
        let intel = c3d::read(dec.convert(Processor::Intel, fmt, None).unwrap()).unwrap();
        assert_eq!(intel.processor(), Processor::Intel);
        let back = c3d::read(intel.convert(Processor::Dec, fmt, None).unwrap()).unwrap();
        assert_eq!(back.processor(), Processor::Dec);
        for f in [&intel, &back] {
            assert_eq!(f.points().xyz, dec.points().xyz, "{name}");
            assert_eq!(f.points().residual, dec.points().residual, "{name}");
            assert_eq!(f.points().camera_mask, dec.points().camera_mask, "{name}");
            assert_eq!(f.analog().raw, dec.analog().raw, "{name}");
            assert_eq!(f.point_labels(), dec.point_labels());
            assert_eq!(f.header_events(), dec.header_events());
            assert!(f.warnings().is_empty(), "{:?}", f.warnings());
        }
        // Every parameter survives with the same values.
        for g in dec.parameters.groups() {
            for p in dec.parameters.parameters_of(g.id) {
                if p.name == "DATA_START" {
                    continue;
                }
                let q = back.parameters.get(&g.name, &p.name).unwrap();
                assert_eq!(q.value, p.value, "{}:{}", g.name, p.name);
            }
        }
    }
}

#[test]
fn int_to_float_to_int_preserves_values() {
    let Some(dir) = sample("sample_01") else {
        return;
    };
    let int = c3d::read_file(dir.join("Eb015pi.c3d")).unwrap();
    let float = c3d::read(
        int.convert(Processor::Intel, NumberFormat::Float, None)
            .unwrap(),
    )
    .unwrap();
    assert_eq!(float.format(), NumberFormat::Float);
    assert_eq!(float.points().xyz, int.points().xyz);
    assert_eq!(float.points().residual, int.points().residual);
    let back = c3d::read(
        float
            .convert(Processor::Intel, NumberFormat::Integer, None)
            .unwrap(),
    )
    .unwrap();
    assert_eq!(back.format(), NumberFormat::Integer);
    assert_eq!(back.points().xyz, int.points().xyz);
    assert_eq!(back.points().residual, int.points().residual);
    assert_eq!(back.points().camera_mask, int.points().camera_mask);
    assert_eq!(back.analog().raw, int.analog().raw);
    assert_eq!(
        back.parameters.get_f32("POINT", "SCALE"),
        int.parameters.get_f32("POINT", "SCALE")
    );
}

#[test]
fn float_analog_to_int_keeps_physical_values() {
    let Some(dir) = sample("sample_25") else {
        return;
    };
    let float = c3d::read_file(dir.join("analogfpscale04.c3d")).unwrap();
    let int = c3d::read(
        float
            .convert(Processor::Intel, NumberFormat::Integer, None)
            .unwrap(),
    )
    .unwrap();
    let (a, b) = (float.analog_physical(), int.analog_physical());
    let cal = float.analog_calibration();
    let ch = float.analog().channels();
    for c in 0..ch {
        let col = |v: &[f32]| v.iter().skip(c).step_by(ch).copied().collect::<Vec<_>>();
        let (x, y) = (col(&a), col(&b));
        let range = x.iter().fold(0f32, |m, v| m.max(v.abs()));
        let err = x
            .iter()
            .zip(&y)
            .map(|(p, q)| (p - q).abs())
            .fold(0.0, f32::max);
        // 16-bit quantization of the channel's range (or exact when it already held integers).
        assert!(
            err <= range / 32000.0 * 0.51 + 1e-6,
            "channel {c}: error {err}, range {range}, {cal:?}"
        );
    }
    let (d, v) = compare_points(&float, &int);
    assert_eq!(v, 0);
    assert!(d <= 0.05, "{d}");
}

#[test]
fn editing_one_sample_changes_only_its_words() {
    let Some(dir) = sample("sample_01") else {
        return;
    };
    for name in ["Eb015pi.c3d", "Eb015vr.c3d", "Eb015si.c3d"] {
        let path = dir.join(name);
        let orig = std::fs::read(&path).unwrap();
        let mut c = c3d::read(orig.clone()).unwrap();
        let k = c.points().index(10, 3);
        {
            let p = c.points_mut();
            p.xyz[k][0] += 10.0;
            p.residual[k] = 0.0;
            p.camera_mask[k] = 0;
        }
        let out = c.to_bytes().unwrap();
        assert_eq!(out.len(), orig.len());
        let diffs: Vec<usize> = (0..out.len()).filter(|&i| out[i] != orig[i]).collect();
        let word = if c.format() == NumberFormat::Float {
            4
        } else {
            2
        };
        let frame_bytes = c.layout().frame_bytes();
        let start = (c.header.data_start as usize - 1) * 512 + 10 * frame_bytes + 3 * 4 * word;
        assert!(!diffs.is_empty());
        assert!(
            diffs
                .iter()
                .all(|&i| (start..start + 4 * word).contains(&i)),
            "{name}: bytes {diffs:?} changed outside the sample at {start}"
        );
        let back = c3d::read(out).unwrap();
        assert!((back.points().xyz[k][0] - c.points().xyz[k][0]).abs() <= 0.0834 / 2.0);
        assert_eq!(back.points().residual[k], 0.0);
    }
}

#[test]
fn growing_parameters_moves_the_data_section() {
    let Some(dir) = sample("sample_01") else {
        return;
    };
    let orig = c3d::read_file(dir.join("Eb015pi.c3d")).unwrap();
    let mut c = orig.clone();
    let long: Vec<String> = (0..200)
        .map(|i| format!("a long vendor note number {i:03}"))
        .collect();
    c.parameters.set_strings("VENDOR", "NOTES", &long).unwrap();
    let bytes = c.to_bytes().unwrap();
    let back = c3d::read(bytes).unwrap();
    assert!(back.header.data_start > orig.header.data_start);
    assert_eq!(
        back.parameters.get_i32("POINT", "DATA_START"),
        Some(back.header.data_start as i32)
    );
    assert_eq!(back.points().xyz, orig.points().xyz);
    assert_eq!(back.analog().raw, orig.analog().raw);
    assert_eq!(
        back.parameters.get_strings("VENDOR", "NOTES").unwrap(),
        long
    );
    assert!(back.warnings().is_empty(), "{:?}", back.warnings());
}

#[test]
fn integer_overflow_is_a_clear_error() {
    let Some(dir) = sample("sample_01") else {
        return;
    };
    let mut c = c3d::read_file(dir.join("Eb015pi.c3d")).unwrap();
    let k = c.points().index(0, 0);
    c.points_mut().xyz[k][1] = 1.0e7;
    c.points_mut().residual[k] = 1.0;
    let e = c.to_bytes().unwrap_err().to_string();
    assert!(
        e.contains("does not fit in a 16-bit integer") && e.contains("frame 0, point 0"),
        "{e}"
    );
}

#[test]
fn every_corpus_file_converts_to_every_format() {
    let files = testkit::all_c3d_files();
    let mut converted = 0;
    for f in &files {
        let Ok(c) = c3d::read_file(f) else { continue };
        for p in [Processor::Intel, Processor::Dec, Processor::Sgi] {
            for fmt in [NumberFormat::Integer, NumberFormat::Float] {
                let name = format!("{} → {} {}", testkit::short(f), p.name(), fmt.name());
                let bytes = match c.convert(p, fmt, None) {
                    Ok(b) => b,
                    Err(e) => panic!("{name}: {e}"),
                };
                let back = c3d::read(bytes).unwrap_or_else(|e| panic!("{name}: {e}"));
                assert_eq!((back.processor(), back.format()), (p, fmt), "{name}");
                assert_eq!(back.points().frames(), c.points().frames(), "{name}");
                assert_eq!(back.points().count(), c.points().count(), "{name}");
                assert_eq!(back.analog().channels(), c.analog().channels(), "{name}");
                assert_eq!(back.point_labels(), c.point_labels(), "{name}");
                // Integer output is quantized by the scale it was given.
                let step = if fmt == NumberFormat::Integer {
                    back.layout().point_scale * 0.5 * 1.001
                } else {
                    0.0
                };
                let (pa, pb) = (c.points(), back.points());
                for k in 0..pa.xyz.len() {
                    let valid = pa.residual[k] >= 0.0;
                    assert_eq!(valid, pb.residual[k] >= 0.0, "{name}: validity at {k}");
                    if !valid {
                        continue;
                    }
                    for a in 0..3 {
                        let (x, y) = (pa.xyz[k][a], pb.xyz[k][a]);
                        // DEC floats cannot hold values beyond ±1.7e38 or below 2.9e-39.
                        let tol = step + 1e-6 * x.abs().max(1.0);
                        assert!(
                            (x - y).abs() <= tol,
                            "{name}: sample {k} axis {a}: {x} vs {y}"
                        );
                    }
                }
                converted += 1;
            }
        }
    }
    if !files.is_empty() {
        assert!(converted >= 88 * 6, "{converted}");
    }
}
