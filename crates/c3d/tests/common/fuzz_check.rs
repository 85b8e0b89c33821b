//! The properties the fuzzer checks, shared with the test that replays every crash it found.
//!
//! For any bytes: reading never panics; a file that reads rewrites to the same bytes (also
//! after its data was opened for editing); a conversion that succeeds reads back with the same
//! shape.

use c3d::Processor;

pub fn check(data: &[u8]) {
    let Ok(c) = c3d::read(data.to_vec()) else {
        return;
    };
    let out = c.to_bytes().expect("an unchanged file must write");
    assert!(out == data, "rewrite differs");
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
