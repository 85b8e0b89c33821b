//! Whether a centre of pressure lies on its plate: the plate's box from its corners, with
//! an edge for the noise of a COP near it. Read where a plate's ORIGIN is checked against
//! its loads and where a plate that gave no event is explained.

/// How far (mm) outside its corners a centre of pressure may lie and still be on the plate:
/// the noise of a COP near the plate's edge.
pub const EDGE_MM: f64 = 50.0;

/// Whether `cop` (point units) lies more than [`EDGE_MM`] outside the box of the plate's
/// `corners` in the plane they span (the axis along which they spread least is the
/// plate's normal).
pub(crate) fn off_plate(corners: &[[f64; 3]; 4], cop: &[f64; 3], mm: f64) -> bool {
    if !cop.iter().all(|v| v.is_finite()) {
        return false;
    }
    let span = |k: usize| {
        let lo = corners.iter().map(|c| c[k]).fold(f64::INFINITY, f64::min);
        let hi = corners
            .iter()
            .map(|c| c[k])
            .fold(f64::NEG_INFINITY, f64::max);
        (lo, hi)
    };
    let normal = (0..3)
        .min_by(|&a, &b| {
            let (la, ha) = span(a);
            let (lb, hb) = span(b);
            (ha - la).total_cmp(&(hb - lb))
        })
        .unwrap_or(2);
    let edge = EDGE_MM / mm;
    (0..3).filter(|&k| k != normal).any(|k| {
        let (lo, hi) = span(k);
        cop[k] < lo - edge || cop[k] > hi + edge
    })
}
