//! The subspace PCA and the Kalman smoother share: per frame, the PCA neighbours' positions
//! centred on their centroid and weighted (the target's offset after them), summed over the
//! training window of the plan's gap. Each artificial gap `auto` scores on is trained
//! without its own rows, and nearby artificial gaps share one such training set while
//! together they hold at most a fifth of the rows (see [`groups`]).

use std::cell::OnceCell;
use std::rc::Rc;

use nalgebra::DMatrix;

use super::data::{Span, Target};
use super::donors::Donors;
use super::options::FillOptions;
use super::outcome::SkipReason;
use crate::linalg::Leading;
use crate::profile::{self, Count};

/// Fewest training frames a PCA or Kalman model accepts.
pub(super) const MIN_TRAIN: usize = 10;

/// What PCA and the Kalman smoother share for one plan, gathered on first use: the
/// training sums of the gap's window, and which artificial holes train together.
#[derive(Debug, Clone, Default)]
pub(crate) struct Shared {
    /// The PCA training sums for the gap's window.
    sums: OnceCell<Result<Sums, SkipReason>>,
    /// Per hole of the plan's `exclude`, the group of holes it is trained without.
    groups: OnceCell<Vec<usize>>,
    /// The components of the gap's own rows, and per group of holes those of the rows
    /// without them: PCA's model and the Kalman smoother's of the same rows both start
    /// from these (see [`Basis`]).
    own: LazyBasis,
    scoring: OnceCell<Vec<LazyBasis>>,
    /// The rows of the plan's training frames ([`row`] each, `dims` apiece), for the
    /// Kalman smoother's training scores.
    rows: OnceCell<Vec<f64>>,
}

/// Training rows gathered once ([`row`] of each frame, `dims` numbers apiece, frame after
/// frame): a plan's whole window, whose frames every model of the plan trains on a part
/// of. The Kalman smoother's models score every training frame, and worked each row out
/// again per model (its neighbours' centroid and offsets), as many times as the plan has
/// models.
#[derive(Clone, Copy)]
pub(super) struct Rows<'a> {
    pub(super) frames: &'a [usize],
    pub(super) data: &'a [f64],
}

/// The rows of `frames` (see [`Rows`]).
pub(super) fn rows_of(t: &Target, nb: &[(usize, f64)], frames: &[usize]) -> Vec<f64> {
    let dims = 3 * nb.len() + 3;
    let mut data = vec![0.0; frames.len() * dims];
    for (&f, out) in frames.iter().zip(data.chunks_exact_mut(dims)) {
        row(t, nb, f, out);
    }
    data
}

/// The rows of the plan's training frames (the gap's own model's), made on first use.
pub(super) fn plan_rows<'s>(
    t: &Target,
    plan: &Donors,
    shared: &'s Shared,
    opts: &FillOptions,
) -> Result<Rows<'s>, SkipReason> {
    let all = plan_sums(t, plan, shared, opts)?;
    let data = shared
        .rows
        .get_or_init(|| rows_of(t, &plan.pca, &all.frames));
    Ok(Rows {
        frames: &all.frames,
        data,
    })
}

/// A [`Basis`] made on first use.
type LazyBasis = OnceCell<Result<Rc<Basis>, SkipReason>>;

/// The principal components of one set of training rows, as PCA and the Kalman smoother
/// both keep them: the components that explain `pca_variance` of the variance, no more
/// than the neighbours determine. Both trained their own from the same rows (a gap's own
/// window, or the window without a group of `auto`'s holes), so each such decomposition
/// was made twice for every gap the smoother is weighed on; made once, the two models are
/// the same to the bit (the decomposition is deterministic).
#[derive(Debug)]
pub(crate) struct Basis {
    /// The training frames.
    pub(super) frames: Vec<usize>,
    /// The mean row.
    pub(super) mean: Vec<f64>,
    /// Every eigenvalue of the rows' covariance, descending.
    pub(super) values: Vec<f64>,
    /// Their sum, negative ones (rounding's) counted as 0.
    pub(super) total: f64,
    /// The kept components (`dims × kept`).
    pub(super) vectors: DMatrix<f64>,
}

/// The components of the rows summed in `s` (`known` neighbour coordinates, the target's
/// three after them).
pub(super) fn basis(s: &Sums, known: usize, opts: &FillOptions) -> Result<Basis, SkipReason> {
    let dims = known + 3;
    let n = s.frames.len();
    if n < MIN_TRAIN {
        return Err(SkipReason::NoContext);
    }
    let (mean, cov) = s.moments();
    // All the eigenvalues choose the components; only the kept ones' vectors are made.
    let eigen = Leading::new(&cov, dims);
    let vals = eigen.values();
    let total: f64 = vals.iter().map(|v| v.max(0.0)).sum();
    if total <= 0.0 {
        return Err(SkipReason::Degenerate);
    }
    // Centring on the neighbours' centroid ties their coordinates (they sum to zero once
    // unweighted), so the known rows carry at most `known - 3` independent directions.
    // Fewer components (99 or 99.5 % for the smoother) were worse at every gap length on
    // the corpus evaluation.
    let max_pcs = (known - 3).min(n - 1).max(1);
    let (mut pcs, mut acc) = (0, 0.0);
    while pcs < max_pcs && acc < opts.pca_variance * total {
        acc += vals[pcs].max(0.0);
        pcs += 1;
    }
    Ok(Basis {
        frames: s.frames.clone(),
        mean,
        values: vals.to_vec(),
        total,
        vectors: eigen.vectors(pcs),
    })
}

/// The components of the plan's own rows (the gap's window), made on first use.
pub(super) fn own_basis(
    t: &Target,
    plan: &Donors,
    shared: &Shared,
    opts: &FillOptions,
) -> Result<Rc<Basis>, SkipReason> {
    shared
        .own
        .get_or_init(|| {
            let all = plan_sums(t, plan, shared, opts)?;
            basis(all, 3 * plan.pca.len(), opts).map(Rc::new)
        })
        .clone()
}

/// The components of the rows without artificial hole `h`'s group (see [`group`]), made
/// on first use; with the group's index.
pub(super) fn scoring_basis(
    t: &Target,
    plan: &Donors,
    shared: &Shared,
    opts: &FillOptions,
    h: (usize, usize),
) -> Result<(usize, Rc<Basis>), SkipReason> {
    let all = plan_sums(t, plan, shared, opts)?;
    let (g, members) = group(plan, shared, all, h);
    let count = scoring_groups(plan, shared, all)
        .last()
        .map_or(1, |&g| g + 1);
    let cells = shared
        .scoring
        .get_or_init(|| (0..count).map(|_| OnceCell::new()).collect());
    let cell = cells.get(g).ok_or(SkipReason::NoContext)?;
    let b = cell.get_or_init(|| {
        let base = Target {
            hole: plan.hole,
            ..*t
        };
        basis(
            &without(all, &base, &plan.pca, &members),
            3 * plan.pca.len(),
            opts,
        )
        .map(Rc::new)
    });
    b.clone().map(|b| (g, b))
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
pub(super) fn known_row(t: &Target, nb: &[(usize, f64)], f: usize, c: [f64; 3], row: &mut [f64]) {
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
    plan: &'p Donors,
) -> Result<&'p [(usize, f64)], SkipReason> {
    let nb = &plan.pca;
    let (lo, hi) = span.outer();
    if nb.len() < 2 || !nb.iter().all(|&(j, _)| t.data.ok_through(j, lo, hi)) {
        return Err(SkipReason::NoDonors);
    }
    Ok(nb)
}

/// Per hole of the plan's `exclude`, its group (see [`groups`]), worked out on first use.
pub(super) fn scoring_groups<'s>(plan: &Donors, shared: &'s Shared, all: &Sums) -> &'s [usize] {
    let holes = plan.exclude.get().map_or(&[][..], Vec::as_slice);
    shared.groups.get_or_init(|| groups(all, holes))
}

/// The scoring model of artificial hole `h`: its index, and the holes trained without.
pub(super) fn group(
    plan: &Donors,
    shared: &Shared,
    all: &Sums,
    h: (usize, usize),
) -> (usize, Vec<(usize, usize)>) {
    let holes = plan.exclude.get().map_or(&[][..], Vec::as_slice);
    let group_of = scoring_groups(plan, shared, all);
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
pub(super) fn plan_sums<'s>(
    t: &Target,
    plan: &Donors,
    shared: &'s Shared,
    opts: &FillOptions,
) -> Result<&'s Sums, SkipReason> {
    let base = Target {
        hole: plan.hole,
        ..*t
    };
    shared
        .sums
        .get_or_init(|| sums(&base, plan.region, &plan.pca, opts))
        .as_ref()
        .map_err(|&e| e)
}

/// Which of PCA's scoring models artificial hole `h` shares (see `groups`), and the holes
/// it is trained without. The Kalman smoother trains its models on the same rows as PCA,
/// so both are scored alike.
pub(super) fn scoring_group(
    t: &Target,
    plan: &Donors,
    shared: &Shared,
    opts: &FillOptions,
    h: (usize, usize),
) -> Result<(usize, Vec<(usize, usize)>), SkipReason> {
    Ok(group(plan, shared, plan_sums(t, plan, shared, opts)?, h))
}

/// Holes sharing a scoring model: consecutive ones while together they remove at most
/// `1 / SHARE` of the training rows (at least one hole per model). Fewer
/// eigen-decompositions, and every model still trains on nearly all the window.
fn groups(s: &Sums, holes: &[(usize, usize)]) -> Vec<usize> {
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
    group_of
}

/// `s` without the rows of frames inside `exclude` (artificial gaps): a downdate instead
/// of a second pass over the window.
pub(super) fn without(
    s: &Sums,
    t: &Target,
    nb: &[(usize, f64)],
    exclude: &[(usize, usize)],
) -> Sums {
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
