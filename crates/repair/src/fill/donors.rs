//! Donor choice for one gap, made once and reused when `auto` scores methods on artificial
//! gaps nearby, so scores describe the fill that will actually be used.

use std::cell::OnceCell;

use super::data::{dist, Span, Target};
use super::options::FillOptions;
use crate::profile::{self, Count, Work};

/// Candidates are first narrowed to the markers nearest the target at the gap's anchor;
/// donors that move with the target are near it, and this bounds the work per gap. 24
/// instead of 16 (with `auto`'s wide PCA model taking all of them) was chosen in 25 of 26
/// folds of `fill_eval --nested` (held-apart cells of `auto` 2.7 % better to 1.5 % worse,
/// most 1–2 % better); the pipeline bench took 1.06× as long.
const NEAREST: usize = 24;
/// Frames both markers must share in the window for their statistics to count.
const MIN_COMMON: usize = 10;

/// Donors chosen for one gap.
#[derive(Debug, Clone)]
pub(crate) struct Donors {
    /// Rigid donors, smallest distance variation to the target first (empty: none usable).
    pub rigid: Vec<usize>,
    /// Best-correlated donor.
    pub pattern: Option<usize>,
    /// PCA neighbours (nearest first) with their weights.
    pub pca: Vec<(usize, f64)>,
    /// The gap the plan was made for (centre of the PCA training window).
    pub region: Span,
    /// The artificial hole the target had when the plan was made (`auto` scoring on
    /// another marker): kept out of PCA training like the target's invalid frames.
    pub hole: Option<(usize, usize)>,
    /// `auto`'s artificial holes in the target, nearest the gap first: PCA scores them
    /// with models trained without a few of them at a time (see `pca::raw`).
    pub exclude: OnceCell<Vec<(usize, usize)>>,
}

struct Stats {
    m: usize,
    mean_dist: f64,
    std_dist: f64,
    corr: f64,
}

impl Donors {
    /// No donors (for methods that use none).
    pub fn empty(span: Span) -> Donors {
        Donors {
            rigid: Vec::new(),
            pattern: None,
            pca: Vec::new(),
            region: span,
            hole: None,
            exclude: OnceCell::new(),
        }
    }

    /// Chooses donors among markers valid through the gap and its anchors, from their
    /// relation to the target over the valid frames within ±max(60, 2 × gap) frames.
    pub fn build(t: &Target, span: Span, opts: &FillOptions) -> Donors {
        let _time = profile::time(Work::Plan);
        profile::count(Count::Plan);
        let d = t.data;
        let (lo_o, hi_o) = span.outer();
        let anchor = match (span.before, span.after) {
            (Some(b), _) if t.ok(b) => b,
            (_, Some(a)) if t.ok(a) => a,
            _ => {
                return Donors {
                    hole: t.hole,
                    ..Donors::empty(span)
                }
            }
        };
        let pa = t.at(anchor);
        let mut cands: Vec<(f64, usize)> = (0..d.xyz.len())
            .filter(|&j| j != t.m && d.ok_through(j, lo_o, hi_o))
            .map(|j| (dist(pa, d.at(j, anchor)), j))
            .collect();
        cands.sort_by(|a, b| a.0.total_cmp(&b.0));
        cands.truncate(NEAREST);

        let c = (2 * span.len()).max(60);
        let lo = span.first.saturating_sub(c);
        let hi = (span.last + c).min(d.frames - 1);
        let stats: Vec<Stats> = cands
            .iter()
            .filter_map(|&(_, j)| stats(t, j, lo, hi, anchor))
            .collect();

        let mut by_std: Vec<&Stats> = stats.iter().collect();
        by_std.sort_by(|a, b| a.std_dist.total_cmp(&b.std_dist));
        let rigid = if by_std.len() >= 3 {
            by_std.iter().take(opts.rigid_donors).map(|s| s.m).collect()
        } else {
            Vec::new()
        };
        let pattern = stats
            .iter()
            .max_by(|a, b| a.corr.total_cmp(&b.corr))
            .map(|s| s.m);
        let mut by_dist: Vec<&Stats> = stats.iter().collect();
        by_dist.sort_by(|a, b| a.mean_dist.total_cmp(&b.mean_dist));
        by_dist.truncate(opts.pca_neighbours);
        let pca = if by_dist.len() >= 2 {
            // Gaussian weights in distance, scaled by the median neighbour distance, so
            // nearby markers dominate the components (Gløersen & Federolf's weighting idea).
            let med = by_dist[by_dist.len() / 2].mean_dist.max(1e-9);
            by_dist
                .iter()
                .map(|s| {
                    let r = s.mean_dist / med;
                    (s.m, (-0.5 * r * r).exp().max(0.05))
                })
                .collect()
        } else {
            Vec::new()
        };
        Donors {
            rigid,
            pattern,
            pca,
            region: span,
            hole: t.hole,
            exclude: OnceCell::new(),
        }
    }
}

/// Distance mean/std and mean per-coordinate Pearson correlation of marker `j` with the
/// target over frames `lo..=hi` where both are valid (both are valid at `anchor`).
fn stats(t: &Target, j: usize, lo: usize, hi: usize, anchor: usize) -> Option<Stats> {
    let d = t.data;
    let (mut n, mut sd, mut sd2) = (0usize, 0.0, 0.0);
    let mut sx = [0.0; 3];
    let mut sy = [0.0; 3];
    let mut sxx = [0.0; 3];
    let mut syy = [0.0; 3];
    let mut sxy = [0.0; 3];
    let (pt0, pj0) = (t.at(anchor), d.at(j, anchor));
    for f in lo..=hi {
        if !(t.ok(f) && d.ok(j, f)) {
            continue;
        }
        let (p, q) = (t.at(f), d.at(j, f));
        let dd = dist(p, q);
        n += 1;
        sd += dd;
        sd2 += dd * dd;
        for k in 0..3 {
            // Shifted sums keep the variance accurate for large coordinates.
            let (x, y) = (p[k] - pt0[k], q[k] - pj0[k]);
            sx[k] += x;
            sy[k] += y;
            sxx[k] += x * x;
            syy[k] += y * y;
            sxy[k] += x * y;
        }
    }
    if n < MIN_COMMON {
        return None;
    }
    let nf = n as f64;
    let mean = sd / nf;
    let var = (sd2 / nf - mean * mean).max(0.0);
    let mut corr = 0.0;
    for k in 0..3 {
        let vx = sxx[k] - sx[k] * sx[k] / nf;
        let vy = syy[k] - sy[k] * sy[k] / nf;
        let cxy = sxy[k] - sx[k] * sy[k] / nf;
        if vx > 1e-12 && vy > 1e-12 {
            corr += cxy / (vx * vy).sqrt();
        }
    }
    Some(Stats {
        m: j,
        mean_dist: mean,
        std_dist: var.sqrt(),
        corr: corr / 3.0,
    })
}
