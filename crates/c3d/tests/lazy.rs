//! A file read keeps one copy of its data, its bytes: the arrays are decoded on first use,
//! scans decode chunk by chunk, patches go into the bytes, and an unchanged file is written
//! from the bytes read. Each of these must give exactly what the decoded model gives, on
//! every corpus file.

use c3d::C3d;
use std::borrow::Cow;

fn bits(p: ([f32; 3], f32, u8)) -> ([u32; 3], u32, u8) {
    (p.0.map(f32::to_bits), p.1.to_bits(), p.2)
}

/// Every sample as [`C3d::map_point_chunks`] gives it, in frame-major order.
fn scanned(c: &C3d) -> Vec<([u32; 3], u32, u8)> {
    c.map_point_chunks(vec![(); c.point_chunks()], |(), v| {
        let mut out = Vec::with_capacity(v.frames * v.count);
        for f in 0..v.frames {
            for i in 0..v.count {
                out.push(bits(v.sample(f, i)));
            }
        }
        out
    })
    .concat()
}

fn decoded(c: &C3d) -> Vec<([u32; 3], u32, u8)> {
    let p = c.points();
    (0..p.xyz.len())
        .map(|k| bits((p.xyz[k], p.residual[k], p.camera_mask[k])))
        .collect()
}

/// The edits both paths make: every 7th sample invalidated, every 5th valid one kept in
/// place but marked processed (residual 0, mask 0) — values any file can hold.
fn edits(c: &C3d) -> Vec<(usize, usize, [f32; 3], f32, u8)> {
    let p = c.points();
    let mut v = Vec::new();
    for f in 0..p.frames() {
        for i in 0..p.count() {
            let k = p.index(f, i);
            if k % 7 == 3 {
                v.push((f, i, [0.0; 3], -1.0, 0));
            } else if k % 5 == 1 && p.is_valid(f, i) {
                v.push((f, i, p.xyz[k], 0.0, 0));
            }
        }
    }
    v
}

#[test]
fn lazy_scans_patches_and_borrowed_bytes_match_the_decoded_model() {
    let files = testkit::all_c3d_files();
    if files.is_empty() {
        eprintln!("skipped: no corpus (set C3D_SAMPLES etc.)");
        testkit::skipped("no corpus");
        return;
    }
    let mut checked = 0;
    for path in files {
        let Ok(read) = c3d::read_file(&path) else {
            continue;
        };
        let mapped = c3d::read_file_mapped(&path).expect("reads mapped as it reads");
        let name = path.display();
        assert_eq!(
            mapped.warnings(),
            read.warnings(),
            "{name}: warnings, mapped or read"
        );
        // An unchanged file is written from the bytes read, without a copy.
        let enc = mapped.encoded().expect("encode unchanged");
        assert!(
            matches!(enc, Cow::Borrowed(_)),
            "{name}: unchanged is borrowed"
        );
        assert!(
            Some(&enc[..]) == read.source_bytes(),
            "{name}: unchanged bytes"
        );
        // Scanning undecoded and decoded points gives the same samples.
        let lazy = scanned(&mapped);
        assert!(
            lazy == decoded(&read),
            "{name}: chunk scan differs from points()"
        );
        assert!(
            lazy == scanned(&read),
            "{name}: chunk scan of decoded points"
        );
        assert_eq!(mapped.frames(), read.points().frames(), "{name}: frames");
        assert_eq!(
            mapped.point_count(),
            read.points().count(),
            "{name}: points"
        );
        assert_eq!(mapped.analog_channels(), read.analog().channels(), "{name}");
        // Patching the bytes gives the bytes editing the decoded model gives.
        let e = edits(&read);
        let mut patched = c3d::read_file_mapped(&path).expect("read again");
        let mut model = read.clone();
        let n = patched.patch_points(e.iter().copied()).expect("patch");
        assert_eq!(n, e.len());
        {
            let p = model.points_mut();
            for &(f, i, xyz, r, m) in &e {
                let k = p.index(f, i);
                (p.xyz[k], p.residual[k], p.camera_mask[k]) = (xyz, r, m);
            }
        }
        let (a, b) = (patched.to_bytes(), model.to_bytes());
        match (a, b) {
            (Ok(a), Ok(b)) => assert!(a == b, "{name}: patched bytes differ from the model's"),
            (a, b) => assert_eq!(a.is_ok(), b.is_ok(), "{name}: {:?} {:?}", a.err(), b.err()),
        }
        // The original file is untouched by a patch of its mapping.
        assert!(
            std::fs::read(&path).ok().as_deref() == read.source_bytes(),
            "{name}: file changed"
        );
        checked += 1;
    }
    assert!(checked >= 80, "only {checked} corpus files read");
}
