//! The steady-offset witness of a jump: a label on another point leaves its path by one
//! vector and comes back by the same vector reversed, and between the two leaps it sits at
//! that offset from where its segment puts it.
//!
//! A person reading a jump whose links barely break (an offset across the links changes
//! their lengths little) looks at exactly this: the two leaps at the span's edges, their
//! sizes against the marker's own steps, and whether the marker, seen from its link
//! partners, holds the offset over the span. Skin sliding, a foot striking the ground or a
//! reconstruction settling do not: their leaps do not cancel, or the partners move with
//! the marker, or the offset drifts.

use super::context::{median, norm, Ctx};
use crate::linalg::kabsch;
use nalgebra::{Rotation3, Vector3};

/// The witness's parts, each 0 to 1 (1: what a label on another point gives).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Offset {
    /// How nearly the leap out takes back the leap in: 1 − |in + out| / the smaller.
    pub closure: f64,
    /// How steadily the marker holds the offset relative to its link partners: 1 when the
    /// median departure is at most [`STEADY_FULL`] of the offset, 0 from [`STEADY_NONE`].
    pub steady: f64,
    /// The smaller edge leap in units of the marker's break ([`Ctx::break_mm`]): above 1,
    /// both edges leave the marker's path.
    pub leap_ratio: f64,
    /// The median departure from the offset, as a share of it.
    pub departure: f64,
}

impl Offset {
    /// The witness as one share: the leaps cancel, the offset holds, and both edges
    /// break the marker's path (0 otherwise).
    pub fn share(&self) -> f64 {
        if self.leap_ratio > 1.0 {
            (self.closure * self.steady).clamp(0.0, 1.0)
        } else {
            0.0
        }
    }
}

/// Departure of the marker's offset from the leaps' offset, as a share of the offset,
/// up to which the span counts as steady in full ...
pub(super) const STEADY_FULL: f64 = 0.25;
/// ... and from which not at all.
pub(super) const STEADY_NONE: f64 = 0.5;

impl Ctx<'_> {
    /// The steady-offset witness of `a` over `s..=e` (the leaps at `s` and `e + 1`);
    /// `None` when an edge cannot be checked (the trial's ends, a sample missing beside an
    /// edge) or no link partner is seen beside both edges.
    ///
    /// The offset is the mean of the leap in and the leap out reversed. The marker's place
    /// just outside each edge is carried to every frame of the span by its link partners'
    /// motion (rigidly with three or more, by the swing of the line between two, by the translation
    /// of one), the two
    /// weighted by nearness; inside, the marker less that place should be the offset. The
    /// departure is the median over the span's frames of the difference, against the
    /// offset's size.
    pub(super) fn offset_witness(&self, a: usize, s: usize, e: usize) -> Option<Offset> {
        let nf = self.t.frames();
        if s < 2 || e + 2 >= nf || e < s {
            return None;
        }
        let (v1, v2) = (self.leap_vec(a, s)?, self.leap_vec(a, e + 1)?);
        let (n1, n2) = (norm(&v1), norm(&v2));
        let smaller = n1.min(n2).max(f64::MIN_POSITIVE);
        let sum: [f64; 3] = std::array::from_fn(|c| v1[c] + v2[c]);
        let closure = (1.0 - norm(&sum) / smaller).clamp(0.0, 1.0);
        let off: [f64; 3] = std::array::from_fn(|c| 0.5 * (v1[c] - v2[c]));
        let size = norm(&off).max(f64::MIN_POSITIVE);
        // Where the partners put the marker at `f`, from its place at the reference frame
        // `r`: the rigid motion of three or more partners from `r` to `f` (the segment
        // turning over a long span), the swing of the line between two, the translation
        // of one.
        let partners: Vec<usize> = self.links[a].iter().map(|l| l.other).collect();
        let put = |f: usize, r: usize| -> Option<[f64; 3]> {
            let at_r = self.pos(a, r, None)?;
            let (mut p, mut q) = (Vec::new(), Vec::new());
            for &l in &partners {
                if let (Some(x), Some(y)) = (self.pos(l, r, None), self.pos(l, f, None)) {
                    p.push(x);
                    q.push(y);
                }
            }
            if p.len() >= 3 {
                return kabsch(&p, &q).map(|t| t.apply(at_r));
            }
            if p.len() == 2 {
                // Two partners fix the segment's swing (the least rotation taking the line
                // between them at `r` to the one at `f`), not its twist about that line.
                let v = |x: [f64; 3]| Vector3::from(x);
                let (u0, u1) = (v(p[1]) - v(p[0]), v(q[1]) - v(q[0]));
                let rot = Rotation3::rotation_between(&u0, &u1)?;
                let (c0, c1) = ((v(p[0]) + v(p[1])) / 2.0, (v(q[0]) + v(q[1])) / 2.0);
                let x = c1 + rot * (v(at_r) - c0);
                return Some([x.x, x.y, x.z]);
            }
            if p.is_empty() {
                return None;
            }
            let n = p.len() as f64;
            Some(std::array::from_fn(|c| {
                at_r[c] + p.iter().zip(&q).map(|(x, y)| y[c] - x[c]).sum::<f64>() / n
            }))
        };
        let span = (e + 2 - s) as f64;
        let mut departures = Vec::with_capacity(e + 1 - s);
        for f in s..=e {
            let w = (f + 1 - s) as f64 / span;
            let (Some(p), Some(x0), Some(x1)) =
                (self.pos(a, f, None), put(f, s - 1), put(f, e + 1))
            else {
                continue;
            };
            let d: [f64; 3] =
                std::array::from_fn(|c| p[c] - (x0[c] + w * (x1[c] - x0[c])) - off[c]);
            departures.push(norm(&d) / size);
        }
        if departures.is_empty() {
            return None;
        }
        let q = median(departures);
        let steady = ((STEADY_NONE - q) / (STEADY_NONE - STEADY_FULL)).clamp(0.0, 1.0);
        Some(Offset {
            closure,
            steady,
            leap_ratio: smaller / self.break_mm(a),
            departure: q,
        })
    }
}
