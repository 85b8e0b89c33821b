//! PCA fill after Gløersen & Federolf (2016, PLoS ONE 11(3) e0152616): marker positions are
//! centred per frame on the neighbours' centroid, weighted by distance to the target, and
//! a principal component model is trained on nearby frames (±max(pca_window, 5 × gap))
//! where all of them are valid. In the gap, the component scores are found by least squares
//! from the neighbours' known coordinates and the target is read back from the model; the
//! anchor errors are then blended out so the fill is continuous with the valid samples.
//!
//! The artificial gaps `auto` scores PCA on share one model trained without the frames of
//! all of them ([`Plan::exclude`]), so scores stay honest at the cost of one extra model per
//! gap rather than one per artificial gap; the real gap's model uses every valid frame.

use super::{blend_edges, Fill, FillOptions, Plan, SkipReason, Span, Target};
use crate::linalg::{solve_in_place, symmetric_eigen};
use nalgebra::DMatrix;

/// Fewest training frames accepted.
const MIN_TRAIN: usize = 10;

/// A trained model reduced to what prediction needs: the target's centred position is
/// `mean_t + B (y - mean_k)` for the neighbours' weighted centred coordinates `y`.
#[derive(Debug, Clone)]
pub(crate) struct Model {
    mean: Vec<f64>,
    bmat: Vec<f64>,
}

pub(super) fn fill(t: &Target, span: Span, plan: &Plan, opts: &FillOptions) -> Fill {
    let d = t.data;
    let nb = &plan.pca;
    let (lo_o, hi_o) = span.outer();
    if nb.len() < 2 || !nb.iter().all(|&(j, _)| d.ok_through(j, lo_o, hi_o)) {
        return Err(SkipReason::NoDonors);
    }
    let real = Target { hole: None, ..*t };
    let fresh;
    let model = match t.hole {
        None => plan
            .pca_model
            .get_or_init(|| train(&real, plan.region, nb, &[], opts)),
        Some((a, b)) if plan.exclude.iter().any(|&(ea, eb)| ea <= a && b <= eb) => plan
            .pca_scoring_model
            .get_or_init(|| train(&real, plan.region, nb, &plan.exclude, opts)),
        Some(_) => {
            fresh = train(t, plan.region, nb, &[], opts);
            &fresh
        }
    };
    let model = model.as_ref().map_err(|&e| e)?;
    let known = 3 * nb.len();
    let mut y = vec![0.0; known];
    let mut predict = |f: usize| {
        let c = centroid(t, nb, f);
        known_row(t, nb, f, c, &mut y);
        let mut out = [0.0; 3];
        for k in 0..3 {
            let brow = &model.bmat[k * known..(k + 1) * known];
            let v: f64 = brow
                .iter()
                .zip(&y)
                .zip(&model.mean)
                .map(|((b, yv), m)| b * (yv - m))
                .sum();
            out[k] = model.mean[known + k] + v + c[k];
        }
        out
    };
    let mut out: Vec<[f64; 3]> = (span.first..=span.last).map(&mut predict).collect();
    let pb = span.before.map(&mut predict);
    let pa = span.after.map(&mut predict);
    blend_edges(&mut out, t, span, pb, pa);
    Ok(out)
}

fn centroid(t: &Target, nb: &[(usize, f64)], f: usize) -> [f64; 3] {
    let mut c = [0.0; 3];
    for &(j, _) in nb {
        let p = t.data.at(j, f);
        for k in 0..3 {
            c[k] += p[k] / nb.len() as f64;
        }
    }
    c
}

/// Weighted neighbour offsets from their centroid `c`.
fn known_row(t: &Target, nb: &[(usize, f64)], f: usize, c: [f64; 3], row: &mut [f64]) {
    for (i, &(j, w)) in nb.iter().enumerate() {
        let p = t.data.at(j, f);
        for k in 0..3 {
            row[3 * i + k] = w * (p[k] - c[k]);
        }
    }
}

/// Trains on the frames of `region`'s window where the target and all neighbours are valid,
/// minus the `exclude` ranges.
fn train(
    t: &Target,
    region: Span,
    nb: &[(usize, f64)],
    exclude: &[(usize, usize)],
    opts: &FillOptions,
) -> Result<Model, SkipReason> {
    let d = t.data;
    let known = 3 * nb.len();
    let dims = known + 3;
    let half = opts.pca_window.max(5 * region.len());
    let lo = region.first.saturating_sub(half);
    let hi = (region.last + half).min(d.frames - 1);
    let frames: Vec<usize> = (lo..=hi)
        .filter(|&f| {
            t.ok(f)
                && !exclude.iter().any(|&(a, b)| f >= a && f <= b)
                && nb.iter().all(|&(j, _)| d.ok(j, f))
        })
        .collect();
    let n = frames.len();
    if n < MIN_TRAIN {
        return Err(SkipReason::NoContext);
    }
    // Rows are accumulated in blocks (columns of a small dims × BLOCK matrix, shifted by the
    // first row for accuracy) so the cross-products go through nalgebra's blocked gemm
    // without one large temporary per gap.
    const BLOCK: usize = 64;
    let mut shift: Option<Vec<f64>> = None;
    let mut sum = vec![0.0; dims];
    let mut xxt = DMatrix::<f64>::zeros(dims, dims);
    for chunk in frames.chunks(BLOCK) {
        let mut x = DMatrix::<f64>::zeros(dims, chunk.len());
        for (i, &f) in chunk.iter().enumerate() {
            let c = centroid(t, nb, f);
            let mut col = x.column_mut(i);
            let s = col.as_mut_slice();
            known_row(t, nb, f, c, &mut s[..known]);
            let p = t.at(f);
            for k in 0..3 {
                s[known + k] = p[k] - c[k];
            }
            let sh = shift.get_or_insert_with(|| s.to_vec());
            for (k, v) in s.iter_mut().enumerate() {
                *v -= sh[k];
                sum[k] += *v;
            }
        }
        xxt.gemm(1.0, &x, &x.transpose(), 1.0);
    }
    let Some(shift) = shift else {
        return Err(SkipReason::NoContext);
    };
    let nf = n as f64;
    let mean: Vec<f64> = (0..dims).map(|i| shift[i] + sum[i] / nf).collect();
    let mut cov = vec![0.0; dims * dims];
    for i in 0..dims {
        for j in 0..dims {
            cov[i * dims + j] = (xxt[(i, j)] - sum[i] * sum[j] / nf) / (nf - 1.0);
        }
    }
    let (vals, vecs) = symmetric_eigen(&cov, dims);
    let total: f64 = vals.iter().map(|v| v.max(0.0)).sum();
    if total <= 0.0 {
        return Err(SkipReason::Degenerate);
    }
    // Centring on the neighbours' centroid ties their coordinates (they sum to zero once
    // unweighted), so the known rows carry at most `known - 3` independent directions.
    let max_pcs = (known - 3).min(n - 1).max(1);
    let mut pcs = 0;
    let mut acc = 0.0;
    while pcs < max_pcs && acc < opts.pca_variance * total {
        acc += vals[pcs].max(0.0);
        pcs += 1;
    }
    // Scores from known rows: z = (Vk' Vk)^-1 Vk' y; B = Vt (Vk' Vk)^-1 Vk' (3 × known).
    // Should the known rows not determine every kept component, drop the weakest.
    let p = loop {
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
        if solve_in_place(&mut g, pcs, &mut p, known) {
            break p;
        }
        if pcs == 1 {
            return Err(SkipReason::Degenerate);
        }
        pcs -= 1;
    };
    let mut bmat = vec![0.0; 3 * known];
    for k in 0..3 {
        for r in 0..known {
            bmat[k * known + r] = (0..pcs)
                .map(|a| vecs[(known + k, a)] * p[a * known + r])
                .sum();
        }
    }
    Ok(Model { mean, bmat })
}
