//! Soft skeleton constraint after Tits, Tilmanne & Dutoit (2018, PLoS ONE 13(7) e0199744):
//! a filled marker keeps each of its distances to neighbouring markers within the interval
//! that distance spans in the recorded data around the gap. Fills that drift away from the
//! body (long gaps, donors far away) are pulled back; fills that already respect the
//! skeleton are left exactly as they are.

use super::{FillOptions, Plan, Span, Target};

fn dist2(a: [f64; 3], b: [f64; 3]) -> f64 {
    (a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)
}

/// Frames both markers must share for an interval to count.
const MIN_FRAMES: usize = 20;
/// Projection sweeps per frame.
const SWEEPS: usize = 10;

/// The observed distance intervals from a target to its donors around one gap.
pub(super) struct Skeleton {
    intervals: Vec<(usize, f64, f64)>,
    /// A correction smaller than this (a millionth of the longest interval's end) ends the
    /// sweeps early: the frame has settled.
    settled: f64,
    /// Per donor its squared distance to the target on each frame of the window from
    /// `lo` (NaN where either is invalid), kept so that `auto`'s artificial holes in the
    /// same marker get their intervals without a second pass over the markers (empty in
    /// those derived skeletons).
    series: Vec<(usize, Vec<f64>)>,
    lo: usize,
}

impl Skeleton {
    /// Intervals to the plan's donors valid through the gap, over the frames of the PCA
    /// training window where both markers are valid; `None` with fewer than two.
    pub fn new(t: &Target, span: Span, plan: &Plan, opts: &FillOptions) -> Option<Skeleton> {
        let d = t.data;
        let (lo_o, hi_o) = span.outer();
        let mut donors: Vec<usize> = plan.rigid.clone();
        donors.extend(plan.pca.iter().map(|&(j, _)| j));
        donors.sort_unstable();
        donors.dedup();
        donors.retain(|&j| d.ok_through(j, lo_o, hi_o));
        let half = opts.pca_window.max(5 * span.len());
        let lo = span.first.saturating_sub(half);
        let hi = (span.last + half).min(d.frames - 1);
        let series: Vec<(usize, Vec<f64>)> = donors
            .into_iter()
            .map(|j| {
                let (xt, xj) = (&d.xyz[t.m], &d.xyz[j]);
                let r: Vec<f64> = (lo..=hi)
                    .map(|f| {
                        if t.ok(f) && d.ok(j, f) {
                            dist2(xt[f], xj[f])
                        } else {
                            f64::NAN
                        }
                    })
                    .collect();
                (j, r)
            })
            .collect();
        let mut s = Skeleton::from_series(&series, lo, None, span.len())?;
        s.series = series;
        Some(s)
    }

    /// The same target's skeleton with the frames of `hole` (an artificial gap of the
    /// marker, as long as `len`) left out of the intervals too.
    pub fn without(&self, hole: (usize, usize), len: usize) -> Option<Skeleton> {
        let mut s = Skeleton::from_series(&self.series, self.lo, Some(hole), len)?;
        s.series = Vec::new();
        Some(s)
    }

    /// Intervals from the series, without the frames of `hole`; the skeleton keeps the
    /// series (callers that need no `without` may drop them).
    fn from_series(
        series: &[(usize, Vec<f64>)],
        lo: usize,
        hole: Option<(usize, usize)>,
        len: usize,
    ) -> Option<Skeleton> {
        let (h0, h1) = hole.map_or((1, 0), |(a, b)| {
            (a.saturating_sub(lo), (b + 1).saturating_sub(lo))
        });
        let intervals: Vec<(usize, f64, f64)> = series
            .iter()
            .filter_map(|(j, r)| {
                // Squared distances: one square root per interval end, not per frame.
                let (mut mn, mut mx, mut n) = (f64::INFINITY, 0.0f64, 0usize);
                for (i, &v) in r.iter().enumerate() {
                    if !(v.is_nan() || (h0..h1).contains(&i)) {
                        mn = mn.min(v);
                        mx = mx.max(v);
                        n += 1;
                    }
                }
                // Intervals seen over fewer frames than twice the gap may well miss the
                // poses inside it, and would then pull a good fill off.
                (n >= MIN_FRAMES.max(2 * len)).then_some((*j, mn.sqrt(), mx.sqrt()))
            })
            .collect();
        let settled = 1e-6 * intervals.iter().map(|x| x.2).fold(0.0, f64::max);
        (intervals.len() >= 2).then_some(Skeleton {
            intervals,
            settled,
            series: Vec::new(),
            lo,
        })
    }

    /// Moves each frame of `fill` (frames `span.first..`) into the intervals by cyclic
    /// projections onto the violated ones (each distance in turn set to the nearest end of
    /// its interval), sweeping until none is violated, the frame has settled, or
    /// [`SWEEPS`] sweeps. Returns whether anything moved.
    pub fn apply(&self, t: &Target, span: Span, fill: &mut [[f64; 3]]) -> bool {
        let d = t.data;
        let mut moved = false;
        for (i, p) in fill.iter_mut().enumerate() {
            let f = span.first + i;
            for _ in 0..SWEEPS {
                let mut step = 0.0f64;
                let mut violated = false;
                for &(j, mn, mx) in &self.intervals {
                    let q = d.at(j, f);
                    // Within the interval (the common case): no square root needed.
                    let r2 = dist2(*p, q);
                    if r2 >= mn * mn && r2 <= mx * mx {
                        continue;
                    }
                    let r = r2.sqrt();
                    if r <= 1e-12 {
                        continue;
                    }
                    let s = (r.clamp(mn, mx) - r) / r;
                    violated = true;
                    for k in 0..3 {
                        let dk = s * (p[k] - q[k]);
                        p[k] += dk;
                        step = step.max(dk.abs());
                    }
                }
                if !violated {
                    break;
                }
                moved = true;
                if step < self.settled {
                    break;
                }
            }
        }
        moved
    }
}
