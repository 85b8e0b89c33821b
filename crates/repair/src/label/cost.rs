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

/// The three other corners of a tetrahedron and the hand they keep.
type Hand = ([f64; 3], [f64; 3], [f64; 3], f64);

/// A marker's placed pairs and tetrahedra, gathered once so that many positions can be
/// costed against them: the same sum as [`marker_cost`], term for term and in the same
/// order (so the same bits), without asking where each neighbour is again.
#[derive(Default)]
pub(crate) struct Around {
    /// Position of the other marker, the pair's distance and tolerance.
    pairs: Vec<([f64; 3], f64, f64)>,
    hands: Vec<Hand>,
}

impl Around {
    /// Gather marker `m`'s pairs and tetrahedra whose markers `at` places.
    pub fn gather<'a>(
        &mut self,
        model: &Model,
        m: usize,
        at: impl Fn(usize) -> Option<&'a [f64; 3]>,
    ) {
        self.pairs.clear();
        self.hands.clear();
        for n in &model.nb[m] {
            if let Some(q) = at(n.other) {
                self.pairs.push((*q, n.d0, n.sigma));
            }
        }
        for c in &model.chiral[m] {
            if let (Some(a), Some(b), Some(cc)) = (at(c.a), at(c.b), at(c.c)) {
                self.hands.push((*a, *b, *cc, c.sign));
            }
        }
    }

    /// Pairs placed.
    pub fn terms(&self) -> usize {
        self.pairs.len()
    }

    /// The cost of the marker at `p`, as [`marker_cost`]'s sum; `None` once it passes
    /// `limit` (then the rest is not added).
    pub fn cost(&self, p: &[f64; 3], cap: f64, limit: f64) -> Option<f64> {
        let mut sum = 0.0;
        for (q, d0, sigma) in &self.pairs {
            let e = (super::options::dist(p, q) - d0) / sigma;
            sum += (e * e).min(cap);
            if sum > limit {
                return None;
            }
        }
        for (a, b, c, sign) in &self.hands {
            if handedness(p, a, b, c) * sign < -0.05 {
                sum += cap;
            }
        }
        Some(sum)
    }
}
