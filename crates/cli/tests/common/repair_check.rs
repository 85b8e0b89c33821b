//! What the `repair` fuzz target checks, shared with the test that replays what it found.
//!
//! For any bytes that read as a C3D file: the force plates compute without a panic (a bad
//! plate is a warning) and serialise. For those with points: the library's repair (what `c3dfix repair` runs, in memory, with
//! options picked from the input's last byte) either fails with an error or gives bytes that
//! read back with the same shape, that `info` can describe, and in which every sample the
//! repair left alone (residual above 0 afterwards) and every analog value is as it was.

use c3dfix::info::describe;
use c3dfix::{FillMethod, RepairOptions, SpikeMode};
use std::path::Path;

/// The repair options for an input: its last byte picks the fill method, spikes and filter.
fn options(data: &[u8]) -> RepairOptions {
    let k = data.last().copied().unwrap_or(0);
    let fill = [
        FillMethod::Linear,
        FillMethod::Spline,
        FillMethod::Auto,
        FillMethod::Rigid,
        FillMethod::Pca,
        FillMethod::Lagrange5,
        FillMethod::Pattern,
        FillMethod::None,
    ];
    let spec = |s: &str| s.parse().expect("a valid spec");
    RepairOptions {
        fill: fill[(k & 7) as usize],
        max_gap: 200,
        max_expected_error_mm: (k & 2 == 0).then_some(20.0),
        spikes: (k & 8 != 0).then(|| "hampel:5:3".parse().expect("a valid spec")),
        spike_mode: if k & 16 != 0 {
            SpikeMode::Median
        } else {
            SpikeMode::Gap
        },
        spike_min_mm: 5.0,
        spike_classic: k & 32 != 0,
        lowpass: match k >> 6 {
            1 => Some(spec("butterworth:4:6")),
            2 => Some(spec("cheby2:4:10:40")),
            _ => None,
        },
        markers: None,
        zero_invalid: k & 1 != 0,
        // Found and reported on every input (never a panic); `fix` would exchange samples
        // the check below expects unchanged.
        swaps: c3dfix::SwapsMode::Report,
        // Judged and reported on every input, likewise; `on` would move recorded samples.
        reclaim: c3dfix::ReclaimMode::Report,
        unlabelled: None,
    }
}

pub fn check(data: &[u8]) {
    let Ok(mut c) = c3d::read(data.to_vec()) else {
        return;
    };
    let input = Path::new("fuzz-input.c3d");
    serde_json::to_string(&describe(&c, input)).expect("info on the input serialises");
    let plates = c3dfix::force_platforms(&c, &c3dfix::ForceOptions::default())
        .expect("the default force options are valid");
    serde_json::to_string(&plates).expect("the plates serialise");
    if c.points().count() == 0 {
        return;
    }
    let original = c.clone();
    if c3dfix::repair(&mut c, &options(data), input).is_err() {
        return;
    }
    let Ok(bytes) = c.encoded() else {
        return;
    };
    let out = match c3d::read(bytes.into_owned()) {
        Ok(out) => out,
        Err(e) => panic!("the repaired file does not read: {e}"),
    };
    serde_json::to_string(&describe(&out, Path::new("fuzz-output.c3d")))
        .expect("info on the output serialises");
    let (a, b) = (original.points(), out.points());
    assert_eq!(b.frames(), a.frames(), "frames");
    assert_eq!(b.count(), a.count(), "points");
    assert_eq!(out.point_labels(), original.point_labels(), "labels");
    for k in 0..a.xyz.len() {
        if b.residual[k] > 0.0 {
            let same = a.xyz[k].map(f32::to_bits) == b.xyz[k].map(f32::to_bits)
                && a.residual[k].to_bits() == b.residual[k].to_bits();
            assert!(
                same,
                "sample {k} not repaired but changed: {:?} -> {:?}",
                (a.xyz[k], a.residual[k]),
                (b.xyz[k], b.residual[k])
            );
        }
    }
    let (x, y) = (original.analog(), out.analog());
    assert_eq!(y.channels(), x.channels(), "analog channels");
    assert_eq!(y.samples(), x.samples(), "analog samples");
    let bits = |v: &[f32]| v.iter().map(|f| f.to_bits()).collect::<Vec<_>>();
    assert!(bits(&x.raw) == bits(&y.raw), "analog values changed");
}
