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
use super::data::{Span, Target};
use super::donors::Donors;
use super::options::FillOptions;
use super::outcome::SkipReason;
use super::subspace::{
    basis, centroid, group, known_row, neighbours_through, own_basis, plan_sums, scoring_basis,
    scoring_groups, sums, without, Basis, Shared, Sums,
};
use crate::linalg::solve_in_place;
use crate::profile::{self, Count};
use std::cell::OnceCell;

/// Gaps shorter than this are filled with a scoring model (see `raw`).
const SHARE_BELOW: usize = 20;

/// A trained model reduced to what prediction needs: the target's centred position is
/// `mean_t + B (y - mean_k)` for the neighbours' weighted centred coordinates `y`.
#[derive(Debug, Clone)]
pub(crate) struct Model {
    mean: Vec<f64>,
    bmat: Vec<f64>,
}

/// A lazily trained PCA model.
type LazyModel = OnceCell<Result<Model, SkipReason>>;

/// One plan's PCA models, trained on first use: the gap's own, and per group of `auto`'s
/// artificial holes (see `subspace::groups`) the one trained without them.
#[derive(Debug, Clone, Default)]
pub(crate) struct Cache {
    /// The model for the gap itself.
    model: LazyModel,
    /// Per group of holes, its model.
    scoring: OnceCell<Vec<LazyModel>>,
}

/// The PCA prediction over the span, with residuals at up to `per_side` frames per side
/// (see [`Raw`]).
pub(super) fn raw(
    t: &Target,
    span: Span,
    plan: &Donors,
    shared: &Shared,
    cache: &Cache,
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
    let all = || plan_sums(t, plan, shared, opts);
    // The model trained without the artificial hole `h` and the others of its group.
    let scoring = |h: (usize, usize)| -> &Result<Model, SkipReason> {
        let s = match all() {
            Ok(s) => s,
            Err(e) => return cache.model.get_or_init(|| Err(e)),
        };
        let (g, _) = group(plan, shared, s, h);
        let models = scoring_models(plan, shared, cache, s);
        models[g].get_or_init(|| {
            scoring_basis(t, plan, shared, opts, h).and_then(|(_, b)| model(&b, known))
        })
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
        (h, p) if h == p => cache
            .model
            .get_or_init(|| own_basis(t, plan, shared, opts).and_then(|b| model(&b, known))),
        (Some(h), None) if plan.exclude.get().is_some_and(|v| v.contains(&h)) => scoring(h),
        (Some(h), None) => {
            fresh = all()
                .and_then(|s| basis(&without(s, &base, nb, &[h]), known, opts))
                .and_then(|b| model(&b, known));
            &fresh
        }
        _ => {
            fresh = sums(t, plan.region, nb, opts)
                .and_then(|s| basis(&s, known, opts))
                .and_then(|b| model(&b, known));
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

/// The plan's scoring models, one per group of holes (see `subspace::groups`), made on
/// first use.
fn scoring_models<'c>(
    plan: &Donors,
    shared: &Shared,
    cache: &'c Cache,
    all: &Sums,
) -> &'c [LazyModel] {
    let count = scoring_groups(plan, shared, all)
        .last()
        .map_or(1, |&g| g + 1);
    cache
        .scoring
        .get_or_init(|| (0..count).map(|_| OnceCell::new()).collect())
}

/// The model of the components `comp` (of rows with `known` neighbour coordinates).
fn model(comp: &Basis, known: usize) -> Result<Model, SkipReason> {
    profile::count(Count::PcaModel);
    let vecs = &comp.vectors;
    let mut pcs = vecs.ncols();
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
    Ok(Model {
        mean: comp.mean.clone(),
        bmat,
    })
}
