//! How well a position fits a template marker, given where other markers are: the
//! distances it keeps to them, each against the template's distance in units of its
//! spread (squared, capped so one moving pair cannot outvote the rest), and the handedness
//! of its tetrahedra.

use super::model::{handedness, Model};
use super::options::LabelOptions;

/// `(sum, terms)`: the capped squared departures of marker `m` at `p` from its pairs whose
/// other marker `at` places, and a penalty of one cap for each tetrahedron of the wrong
/// hand. `at(n)` is the position of marker `n`, if placed. Once the sum passes `limit`
/// the rest is not added (a caller that only wants costs below it asks no more).
pub(crate) fn marker_cost<'a>(
    model: &Model,
    m: usize,
    p: &[f64; 3],
    at: impl Fn(usize) -> Option<&'a [f64; 3]>,
    opts: &LabelOptions,
    limit: f64,
) -> (f64, usize) {
    let (mut sum, mut terms) = (0.0, 0usize);
    for n in &model.nb[m] {
        if let Some(q) = at(n.other) {
            let e = (super::options::dist(p, q) - n.d0) / n.sigma;
            sum += (e * e).min(opts.cap);
            terms += 1;
            if sum > limit {
                return (sum, terms);
            }
        }
    }
    for c in &model.chiral[m] {
        if let (Some(a), Some(b), Some(cc)) = (at(c.a), at(c.b), at(c.c)) {
            let h = handedness(p, a, b, cc);
            if h * c.sign < -0.05 {
                sum += opts.cap;
            }
        }
    }
    (sum, terms)
}
