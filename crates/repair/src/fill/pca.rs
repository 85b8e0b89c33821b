//! PCA fill after Gløersen & Federolf (2016, PLoS ONE 11(3) e0152616): marker positions are
//! centred per frame on the neighbours' centroid, weighted by distance to the target, and
//! a principal component model is trained on nearby frames where all of them are valid.
//! In the gap, the component scores are found by least squares from the neighbours' known
//! coordinates and the target is read back from the model; the anchor errors are then
//! blended out so the fill is continuous with the valid samples.

use super::{blend_edges, Fill, FillOptions, Plan, SkipReason, Span, Target};
use crate::linalg::{solve_in_place, symmetric_eigen};

/// Fewest training frames accepted.
const MIN_TRAIN: usize = 10;

pub(super) fn fill(t: &Target, span: Span, plan: &Plan, opts: &FillOptions) -> Fill {
    let d = t.data;
    let nb = &plan.pca;
    let (lo_o, hi_o) = span.outer();
    if nb.len() < 2 || !nb.iter().all(|&(j, _)| d.ok_through(j, lo_o, hi_o)) {
        return Err(SkipReason::NoDonors);
    }
    let known = 3 * nb.len();
    let dims = known + 3;
    // Row of one frame: weighted neighbour offsets from their centroid, then the target's.
    let centroid = |f: usize| {
        let mut c = [0.0; 3];
        for &(j, _) in nb {
            let p = d.at(j, f);
            for k in 0..3 {
                c[k] += p[k] / nb.len() as f64;
            }
        }
        c
    };
    let known_row = |f: usize, c: [f64; 3], row: &mut [f64]| {
        for (i, &(j, w)) in nb.iter().enumerate() {
            let p = d.at(j, f);
            for k in 0..3 {
                row[3 * i + k] = w * (p[k] - c[k]);
            }
        }
    };

    let half = opts.pca_window.max(5 * span.len());
    let lo = span.first.saturating_sub(half);
    let hi = (span.last + half).min(d.frames - 1);
    let mut n = 0usize;
    let mut sum = vec![0.0; dims];
    let mut cov = vec![0.0; dims * dims];
    let mut row = vec![0.0; dims];
    let mut shift: Option<Vec<f64>> = None;
    for f in lo..=hi {
        if !(t.ok(f) && nb.iter().all(|&(j, _)| d.ok(j, f))) {
            continue;
        }
        let c = centroid(f);
        known_row(f, c, &mut row);
        let p = t.at(f);
        for k in 0..3 {
            row[known + k] = p[k] - c[k];
        }
        // Sums about the first row keep the covariance accurate.
        let s = shift.get_or_insert_with(|| row.clone());
        for i in 0..dims {
            row[i] -= s[i];
        }
        n += 1;
        for i in 0..dims {
            sum[i] += row[i];
            let ri = row[i];
            for jj in i..dims {
                cov[i * dims + jj] += ri * row[jj];
            }
        }
    }
    let Some(shift) = shift.filter(|_| n >= MIN_TRAIN) else {
        return Err(SkipReason::NoContext);
    };
    let nf = n as f64;
    let mean: Vec<f64> = (0..dims).map(|i| shift[i] + sum[i] / nf).collect();
    for i in 0..dims {
        for jj in i..dims {
            let v = (cov[i * dims + jj] - sum[i] * sum[jj] / nf) / (nf - 1.0);
            cov[i * dims + jj] = v;
            cov[jj * dims + i] = v;
        }
    }
    let (vals, vecs) = symmetric_eigen(&cov, dims);
    let total: f64 = vals.iter().map(|v| v.max(0.0)).sum();
    if total <= 0.0 {
        return Err(SkipReason::Degenerate);
    }
    let max_pcs = known.min(n - 1).max(1);
    let mut pcs = 0;
    let mut acc = 0.0;
    while pcs < max_pcs && acc < opts.pca_variance * total {
        acc += vals[pcs].max(0.0);
        pcs += 1;
    }
    // Scores from known rows: z = (Vk' Vk)^-1 Vk' y. Precompute B = Vt (Vk' Vk)^-1 Vk'
    // (3 × known) so each frame costs one small product.
    let mut g = vec![0.0; pcs * pcs];
    for a in 0..pcs {
        for b in 0..pcs {
            g[a * pcs + b] = (0..known).map(|r| vecs[(r, a)] * vecs[(r, b)]).sum();
        }
    }
    let mut p = vec![0.0; pcs * known];
    for a in 0..pcs {
        for r in 0..known {
            p[a * known + r] = vecs[(r, a)];
        }
    }
    if !solve_in_place(&mut g, pcs, &mut p, known) {
        return Err(SkipReason::Degenerate);
    }
    let mut bmat = vec![0.0; 3 * known];
    for k in 0..3 {
        for r in 0..known {
            bmat[k * known + r] = (0..pcs)
                .map(|a| vecs[(known + k, a)] * p[a * known + r])
                .sum();
        }
    }
    let mut y = vec![0.0; known];
    let mut predict = |f: usize| {
        let c = centroid(f);
        known_row(f, c, &mut y);
        let mut out = [0.0; 3];
        for k in 0..3 {
            let mut v = mean[known + k];
            for r in 0..known {
                v += bmat[k * known + r] * (y[r] - mean[r]);
            }
            out[k] = v + c[k];
        }
        out
    };
    let mut out: Vec<[f64; 3]> = (span.first..=span.last).map(&mut predict).collect();
    let pb = span.before.map(&mut predict);
    let pa = span.after.map(&mut predict);
    blend_edges(&mut out, t, span, pb, pa);
    Ok(out)
}
