//! PCA fill after Gløersen & Federolf (2016, PLoS ONE 11(3) e0152616): marker positions are
//! centred per frame on the neighbours' centroid, weighted by distance to the target, and
//! a principal component model is trained on nearby frames (±max(pca_window, 5 × gap))
//! where all of them are valid. In the gap, the component scores are found by least squares
//! from the neighbours' known coordinates and the target is read back from the model; the
//! anchor errors are then blended out so the fill is continuous with the valid samples.
//!
//! Each artificial gap `auto` scores PCA on gets a model trained without the gap's frames,
//! so scores stay honest: the real gap's training sums with those rows subtracted (no
//! second pass over the window). Nearby artificial gaps share a model trained without all
//! of them while together they hold at most a fifth of the training rows, which saves
//! eigen-decompositions.

use super::anchor::Raw;
use super::plan::ScoringModels;
use super::{FillOptions, Plan, SkipReason, Span, Target};
use crate::linalg::{solve_in_place, symmetric_eigen};
use crate::profile::{self, Count};
use nalgebra::DMatrix;
use std::cell::OnceCell;

/// Gaps shorter than this are filled with a scoring model (see `raw`).
const SHARE_BELOW: usize = 20;
/// Fewest training frames accepted.
const MIN_TRAIN: usize = 10;

/// A trained model reduced to what prediction needs: the target's centred position is
/// `mean_t + B (y - mean_k)` for the neighbours' weighted centred coordinates `y`.
#[derive(Debug, Clone)]
pub(crate) struct Model {
    mean: Vec<f64>,
    bmat: Vec<f64>,
}

/// The PCA prediction over the span, with residuals at up to `per_side` frames per side
/// (see [`Raw`]).
pub(super) fn raw(
    t: &Target,
    span: Span,
    plan: &Plan,
    opts: &FillOptions,
    per_side: usize,
) -> Result<Raw, SkipReason> {
    let d = t.data;
    let nb = neighbours_through(t, span, plan)?;
    let known = 3 * nb.len();
    // The target as the plan saw it (with the plan's own hole, if any).
    let base = Target {
        hole: plan.hole,
        ..*t
    };
    let all = || plan_sums(t, plan, opts);
    // The model trained without the artificial hole `h` and the others of its group.
    let scoring = |h: (usize, usize)| -> &Result<Model, SkipReason> {
        let s = match all() {
            Ok(s) => s,
            Err(e) => return plan.pca_model.get_or_init(|| Err(e)),
        };
        let (g, members) = group(plan, s, h);
        let models = &scoring_models(plan, s).1;
        models[g].get_or_init(|| model(&without(s, &base, nb, &members), known, opts))
    };
    let fresh;
    let model = match (t.hole, plan.hole) {
        // A short gap itself, with `auto`'s artificial holes chosen: the model of the
        // nearest holes' group fills it, one eigen-decomposition fewer per gap (it misses
        // a few short holes' rows, at most a fifth of the window), and PCA's scores on
        // those holes are exactly those of the model that fills. Long gaps keep the full
        // model: their holes are long and near, and their frames are the poses the gap
        // needs most (on the corpus evaluation, sharing cost 15 % at 80 frames).
        (None, None)
            if span.len() < SHARE_BELOW && plan.exclude.get().is_some_and(|v| !v.is_empty()) =>
        {
            let h0 = plan.exclude.get().and_then(|v| v.first().copied());
            scoring(h0.unwrap_or((0, 0)))
        }
        (h, p) if h == p => plan.pca_model.get_or_init(|| model(all()?, known, opts)),
        (Some(h), None) if plan.exclude.get().is_some_and(|v| v.contains(&h)) => scoring(h),
        (Some(h), None) => {
            fresh = all().and_then(|s| model(&without(s, &base, nb, &[h]), known, opts));
            &fresh
        }
        _ => {
            fresh = sums(t, plan.region, nb, opts).and_then(|s| model(&s, known, opts));
            &fresh
        }
    };
    let model = model.as_ref().map_err(|&e| e)?;
    let mut y = vec![0.0; known];
    let predict = |f: usize| {
        if !nb.iter().all(|&(j, _)| d.ok(j, f)) {
            return None;
        }
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
        Some(out)
    };
    Raw::gather(t, span, per_side, predict).ok_or(SkipReason::NoDonors)
}

pub(super) fn centroid(t: &Target, nb: &[(usize, f64)], f: usize) -> [f64; 3] {
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

/// Sums over the training rows: frames of `region`'s window where the target and all
/// neighbours are valid. Rows are shifted by the first one for accuracy.
#[derive(Debug, Clone)]
pub(crate) struct Sums {
    frames: Vec<usize>,
    shift: Vec<f64>,
    sum: Vec<f64>,
    xxt: DMatrix<f64>,
}

/// One frame's row (unshifted): weighted neighbour offsets, then the target's offset.
pub(super) fn row(t: &Target, nb: &[(usize, f64)], f: usize, out: &mut [f64]) {
    let known = 3 * nb.len();
    let c = centroid(t, nb, f);
    known_row(t, nb, f, c, &mut out[..known]);
    let p = t.at(f);
    for k in 0..3 {
        out[known + k] = p[k] - c[k];
    }
}

pub(super) fn sums(
    t: &Target,
    region: Span,
    nb: &[(usize, f64)],
    opts: &FillOptions,
) -> Result<Sums, SkipReason> {
    profile::count(Count::PcaSums);
    let d = t.data;
    let dims = 3 * nb.len() + 3;
    let half = opts.pca_window.max(5 * region.len());
    let lo = region.first.saturating_sub(half);
    let hi = (region.last + half).min(d.frames - 1);
    let frames: Vec<usize> = (lo..=hi)
        .filter(|&f| t.ok(f) && nb.iter().all(|&(j, _)| d.ok(j, f)))
        .collect();
    let Some(&f0) = frames.first() else {
        return Err(SkipReason::NoContext);
    };
    let mut shift = vec![0.0; dims];
    row(t, nb, f0, &mut shift);
    // Rows are accumulated in blocks (columns of a small dims × BLOCK matrix) so the
    // cross-products go through nalgebra's blocked gemm without a large temporary.
    const BLOCK: usize = 64;
    let mut sum = vec![0.0; dims];
    let mut xxt = DMatrix::<f64>::zeros(dims, dims);
    for chunk in frames.chunks(BLOCK) {
        let mut x = DMatrix::<f64>::zeros(dims, chunk.len());
        for (i, &f) in chunk.iter().enumerate() {
            let mut col = x.column_mut(i);
            let s = col.as_mut_slice();
            row(t, nb, f, s);
            for (k, v) in s.iter_mut().enumerate() {
                *v -= shift[k];
                sum[k] += *v;
            }
        }
        xxt.gemm(1.0, &x, &x.transpose(), 1.0);
    }
    Ok(Sums {
        frames,
        shift,
        sum,
        xxt,
    })
}

impl Sums {
    /// The training frames.
    pub(super) fn frames(&self) -> &[usize] {
        &self.frames
    }

    /// Mean row and covariance (row-major, `dims × dims`) of the rows summed.
    pub(super) fn moments(&self) -> (Vec<f64>, Vec<f64>) {
        let dims = self.shift.len();
        let nf = self.frames.len() as f64;
        let (sum, xxt) = (&self.sum, &self.xxt);
        let mean: Vec<f64> = (0..dims).map(|i| self.shift[i] + sum[i] / nf).collect();
        let mut cov = vec![0.0; dims * dims];
        for i in 0..dims {
            for j in 0..dims {
                cov[i * dims + j] = (xxt[(i, j)] - sum[i] * sum[j] / nf) / (nf - 1.0);
            }
        }
        (mean, cov)
    }
}

/// The plan's PCA neighbours, when there are at least two and each is valid through the
/// span and its anchors (the rows are centred on their centroid frame by frame).
pub(super) fn neighbours_through<'p>(
    t: &Target,
    span: Span,
    plan: &'p Plan,
) -> Result<&'p [(usize, f64)], SkipReason> {
    let nb = &plan.pca;
    let (lo, hi) = span.outer();
    if nb.len() < 2 || !nb.iter().all(|&(j, _)| t.data.ok_through(j, lo, hi)) {
        return Err(SkipReason::NoDonors);
    }
    Ok(nb)
}

/// The plan's scoring models, grouped on first use (see `groups`).
fn scoring_models<'p>(plan: &'p Plan, all: &Sums) -> &'p ScoringModels {
    let holes = plan.exclude.get().map_or(&[][..], Vec::as_slice);
    plan.pca_scoring_models.get_or_init(|| groups(all, holes))
}

/// The scoring model of artificial hole `h`: its index, and the holes trained without.
fn group(plan: &Plan, all: &Sums, h: (usize, usize)) -> (usize, Vec<(usize, usize)>) {
    let holes = plan.exclude.get().map_or(&[][..], Vec::as_slice);
    let group_of = &scoring_models(plan, all).0;
    let g = group_of[holes.iter().position(|&x| x == h).unwrap_or(0)];
    let members = holes
        .iter()
        .zip(group_of)
        .filter(|&(_, &k)| k == g)
        .map(|(&x, _)| x)
        .collect();
    (g, members)
}

/// The plan's training sums (the gap's own model's rows), gathered on first use.
fn plan_sums<'p>(t: &Target, plan: &'p Plan, opts: &FillOptions) -> Result<&'p Sums, SkipReason> {
    let base = Target {
        hole: plan.hole,
        ..*t
    };
    plan.pca_sums
        .get_or_init(|| sums(&base, plan.region, &plan.pca, opts))
        .as_ref()
        .map_err(|&e| e)
}

/// Which of PCA's scoring models artificial hole `h` shares (see `groups`), and the holes
/// it is trained without. The Kalman smoother trains its models on the same rows as PCA,
/// so both are scored alike.
pub(super) fn scoring_group(
    t: &Target,
    plan: &Plan,
    opts: &FillOptions,
    h: (usize, usize),
) -> Result<(usize, Vec<(usize, usize)>), SkipReason> {
    Ok(group(plan, plan_sums(t, plan, opts)?, h))
}

/// The training sums of the plan's window without the artificial holes `exclude` (none:
/// the gap's own model's rows).
pub(super) fn training(
    t: &Target,
    plan: &Plan,
    opts: &FillOptions,
    exclude: &[(usize, usize)],
) -> Result<Sums, SkipReason> {
    let all = plan_sums(t, plan, opts)?;
    let base = Target {
        hole: plan.hole,
        ..*t
    };
    Ok(without(all, &base, &plan.pca, exclude))
}

/// Holes sharing a scoring model: consecutive ones while together they remove at most
/// `1 / SHARE` of the training rows (at least one hole per model). Fewer
/// eigen-decompositions, and every model still trains on nearly all the window.
fn groups(s: &Sums, holes: &[(usize, usize)]) -> ScoringModels {
    const SHARE: usize = 5;
    let cap = s.frames.len() / SHARE;
    let mut group_of = Vec::with_capacity(holes.len());
    let (mut g, mut used) = (0, 0);
    for (i, &(a, b)) in holes.iter().enumerate() {
        let n = b - a + 1;
        if i > 0 && used + n > cap {
            g += 1;
            used = 0;
        }
        used += n;
        group_of.push(g);
    }
    let models = (0..=g).map(|_| OnceCell::new()).collect();
    (group_of, models)
}

/// `s` without the rows of frames inside `exclude` (artificial gaps): a downdate instead
/// of a second pass over the window.
fn without(s: &Sums, t: &Target, nb: &[(usize, f64)], exclude: &[(usize, usize)]) -> Sums {
    let dims = s.shift.len();
    let mut out = s.clone();
    let mut gone: Vec<usize> = Vec::new();
    for &(a, b) in exclude {
        let i0 = out.frames.partition_point(|&f| f < a);
        let i1 = out.frames.partition_point(|&f| f <= b);
        gone.extend_from_slice(&out.frames[i0..i1]);
        out.frames.drain(i0..i1);
    }
    // The removed rows' cross-products go through one gemm per block, as in `sums`.
    const BLOCK: usize = 64;
    for chunk in gone.chunks(BLOCK) {
        let mut x = DMatrix::<f64>::zeros(dims, chunk.len());
        for (i, &f) in chunk.iter().enumerate() {
            let mut col = x.column_mut(i);
            let r = col.as_mut_slice();
            row(t, nb, f, r);
            for ((v, sh), acc) in r.iter_mut().zip(&out.shift).zip(out.sum.iter_mut()) {
                *v -= sh;
                *acc -= *v;
            }
        }
        out.xxt.gemm(-1.0, &x, &x.transpose(), 1.0);
    }
    out
}

/// The model of the rows summed in `s`.
fn model(s: &Sums, known: usize, opts: &FillOptions) -> Result<Model, SkipReason> {
    profile::count(Count::PcaModel);
    let dims = known + 3;
    let n = s.frames.len();
    if n < MIN_TRAIN {
        return Err(SkipReason::NoContext);
    }
    let (mean, cov) = s.moments();
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
