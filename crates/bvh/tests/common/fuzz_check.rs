//! What the BVH fuzz target checks, shared with the test that replays what it found: parsing
//! any text never panics, and what parses writes back to text that parses to the same shape
//! and the same values (within print precision).

pub fn check(data: &[u8]) {
    let text = String::from_utf8_lossy(data);
    let Ok(b) = bvh::parse(&text) else { return };
    let again = bvh::parse(&bvh::write(&b)).expect("written BVH must parse");
    assert_eq!(again.skeleton.joints.len(), b.skeleton.joints.len());
    assert_eq!(again.motion.frames(), b.motion.frames());
    assert_eq!(again.motion.values.len(), b.motion.values.len());
    for (x, y) in b.motion.values.iter().zip(&again.motion.values) {
        assert!(
            x == y || (x - y).abs() <= 1e-9 * x.abs().max(1.0),
            "{x} vs {y}"
        );
    }
}
