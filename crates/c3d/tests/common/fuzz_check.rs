//! The properties the fuzzer checks, shared with the test that replays every crash it found.
//!
//! For any bytes: reading never panics; a file that reads rewrites to the same bytes (also
//! after its data was opened for editing, and when borrowed unchanged); scanning the samples
//! chunk by chunk gives what decoding them gives; patching samples into the bytes writes
//! what editing the decoded points writes; a conversion that succeeds reads back with the same
//! shape.

use c3d::{C3d, NumberFormat, Processor};

pub fn check(data: &[u8]) {
    let Ok(c) = c3d::read(data.to_vec()) else {
        return;
    };
    let out = c.to_bytes().expect("an unchanged file must write");
    assert!(out == data, "rewrite differs");
    let borrowed = c.encoded().expect("an unchanged file must encode");
    assert!(&borrowed[..] == data, "borrowed bytes differ");
    lazy_matches_decoded(&c);
    let mut touched = c.clone();
    touched.points_mut();
    touched.analog_mut();
    let out = touched
        .to_bytes()
        .expect("a file with untouched values must write");
    assert!(out == data, "rewrite after points_mut differs");
    let _ = c.diff_self_check();
    for p in [Processor::Intel, Processor::Dec, Processor::Sgi] {
        if let Ok(bytes) = c.convert(p, c.format(), None) {
            let back = c3d::read(bytes).expect("a converted file must read back");
            assert_eq!(back.points().frames(), c.points().frames());
            assert_eq!(back.points().count(), c.points().count());
            assert_eq!(back.analog().channels(), c.analog().channels());
        }
    }
}

/// The chunk scan of undecoded points equals the decoded points, and a patch of every third
/// sample (invalidated, or kept and marked processed) writes what the same edit of the decoded
/// points writes.
fn lazy_matches_decoded(c: &C3d) {
    let lazy = c.clone();
    let scanned: Vec<_> = lazy
        .map_point_chunks(vec![(); lazy.point_chunks()], |(), v| {
            let mut out = Vec::new();
            for f in 0..v.frames {
                for i in 0..v.count {
                    let (p, r, m) = v.sample(f, i);
                    out.push((p.map(f32::to_bits), r.to_bits(), m));
                }
            }
            out
        })
        .concat();
    let p = c.points();
    assert_eq!(scanned.len(), p.xyz.len(), "chunk scan covers every sample");
    let mut edits = Vec::new();
    for (k, s) in scanned.iter().enumerate() {
        let d = (
            p.xyz[k].map(f32::to_bits),
            p.residual[k].to_bits(),
            p.camera_mask[k],
        );
        assert!(*s == d, "sample {k}: chunk scan {s:?}, decoded {d:?}");
        let (f, i) = (k / p.count().max(1), k % p.count().max(1));
        match k % 3 {
            0 => edits.push((f, i, [0.0; 3], -1.0, 0)),
            1 if p.is_valid(f, i) => edits.push((f, i, p.xyz[k], 0.0, 0)),
            _ => {}
        }
    }
    // Converting undecoded points (chunk by chunk) writes what converting decoded ones writes.
    for p in [Processor::Intel, Processor::Dec, Processor::Sgi] {
        for fmt in [NumberFormat::Float, NumberFormat::Integer] {
            let (a, b) = (lazy.clone().convert(p, fmt, None), c.convert(p, fmt, None));
            match (a, b) {
                (Ok(a), Ok(b)) => assert!(a == b, "{p:?} {fmt:?}: chunked conversion differs"),
                (a, b) => assert_eq!(a.is_ok(), b.is_ok(), "{:?} / {:?}", a.err(), b.err()),
            }
        }
    }
    // `lazy` is still undecoded: its samples are patched into its bytes.
    let mut patched = lazy;
    let mut model = c.clone();
    if patched.patch_points(edits.iter().copied()).is_err() {
        return;
    }
    {
        let m = model.points_mut();
        for &(f, i, xyz, r, mask) in &edits {
            let k = m.index(f, i);
            (m.xyz[k], m.residual[k], m.camera_mask[k]) = (xyz, r, mask);
        }
    }
    match (patched.to_bytes(), model.to_bytes()) {
        (Ok(a), Ok(b)) => assert!(a == b, "patched bytes differ from the edited model's"),
        (a, b) => assert_eq!(a.is_ok(), b.is_ok(), "{:?} / {:?}", a.err(), b.err()),
    }
}

/// Diffing a file against itself finds nothing.
trait SelfDiff {
    fn diff_self_check(&self) -> bool;
}

impl SelfDiff for c3d::C3d {
    fn diff_self_check(&self) -> bool {
        let d = c3d::diff::diff(self, self, 0.0);
        assert!(
            d.parameters.is_empty() && d.points.markers.is_empty(),
            "a file differs from itself"
        );
        true
    }
}
