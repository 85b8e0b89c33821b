//! Soft skeleton constraint after Tits, Tilmanne & Dutoit (2018, PLoS ONE 13(7) e0199744):
//! a filled marker keeps each of its distances to neighbouring markers within the interval
//! that distance spans in the recorded data around the gap. Fills that drift away from the
//! body (long gaps, donors far away) are pulled back; fills that already respect the
//! skeleton are left exactly as they are.

use super::data::{Span, Target};
use super::donors::Donors;
use super::options::FillOptions;

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
    /// Per donor the running extremes of its squared distance to the target over the
    /// window from `lo`, kept so that `auto`'s artificial holes in the same marker get
    /// their intervals without another pass (empty in those derived skeletons).
    runs: Vec<Runs>,
    lo: usize,
}

/// One donor's squared distances over a window of `w` frames summarised for any hole:
/// `pre[i]` covers frames `..i`, `suf[i]` frames `i..`, each (min, max, valid count).
struct Runs {
    j: usize,
    pre: Vec<(f64, f64, usize)>,
    suf: Vec<(f64, f64, usize)>,
}

impl Runs {
    /// The runs of `values` (one per window frame, `None` where either marker is invalid),
    /// read twice (forwards, then backwards) rather than gathered first: a skeleton reads
    /// a window of up to thousands of frames for each of its donors.
    fn new(j: usize, w: usize, values: impl Fn(usize) -> Option<f64>) -> Runs {
        let add = |(mn, mx, n): (f64, f64, usize), v: Option<f64>| match v {
            Some(v) => (mn.min(v), mx.max(v), n + 1),
            None => (mn, mx, n),
        };
        let empty = (f64::INFINITY, 0.0f64, 0usize);
        let mut pre = Vec::with_capacity(w + 1);
        let mut acc = empty;
        pre.push(acc);
        for i in 0..w {
            acc = add(acc, values(i));
            pre.push(acc);
        }
        let mut suf = vec![empty; w + 1];
        let mut acc = empty;
        for (i, s) in suf[..w].iter_mut().enumerate().rev() {
            acc = add(acc, values(i));
            *s = acc;
        }
        Runs { j, pre, suf }
    }

    /// (min, max, count) over the window without window indices `h0..h1`.
    fn without(&self, h0: usize, h1: usize) -> (f64, f64, usize) {
        let w = self.suf.len() - 1;
        let (h0, h1) = (h0.min(w), h1.clamp(h0.min(w), w));
        let (a, b) = (self.pre[h0], self.suf[h1]);
        (a.0.min(b.0), a.1.max(b.1), a.2 + b.2)
    }
}

impl Skeleton {
    /// Intervals to the plan's donors valid through the gap, over the frames of the PCA
    /// training window where both markers are valid; `None` with fewer than two.
    pub fn new(t: &Target, span: Span, plan: &Donors, opts: &FillOptions) -> Option<Skeleton> {
        let _time = crate::profile::time(crate::profile::Work::Skeleton);
        crate::profile::count(crate::profile::Count::Skeleton);
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
        // Squared distances: one square root per interval end, not per frame.
        let runs: Vec<Runs> = donors
            .into_iter()
            .map(|j| {
                let (xt, xj) = (&d.xyz[t.m][lo..=hi], &d.xyz[j][lo..=hi]);
                let ok = |f: usize| t.ok(f) && d.ok(j, f);
                Runs::new(j, hi - lo + 1, |i| ok(lo + i).then(|| dist2(xt[i], xj[i])))
            })
            .collect();
        let mut s = Skeleton::from_runs(&runs, lo, None, span.len())?;
        s.runs = runs;
        Some(s)
    }

    /// The same target's skeleton with the frames of `hole` (an artificial gap of the
    /// marker, as long as `len`) left out of the intervals too.
    pub fn without(&self, hole: (usize, usize), len: usize) -> Option<Skeleton> {
        Skeleton::from_runs(&self.runs, self.lo, Some(hole), len)
    }

    /// Intervals from the runs, without the frames of `hole`.
    fn from_runs(
        runs: &[Runs],
        lo: usize,
        hole: Option<(usize, usize)>,
        len: usize,
    ) -> Option<Skeleton> {
        let (h0, h1) = hole.map_or((0, 0), |(a, b)| {
            (a.saturating_sub(lo), (b + 1).saturating_sub(lo))
        });
        let intervals: Vec<(usize, f64, f64)> = runs
            .iter()
            .filter_map(|r| {
                let (mn, mx, n) = r.without(h0, h1);
                // Intervals seen over fewer frames than twice the gap may well miss the
                // poses inside it, and would then pull a good fill off.
                (n >= MIN_FRAMES.max(2 * len)).then_some((r.j, mn.sqrt(), mx.sqrt()))
            })
            .collect();
        let settled = 1e-6 * intervals.iter().map(|x| x.2).fold(0.0, f64::max);
        (intervals.len() >= 2).then_some(Skeleton {
            intervals,
            settled,
            runs: Vec::new(),
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
