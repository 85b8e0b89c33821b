//! Soft skeleton constraint after Tits, Tilmanne & Dutoit (2018, PLoS ONE 13(7) e0199744):
//! a filled marker keeps each of its distances to neighbouring markers within the interval
//! that distance spans in the recorded data around the gap. Fills that drift away from the
//! body (long gaps, donors far away) are pulled back; fills that already respect the
//! skeleton are left exactly as they are.

use super::{dist, FillOptions, Plan, Span, Target};

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
        let intervals: Vec<(usize, f64, f64)> = donors
            .into_iter()
            .filter_map(|j| {
                let (mut mn, mut mx, mut n) = (f64::INFINITY, 0.0f64, 0usize);
                for f in lo..=hi {
                    if t.ok(f) && d.ok(j, f) {
                        let r = dist(t.at(f), d.at(j, f));
                        mn = mn.min(r);
                        mx = mx.max(r);
                        n += 1;
                    }
                }
                // Intervals seen over fewer frames than twice the gap may well miss the
                // poses inside it, and would then pull a good fill off.
                (n >= MIN_FRAMES.max(2 * span.len())).then_some((j, mn, mx))
            })
            .collect();
        let settled = 1e-6 * intervals.iter().map(|x| x.2).fold(0.0, f64::max);
        (intervals.len() >= 2).then_some(Skeleton { intervals, settled })
    }

    /// Moves each frame of `fill` (frames `span.first..`) into the intervals, by averaged
    /// projections onto the violated ones. Returns whether anything moved.
    pub fn apply(&self, t: &Target, span: Span, fill: &mut [[f64; 3]]) -> bool {
        let d = t.data;
        let mut moved = false;
        for (i, p) in fill.iter_mut().enumerate() {
            let f = span.first + i;
            for _ in 0..SWEEPS {
                let mut acc = [0.0; 3];
                let mut n = 0usize;
                for &(j, mn, mx) in &self.intervals {
                    let q = d.at(j, f);
                    let r = dist(*p, q);
                    if r <= 1e-12 {
                        continue;
                    }
                    let target = r.clamp(mn, mx);
                    if target != r {
                        let s = (target - r) / r;
                        for k in 0..3 {
                            acc[k] += s * (p[k] - q[k]);
                        }
                        n += 1;
                    }
                }
                if n == 0 {
                    break;
                }
                moved = true;
                let mut step = 0.0f64;
                for k in 0..3 {
                    let dk = acc[k] / n as f64;
                    p[k] += dk;
                    step = step.max(dk.abs());
                }
                if step < self.settled {
                    break;
                }
            }
        }
        moved
    }
}
