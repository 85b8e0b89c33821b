//! Kalman smoothing in a low-dimensional subspace, after Burke & Lasenby (2016, J. Biomech.
//! 49(9), "Estimation of missing marker positions using low dimensional Kalman
//! smoothing").
//!
//! The marker and its PCA neighbours (the PCA fill's, centred per frame on their centroid
//! and weighted alike) are described by a few principal component scores that move
//! smoothly in time: a constant-velocity model whose acceleration noise per component comes
//! from the scores' second differences over the training frames, and whose observation
//! noise is the variance the kept components leave (probabilistic PCA). A Kalman filter
//! and a Rauch–Tung–Striebel smoother estimate the scores frame by frame from whatever is
//! observed — the neighbours throughout, the marker outside the gap — and the marker is
//! read back from them. Unlike the per-frame PCA fill, the marker's own samples on both
//! sides and the continuity of the motion both inform the gap.

use std::cell::{OnceCell, RefCell};
use std::rc::Rc;

use nalgebra::DMatrix;

use super::anchor::Raw;
use super::data::{Span, Target};
use super::donors::Donors;
use super::options::FillOptions;
use super::outcome::SkipReason;
use super::subspace::{
    basis, centroid, neighbours_through, own_basis, plan_rows, row, rows_of, scoring_basis,
    scoring_group, sums, Basis, Rows, Shared, MIN_TRAIN,
};

/// Context frames on each side of the gap the smoother runs over: enough for the filter to
/// settle from its prior before it reaches the gap. On the corpus evaluation (quick run),
/// 20 frames changed no mean error by more than 0.03 mm at 1.2–1.6× the cost, 5 frames
/// were 0.5–3 % worse.
const CONTEXT: usize = 10;

/// The smoothed prediction over the span, with residuals at up to `per_side` frames per
/// side (see [`Raw`]).
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
    let (lo_o, hi_o) = span.outer();
    // The gap itself has a model trained on every row; `auto`'s artificial gaps in the
    // same marker share PCA's scoring models' rows (trained without a few holes at a
    // time); any other hole gets a model of its own.
    let scoring = match (t.hole, plan.hole) {
        (h, p) if h == p => None,
        (Some(h), None) if plan.exclude.get().is_some_and(|v| v.contains(&h)) => Some(Some(h)),
        _ => Some(None),
    };
    let model: Rc<Model> = match scoring {
        None => cache
            .model
            .get_or_init(|| {
                let b = own_basis(t, plan, shared, opts)?;
                Model::train(&b, plan_rows(t, plan, shared, opts)?, nb).map(Rc::new)
            })
            .clone()?,
        Some(Some(h)) => {
            let (g, _) = scoring_group(t, plan, shared, opts, h)?;
            let hit = cache
                .scoring
                .borrow()
                .iter()
                .find(|(k, _)| *k == g)
                .map(|(_, m)| Rc::clone(m));
            match hit {
                Some(m) => m,
                None => {
                    let (_, b) = scoring_basis(t, plan, shared, opts, h)?;
                    let rows = plan_rows(t, plan, shared, opts)?;
                    let m = Rc::new(Model::train(&b, rows, nb)?);
                    cache.scoring.borrow_mut().push((g, Rc::clone(&m)));
                    m
                }
            }
        }
        Some(None) => {
            let known = 3 * nb.len();
            let b = sums(t, plan.region, nb, opts).and_then(|s| basis(&s, known, opts))?;
            let data = rows_of(t, nb, &b.frames);
            let rows = Rows {
                frames: &b.frames,
                data: &data,
            };
            Rc::new(Model::train(&b, rows, nb)?)
        }
    };
    // The smoother's window: the context each side, within the run where every neighbour
    // is valid (the rows are centred on their centroid).
    let all_nb = |f: usize| nb.iter().all(|&(j, _)| d.ok(j, f));
    let mut lo = lo_o;
    while lo > 0 && lo_o - lo < CONTEXT && all_nb(lo - 1) {
        lo -= 1;
    }
    let mut hi = hi_o;
    while hi + 1 < d.frames && hi - hi_o < CONTEXT && all_nb(hi + 1) {
        hi += 1;
    }
    let z = model.smooth(t, nb, lo, hi)?;
    let k0 = model.known;
    let predict = |f: usize| {
        if f < lo || f > hi {
            return None;
        }
        let c = centroid(t, nb, f);
        let zf = &z[f - lo];
        Some([0, 1, 2].map(|k| {
            model.mean[k0 + k]
                + (0..model.r)
                    .map(|a| model.basis[(k0 + k, a)] * zf[a])
                    .sum::<f64>()
                + c[k]
        }))
    };
    Raw::gather(t, span, per_side, predict).ok_or(SkipReason::NoDonors)
}

/// One plan's smoother models, trained on first use: the gap's own, and per group of
/// `auto`'s artificial holes (PCA's groups, see `subspace::groups`) the one trained without
/// them.
#[derive(Debug, Clone, Default)]
pub(crate) struct Cache {
    model: OnceCell<Result<Rc<Model>, SkipReason>>,
    scoring: RefCell<Vec<(usize, Rc<Model>)>>,
}

/// The subspace and its dynamics.
#[derive(Debug, Clone)]
pub(crate) struct Model {
    /// Neighbour coordinates per row (the target's three follow).
    known: usize,
    mean: Vec<f64>,
    /// The kept components (`dims × r`).
    basis: DMatrix<f64>,
    r: usize,
    /// Process noise over [scores; velocities] (the transition adds each velocity to its
    /// score).
    process: DMatrix<f64>,
    /// The prior at a window's first frame: each component's score variance and that of
    /// its change from frame to frame.
    prior: DMatrix<f64>,
    /// Information one frame's observation adds to the scores (Hᵀ H / noise, `r × r`): the
    /// neighbours alone, and with the target.
    info_nb: DMatrix<f64>,
    info_all: DMatrix<f64>,
    /// Observation noise per coordinate.
    noise: f64,
    /// Filter and smoother gains per observation pattern (which frames of the window see
    /// the target). They do not depend on the data, and the gap and its artificial gaps
    /// mostly share one pattern, so they are worked out once.
    gains: RefCell<Vec<(Vec<bool>, Rc<Gains>)>>,
}

/// Per frame of a window: the predicted covariance P (`2r × 2r`), and M = (I + J P_zz)⁻¹
/// (`r × r`; J: the frame's information on the scores), column-major, frame after frame.
#[derive(Debug)]
struct Gains {
    predicted: Vec<f64>,
    m: Vec<f64>,
}

impl Gains {
    /// Frame `i`'s predicted covariance.
    #[inline(always)]
    fn predicted(&self, i: usize, n: usize) -> Block<'_> {
        Block::slice(&self.predicted[i * n * n..(i + 1) * n * n], n, n)
    }

    /// Frame `i`'s M.
    #[inline(always)]
    fn m(&self, i: usize, r: usize) -> Block<'_> {
        Block::slice(&self.m[i * r * r..(i + 1) * r * r], r, r)
    }
}

/// Calls `Self::f::<R>(args)` with `R` the component count `r` when it is one the models
/// commonly keep, else `Self::f::<0>` (read at run time).
macro_rules! by_size {
    ($r:expr, $f:ident, $($arg:expr),*) => {
        match $r {
            1 => Self::$f::<1>($($arg),*),
            2 => Self::$f::<2>($($arg),*),
            3 => Self::$f::<3>($($arg),*),
            4 => Self::$f::<4>($($arg),*),
            5 => Self::$f::<5>($($arg),*),
            6 => Self::$f::<6>($($arg),*),
            7 => Self::$f::<7>($($arg),*),
            8 => Self::$f::<8>($($arg),*),
            9 => Self::$f::<9>($($arg),*),
            10 => Self::$f::<10>($($arg),*),
            11 => Self::$f::<11>($($arg),*),
            12 => Self::$f::<12>($($arg),*),
            13 => Self::$f::<13>($($arg),*),
            14 => Self::$f::<14>($($arg),*),
            15 => Self::$f::<15>($($arg),*),
            16 => Self::$f::<16>($($arg),*),
            _ => Self::$f::<0>($($arg),*),
        }
    };
}
impl Model {
    /// The model of the components `b`, whose training rows are among `rows` (see
    /// [`Rows`]).
    fn train(b: &Basis, rows: Rows, nb: &[(usize, f64)]) -> Result<Model, SkipReason> {
        crate::profile::count(crate::profile::Count::KalmanModel);
        let known = 3 * nb.len();
        let dims = known + 3;
        let frames = &b.frames;
        // The components PCA keeps on the same rows (see `Basis`): those that explain
        // `pca_variance`, no more than the neighbours determine. Fewer (99 or 99.5 %) were
        // worse at every gap length on the corpus evaluation.
        let (vals, total, r) = (&b.values, b.total, b.vectors.ncols());
        // The variance left in the free directions, spread evenly (probabilistic PCA's
        // maximum-likelihood noise); a floor keeps the update well posed on clean data.
        let free = dims - 3;
        let left: f64 = vals[r.min(free)..free].iter().map(|v| v.max(0.0)).sum();
        let noise = (left / (free - r).max(1) as f64).max(1e-9 * total);
        let basis = b.vectors.clone();
        let mean = b.mean.clone();

        // Scores at the training frames, and their first and second differences where the
        // neighbouring frames trained too.
        let ((v1, n1), (v2, n2)) = by_size!(
            r,
            differences,
            frames,
            rows,
            &mean,
            basis.as_slice(),
            dims,
            r
        )?;
        if n2 < MIN_TRAIN {
            return Err(SkipReason::NoContext);
        }
        let floor = 1e-12 * total;
        // Under the constant-velocity model with white acceleration `q` per frame, second
        // differences have variance q / 2 plus 6 × the observation noise; at least a tenth
        // of what was seen is kept as motion should the noise estimate be too large.
        let n = 2 * r;
        let mut process = DMatrix::<f64>::zeros(n, n);
        let mut prior = DMatrix::<f64>::zeros(n, n);
        for a in 0..r {
            let seen = v2[a] / n2 as f64;
            let q = 2.0 * (seen - 6.0 * noise).max(0.1 * seen).max(floor);
            process[(a, a)] = 0.25 * q;
            process[(a, r + a)] = 0.5 * q;
            process[(r + a, a)] = 0.5 * q;
            process[(r + a, r + a)] = q;
            prior[(a, a)] = vals[a].max(floor);
            prior[(r + a, r + a)] = (v1[a] / n1 as f64).max(floor);
        }
        let info = |rows: usize| {
            let mut m = DMatrix::<f64>::zeros(r, r);
            for a in 0..r {
                for b in 0..r {
                    m[(a, b)] = (0..rows)
                        .map(|i| basis[(i, a)] * basis[(i, b)])
                        .sum::<f64>()
                        / noise;
                }
            }
            m
        };
        let (info_nb, info_all) = (info(known), info(dims));
        Ok(Model {
            known,
            mean,
            basis,
            r,
            process,
            prior,
            info_nb,
            info_all,
            noise,
            gains: RefCell::new(Vec::new()),
        })
    }

    /// Per component, the sums of the squared first and second differences of the scores
    /// over the training `frames` (each frame's row from `rows`, less `mean`, on `basis`:
    /// `dims × r`, column-major) where the frames before it trained too, and how many of
    /// each. Compiled per component count, as [`Model::recursion`]; each score is summed in
    /// the order [`project`] sums it, so the bits are the same.
    #[allow(clippy::type_complexity)]
    fn differences<const R: usize>(
        frames: &[usize],
        rows: Rows,
        mean: &[f64],
        basis: &[f64],
        dims: usize,
        r: usize,
    ) -> Result<((Vec<f64>, usize), (Vec<f64>, usize)), SkipReason> {
        let r = if R == 0 { r } else { R };
        // The basis by rows (`dims × r`, row-major), so that a row's share of every score
        // is one short contiguous run.
        let by_rows: Vec<f64> = (0..dims)
            .flat_map(|i| (0..r).map(move |a| basis[i + a * dims]))
            .collect();
        let mut buf = vec![0.0; dims];
        let (mut z, mut pz, mut ppz) = (vec![0.0; r], vec![0.0; r], vec![0.0; r]);
        let (mut pf, mut ppf): (Option<usize>, Option<usize>) = (None, None);
        let (mut v1, mut n1) = (vec![0.0; r], 0usize);
        let (mut v2, mut n2) = (vec![0.0; r], 0usize);
        let mut at = 0;
        for &f in frames {
            // The model's frames are in `rows.frames`, in order.
            at += rows.frames[at..]
                .iter()
                .position(|&g| g == f)
                .ok_or(SkipReason::NoContext)?;
            let x = &rows.data[at * dims..(at + 1) * dims];
            for ((v, &xv), m) in buf.iter_mut().zip(x).zip(mean) {
                *v = xv - m;
            }
            let zr = &mut z[..r];
            zr.fill(-0.0);
            for (&xi, bi) in buf.iter().zip(by_rows.chunks_exact(r)) {
                let bi = &bi[..r];
                for a in 0..r {
                    zr[a] += bi[a] * xi;
                }
            }
            if let Some(p) = pf {
                if p + 1 == f {
                    let (zr, pzr) = (&z[..r], &pz[..r]);
                    for a in 0..r {
                        v1[a] += (zr[a] - pzr[a]).powi(2);
                    }
                    n1 += 1;
                    if let Some(pp) = ppf {
                        if pp + 2 == f {
                            let ppzr = &ppz[..r];
                            for a in 0..r {
                                v2[a] += (zr[a] - 2.0 * pzr[a] + ppzr[a]).powi(2);
                            }
                            n2 += 1;
                        }
                    }
                }
            }
            std::mem::swap(&mut ppz, &mut pz);
            std::mem::swap(&mut pz, &mut z);
            (ppf, pf) = (pf, Some(f));
        }
        Ok(((v1, n1), (v2, n2)))
    }

    /// The covariances for a window whose frames see the target where `seen` is true: the
    /// filter's covariance recursion, kept per frame.
    fn gains(&self, seen: &[bool]) -> Result<Rc<Gains>, SkipReason> {
        if let Some((_, g)) = self.gains.borrow().iter().find(|(s, _)| s == seen) {
            return Ok(Rc::clone(g));
        }
        let g = Rc::new(by_size!(self.r, recursion, self, seen)?);
        self.gains.borrow_mut().push((seen.to_vec(), Rc::clone(&g)));
        Ok(g)
    }

    /// The covariance recursion of [`Model::gains`], for `R` components known when
    /// compiled (0: `self.r`, read at run time). The same operations in the same order
    /// for every `R`, so the gains are the same to the bit; a known `R` lets the compiler
    /// unroll the small loops and drop their bounds checks, which cost more than the
    /// arithmetic at the few components the models keep (2–11 on 03_rolling, 3–16 on
    /// Facial-Sing).
    fn recursion<const R: usize>(&self, seen: &[bool]) -> Result<Gains, SkipReason> {
        let r = if R == 0 { self.r } else { R };
        let n = 2 * r;
        let len = seen.len();
        let mut g = Gains {
            predicted: Vec::with_capacity(len * n * n),
            m: Vec::with_capacity(len * r * r),
        };
        let mut p = self.prior.as_slice().to_vec();
        // Scratch, reused frame to frame: I + J P_zz and M, S = M J, W = S P_z·, P⁺.
        let (mut jp, mut m) = (vec![0.0; r * r], vec![0.0; r * r]);
        let (mut sm, mut w, mut post) = (vec![0.0; r * r], vec![0.0; r * n], vec![0.0; n * n]);
        for (i, &s) in seen.iter().enumerate() {
            if i > 0 {
                predict(&mut p, self.process.as_slice(), r);
            }
            // The observation informs the scores only (J, r × r), so the update needs an
            // r × r inverse (Woodbury): with M = (I + J P_zz)⁻¹, P⁺ = P − P_·z M J P_z·.
            let j = Block::slice(self.info(s).as_slice(), r, r);
            mat_mul(j, Block::of(&p, n, r, r), &mut jp);
            for a in 0..r {
                jp[a + a * r] += 1.0;
            }
            if !invert(&mut jp, r, &mut m) {
                return Err(SkipReason::Degenerate);
            }
            mat_mul(Block::slice(&m, r, r), j, &mut sm);
            mat_mul(Block::slice(&sm, r, r), Block::of(&p, n, r, n), &mut w);
            g.predicted.extend_from_slice(&p);
            g.m.extend_from_slice(&m);
            // P⁺ = P − P_·z W, symmetric: the lower triangle, mirrored (P_·z's rows are P's
            // first columns, as P is symmetric).
            for c in 0..n {
                for k in c..n {
                    post[k + c * n] =
                        p[k + c * n] - dot(&p[k * n..k * n + r], &w[c * r..(c + 1) * r]);
                }
            }
            for c in 0..n {
                for k in c..n {
                    let v = post[k + c * n];
                    p[k + c * n] = v;
                    p[c + k * n] = v;
                }
            }
        }
        Ok(g)
    }

    /// The information a frame adds to the scores, with or without the target seen.
    fn info(&self, seen: bool) -> &DMatrix<f64> {
        if seen {
            &self.info_all
        } else {
            &self.info_nb
        }
    }

    /// Smoothed scores for frames `lo..=hi` (every neighbour valid there): a Kalman filter
    /// forwards, then the modified Bryson–Frazier smoother backwards, which needs no
    /// inverse of the predicted covariances (Rauch–Tung–Striebel would need one per frame;
    /// both give the same estimates).
    fn smooth(
        &self,
        t: &Target,
        nb: &[(usize, f64)],
        lo: usize,
        hi: usize,
    ) -> Result<Vec<Vec<f64>>, SkipReason> {
        let seen: Vec<bool> = (lo..=hi).map(|f| t.ok(f)).collect();
        let g = self.gains(&seen)?;
        Ok(by_size!(self.r, passes, self, t, nb, lo, &seen, &g))
    }

    /// The filter's and smoother's passes of [`Model::smooth`] over the gains, for `R`
    /// components known when compiled (0: at run time), as [`Model::recursion`].
    fn passes<const R: usize>(
        &self,
        t: &Target,
        nb: &[(usize, f64)],
        lo: usize,
        seen: &[bool],
        g: &Gains,
    ) -> Vec<Vec<f64>> {
        let r = if R == 0 { self.r } else { R };
        let known = self.known;
        let n = 2 * r;
        let dims = known + 3;
        let len = seen.len();
        let mut x = vec![0.0; n];
        // Per frame the predicted state and M (h − J x_z), the scaled innovation (h: the
        // observation's information vector on the scores), in rows of `n` and `r`.
        let mut pred: Vec<f64> = Vec::with_capacity(len * n);
        let mut innov: Vec<f64> = Vec::with_capacity(len * r);
        let mut buf = vec![0.0; dims];
        let (mut h, mut v, mut u, mut y) = (vec![0.0; r], vec![0.0; r], vec![0.0; r], vec![0.0; n]);
        for (i, &s) in seen.iter().enumerate() {
            if i > 0 {
                for a in 0..r {
                    x[a] += x[r + a];
                }
            }
            let rows = if s { dims } else { known };
            row(t, nb, lo + i, &mut buf);
            for (b, m) in buf[..rows].iter_mut().zip(&self.mean) {
                *b -= m;
            }
            project(self.basis.as_slice(), dims, &buf[..rows], &mut h);
            for ha in h.iter_mut() {
                *ha /= self.noise;
            }
            mat_vec(Block::slice(self.info(s).as_slice(), r, r), &x[..r], &mut v);
            for (va, ha) in v.iter_mut().zip(&h) {
                *va = ha - *va;
            }
            mat_vec(g.m(i, r), &v, &mut u);
            pred.extend_from_slice(&x);
            mat_vec(g.predicted(i, n).cols(r), &u, &mut y);
            for (xk, yk) in x.iter_mut().zip(&y) {
                *xk += yk;
            }
            innov.extend_from_slice(&u);
        }
        // λ̃ = λ − [u + J Mᵀ P_z· λ; 0], x̂ = x⁻ − P λ̃, then λ ← Fᵀ λ̃.
        let mut out = vec![Vec::new(); len];
        let mut lam = vec![0.0; n];
        let (mut t1, mut t2, mut back) = (vec![0.0; r], vec![0.0; r], vec![0.0; r]);
        for i in (0..len).rev() {
            let p = g.predicted(i, n).rows(r);
            mat_vec(p, &lam, &mut t1);
            mat_t_vec(g.m(i, r), &t1, &mut t2);
            mat_vec(
                Block::slice(self.info(seen[i]).as_slice(), r, r),
                &t2,
                &mut back,
            );
            for a in 0..r {
                lam[a] -= innov[i * r + a] + back[a];
            }
            mat_vec(p, &lam, &mut t1);
            out[i] = (0..r).map(|a| pred[i * n + a] - t1[a]).collect();
            for a in 0..r {
                lam[r + a] += lam[a];
            }
        }
        out
    }
}

/// `P ← F P Fᵀ + Q` in place, for the transition F = [[I, I], [0, I]] (blocks of `r`): the
/// velocity rows added to the score rows, then the velocity columns to the score columns,
/// without a general product.
#[inline(always)]
fn predict(p: &mut [f64], process: &[f64], r: usize) {
    let n = 2 * r;
    for c in 0..n {
        for a in 0..r {
            p[a + c * n] += p[r + a + c * n];
        }
    }
    for a in 0..r {
        for k in 0..n {
            p[k + a * n] += p[k + (r + a) * n];
        }
    }
    for (v, q) in p.iter_mut().zip(process) {
        *v += q;
    }
}

/// `out = A⁻¹` for the `r × r` matrix `a` (column-major, overwritten) by Gauss–Jordan
/// elimination with partial pivoting; false if `a` is singular.
#[inline(always)]
fn invert(a: &mut [f64], r: usize, out: &mut [f64]) -> bool {
    out.fill(0.0);
    for k in 0..r {
        out[k + k * r] = 1.0;
    }
    for k in 0..r {
        let Some(piv) = (k..r).max_by(|&x, &y| a[x + k * r].abs().total_cmp(&a[y + k * r].abs()))
        else {
            return false;
        };
        let d = a[piv + k * r];
        if d == 0.0 || !d.is_finite() {
            return false;
        }
        if piv != k {
            for c in 0..r {
                a.swap(k + c * r, piv + c * r);
                out.swap(k + c * r, piv + c * r);
            }
        }
        for c in 0..r {
            a[k + c * r] /= d;
            out[k + c * r] /= d;
        }
        for i in 0..r {
            let f = a[i + k * r];
            if i == k || f == 0.0 {
                continue;
            }
            for c in 0..r {
                a[i + c * r] -= f * a[k + c * r];
                out[i + c * r] -= f * out[k + c * r];
            }
        }
    }
    true
}

/// `z_a = Σ_i basis_ia x_i` for each of `z`'s components (`basis` column-major with
/// `stride` rows, `x` its first rows), every sum taken in order from −0 as [`dot`] (and
/// `Iterator::sum`) takes it, so the scores are those of a dot product per component to
/// the bit; the components' sums advance together, which keeps several additions in
/// flight instead of waiting on one chain at a time.
#[inline(always)]
fn project(basis: &[f64], stride: usize, x: &[f64], z: &mut [f64]) {
    z.fill(-0.0);
    for (i, &xi) in x.iter().enumerate() {
        for (a, za) in z.iter_mut().enumerate() {
            *za += basis[i + a * stride] * xi;
        }
    }
}

/// `Σ a_i b_i`, summed in order.
#[inline(always)]
fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// A column-major block at the top left of a matrix: `rows × cols` of a matrix with
/// `stride` rows. The recursion's matrices are a few dozen wide at most, where nalgebra's
/// products cost more in temporaries and packing than in arithmetic.
#[derive(Clone, Copy)]
struct Block<'a> {
    data: &'a [f64],
    rows: usize,
    cols: usize,
    stride: usize,
}

impl<'a> Block<'a> {
    /// A whole `rows × cols` matrix stored in `data`.
    #[inline(always)]
    fn slice(data: &'a [f64], rows: usize, cols: usize) -> Block<'a> {
        Block {
            data,
            rows,
            cols,
            stride: rows,
        }
    }

    /// The top-left `rows × cols` of a matrix of `stride` rows stored in `data`.
    #[inline(always)]
    fn of(data: &'a [f64], stride: usize, rows: usize, cols: usize) -> Block<'a> {
        Block {
            data,
            rows,
            cols,
            stride,
        }
    }

    /// The first `rows` rows.
    #[inline(always)]
    fn rows(self, rows: usize) -> Block<'a> {
        Block { rows, ..self }
    }

    /// The first `cols` columns.
    #[inline(always)]
    fn cols(self, cols: usize) -> Block<'a> {
        Block { cols, ..self }
    }

    #[inline(always)]
    fn col(&self, c: usize) -> &'a [f64] {
        &self.data[c * self.stride..c * self.stride + self.rows]
    }
}

/// `y = A x`, each row summed over the columns in order, as nalgebra's product of a
/// matrix and a vector sums (so the smoother's estimates are those of the products it
/// replaces, bit for bit), into `y` instead of a new vector.
#[inline(always)]
fn mat_vec(a: Block, x: &[f64], y: &mut [f64]) {
    let y = &mut y[..a.rows];
    for (c, &xc) in x.iter().enumerate().take(a.cols) {
        let col = a.col(c);
        if c == 0 {
            for (yi, v) in y.iter_mut().zip(col) {
                *yi = v * xc;
            }
        } else {
            for (yi, v) in y.iter_mut().zip(col) {
                *yi += v * xc;
            }
        }
    }
}

/// `y = Aᵀ x`: each entry the column's dot product with `x`, in order (as nalgebra's
/// product of the transposed copy and a vector sums).
#[inline(always)]
fn mat_t_vec(a: Block, x: &[f64], y: &mut [f64]) {
    for (c, yc) in y.iter_mut().enumerate().take(a.cols) {
        *yc = dot(a.col(c), x);
    }
}

/// `out = A B` (`out` with `A`'s rows), column by column, each a [`mat_vec`].
#[inline(always)]
fn mat_mul(a: Block, b: Block, out: &mut [f64]) {
    let rows = a.rows;
    for c in 0..b.cols {
        mat_vec(a, b.col(c), &mut out[c * rows..(c + 1) * rows]);
    }
}

#[cfg(test)]
mod tests {
    use super::super::data::Data;
    use super::super::method::FillMethod;
    use super::super::plan::Plan;
    use super::super::rigid::tests::rigid_cluster;
    use super::super::step::max_steps;
    use super::super::test_util::*;
    use super::*;
    use nalgebra::DVector;

    /// The textbook Rauch–Tung–Striebel smoother with explicit inverses, as a reference for
    /// the Bryson–Frazier pass `smooth` uses.
    fn rts(m: &Model, t: &Target, nb: &[(usize, f64)], lo: usize, hi: usize) -> Vec<Vec<f64>> {
        let (r, dims) = (m.r, m.known + 3);
        let n = 2 * r;
        let mut f = DMatrix::<f64>::identity(n, n);
        for a in 0..r {
            f[(a, r + a)] = 1.0;
        }
        let mut x = DVector::<f64>::zeros(n);
        let mut p = m.prior.clone();
        let (mut pred, mut filt) = (Vec::new(), Vec::new());
        let mut buf = vec![0.0; dims];
        for fr in lo..=hi {
            if fr > lo {
                x = &f * &x;
                p = &f * &p * f.transpose() + &m.process;
            }
            pred.push((x.clone(), p.clone()));
            let seen = t.ok(fr);
            let rows = if seen { dims } else { m.known };
            row(t, nb, fr, &mut buf);
            let mut info = DMatrix::<f64>::zeros(n, n);
            info.view_mut((0, 0), (r, r)).copy_from(m.info(seen));
            let mut h = DVector::<f64>::zeros(n);
            for a in 0..r {
                h[a] = (0..rows)
                    .map(|k| m.basis[(k, a)] * (buf[k] - m.mean[k]))
                    .sum::<f64>()
                    / m.noise;
            }
            let p_inv = p.clone().try_inverse().unwrap();
            p = (&p_inv + info).try_inverse().unwrap();
            x = &p * (&p_inv * &x + h);
            filt.push((x.clone(), p.clone()));
        }
        let len = filt.len();
        let mut out = vec![Vec::new(); len];
        let mut xs = filt[len - 1].0.clone();
        out[len - 1] = xs.rows(0, r).iter().copied().collect();
        for i in (0..len - 1).rev() {
            let gain = &filt[i].1 * f.transpose() * pred[i + 1].1.clone().try_inverse().unwrap();
            xs = &filt[i].0 + gain * (&xs - &pred[i + 1].0);
            out[i] = xs.rows(0, r).iter().copied().collect();
        }
        out
    }

    /// The training scores' differences from the plan's rows, compiled per component count
    /// or not, equal those worked out frame by frame from each frame's row (the training
    /// before the rows were shared), bit for bit, for the gap's own model and for a group
    /// of `auto`'s holes.
    #[test]
    fn differences_from_the_plan_rows_equal_frame_by_frame() {
        let trial = crate::synth::gait_like(24, 8, 800, 100.0, 0.3, 7);
        let mut valid = trial.valid.clone();
        valid[0][400..450].fill(false);
        let steps = max_steps(&trial.xyz, &valid);
        let data = Data::new(&trial.xyz, &valid, &steps);
        let t = Target {
            m: 0,
            data,
            hole: None,
        };
        let opts = FillOptions::default();
        let plan = Plan::build(&t, Span::new(400, 449, 800), &opts);
        plan.exclude.set(vec![(200, 239), (600, 639)]).unwrap();
        let (nb, shared) = (&plan.pca, &plan.subspace);
        let dims = 3 * nb.len() + 3;
        let rows = plan_rows(&t, &plan, shared, &opts).unwrap();
        let own = own_basis(&t, &plan, shared, &opts).unwrap();
        let (_, holes) = scoring_basis(&t, &plan, shared, &opts, (200, 239)).unwrap();
        assert!(holes.frames.len() + 80 <= own.frames.len());
        for b in [own, holes] {
            let r = b.vectors.ncols();
            let (mut v1, mut n1, mut v2, mut n2) = (vec![0.0; r], 0, vec![0.0; r], 0);
            let mut buf = vec![0.0; dims];
            let mut seen: Vec<(usize, Vec<f64>)> = Vec::new();
            for &f in &b.frames {
                row(&t, nb, f, &mut buf);
                buf.iter_mut().zip(&b.mean).for_each(|(v, m)| *v -= m);
                let mut z = vec![0.0; r];
                project(b.vectors.as_slice(), dims, &buf, &mut z);
                let k = seen.len();
                if k >= 1 && seen[k - 1].0 + 1 == f {
                    let pz = &seen[k - 1].1;
                    (0..r).for_each(|a| v1[a] += (z[a] - pz[a]).powi(2));
                    n1 += 1;
                    if k >= 2 && seen[k - 2].0 + 2 == f {
                        let ppz = &seen[k - 2].1;
                        (0..r).for_each(|a| v2[a] += (z[a] - 2.0 * pz[a] + ppz[a]).powi(2));
                        n2 += 1;
                    }
                }
                seen.push((f, z));
            }
            let want = ((v1, n1), (v2, n2));
            let (frames, mean, basis) = (&b.frames, &b.mean, b.vectors.as_slice());
            macro_rules! compiled {
                ($($k:literal),*) => {
                    match r {
                        $($k => Model::differences::<$k>(frames, rows, mean, basis, dims, r),)*
                        _ => panic!("{r} components"),
                    }
                };
            }
            let fixed = compiled!(1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15, 16).unwrap();
            let run_time = Model::differences::<0>(frames, rows, mean, basis, dims, r).unwrap();
            assert!(n1 > 100 && n2 > 100, "{n1} {n2}");
            assert_eq!(fixed, want);
            assert_eq!(run_time, want);
        }
    }

    #[test]
    fn smoother_matches_rauch_tung_striebel() {
        // The rigid cluster with 0.5 mm of deterministic jitter, so the model keeps
        // several components and some observation noise.
        let mut xyz = rigid_cluster(300);
        for (m, tr) in xyz.iter_mut().enumerate() {
            for (f, p) in tr.iter_mut().enumerate() {
                for (k, c) in p.iter_mut().enumerate() {
                    *c += 0.5 * (((m * 31 + f * 17 + k * 7) % 11) as f64 / 10.0 - 0.5);
                }
            }
        }
        let (xyz, valid) = with_gap(xyz, 120, 159);
        let steps = max_steps(&xyz, &valid);
        let data = Data::new(&xyz, &valid, &steps);
        let t = Target {
            m: 0,
            data,
            hole: None,
        };
        let span = Span::new(120, 159, data.frames);
        let opts = FillOptions::default();
        let plan = Plan::build(&t, span, &opts);
        let b = own_basis(&t, &plan, &plan.subspace, &opts).unwrap();
        let rows = plan_rows(&t, &plan, &plan.subspace, &opts).unwrap();
        let model = Model::train(&b, rows, &plan.pca).unwrap();
        assert!(model.r >= 3, "components kept: {}", model.r);
        let got = model.smooth(&t, &plan.pca, 100, 179).unwrap();
        let want = rts(&model, &t, &plan.pca, 100, 179);
        let scale = want.iter().flatten().fold(0.0f64, |a, v| a.max(v.abs()));
        for (g, w) in got.iter().zip(&want) {
            for (a, b) in g.iter().zip(w) {
                assert!((a - b).abs() <= 1e-7 * scale, "{a} vs {b} (scale {scale})");
            }
        }
    }

    #[test]
    fn kalman_reconstructs_rigid_cluster() {
        let truth = rigid_cluster(400);
        let (xyz, valid) = with_gap(truth.clone(), 150, 209);
        let v = fill(&xyz, &valid, 150, 209, FillMethod::Kalman).unwrap();
        let e = max_err(&v, |f| truth[0][f], 150);
        assert!(e < 2.0, "kalman max error {e}");
        let s = fill(&xyz, &valid, 150, 209, FillMethod::Spline).unwrap();
        assert!(max_err(&s, |f| truth[0][f], 150) > 10.0 * e.max(0.1));
        // At the trial's start the smoother runs from the gap's first frame.
        let (xyz, valid) = with_gap(truth.clone(), 0, 29);
        let v = fill(&xyz, &valid, 0, 29, FillMethod::Kalman).unwrap();
        let e = max_err(&v, |f| truth[0][f], 0);
        assert!(e < 2.0, "kalman max error at the start {e}");
    }
}
