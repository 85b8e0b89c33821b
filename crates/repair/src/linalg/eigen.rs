//! Every eigenvalue of a symmetric matrix, and the eigenvectors of only the leading ones.
//!
//! Principal components keep a few leading components, chosen from all the eigenvalues
//! (a share of their sum). nalgebra's `SymmetricEigen` accumulates every eigenvector through
//! its implicit QR sweeps, about 9n³ operations for an n × n matrix, where the eigenvalues
//! alone cost the tridiagonal reduction's 4n³/3 and k eigenvectors another 2n²k. So the
//! matrix is reduced to tridiagonal form by Householder reflections (kept, as LAPACK keeps
//! them), the tridiagonal's eigenvalues found by implicit QL without vectors, and each
//! requested eigenvector by inverse iteration on the tridiagonal, made orthogonal to the
//! others of its cluster (LAPACK's `dstein` rule: eigenvalues within 10⁻³ of the block's
//! norm), then carried back through the reflections.
//!
//! The eigenvectors' signs are left as they come (callers that need a sign choose it); within
//! a repeated eigenvalue the basis is any orthonormal one, as with any decomposition.

use nalgebra::DMatrix;

/// Sweeps of implicit QL allowed per eigenvalue before the decomposition falls back to
/// nalgebra's (LAPACK allows 30 per eigenvalue; none of the corpora's matrices came near).
const MAX_SWEEPS: usize = 60;
/// Inverse-iteration steps per eigenvector. From an accurate eigenvalue one step reaches
/// the eigenvector to rounding unless the start vector happens to lack it (by a share of
/// the order of rounding); a second leaves no such chance. Three moved no fill of the
/// held-apart evaluation by a millionth (`docs/price.md`, price11) and cost a third more.
const STEPS: usize = 2;
/// Eigenvalues closer than this share of their block's norm form a cluster whose vectors
/// are orthogonalised against each other (LAPACK's `dstein`).
const CLUSTER: f64 = 1e-3;

/// The decomposition of a symmetric matrix: all eigenvalues, eigenvectors on request.
pub(crate) struct Leading {
    n: usize,
    values: Vec<f64>,
    kind: Kind,
}

enum Kind {
    /// The reduction: the reflectors (column i holds vᵢ below row i + 1, its first entry 1
    /// implied), their factors, the tridiagonal, and each value's unreduced block.
    Tridiagonal {
        reflectors: Vec<f64>,
        tau: Vec<f64>,
        diag: Vec<f64>,
        off: Vec<f64>,
        blocks: Vec<(usize, usize)>,
    },
    /// nalgebra's full decomposition, where the QL did not converge (never seen; kept so
    /// that a pathological matrix still gets an answer).
    Full(DMatrix<f64>),
}

impl Leading {
    /// The eigenvalues of the symmetric `n` × `n` matrix `a` (either order: it is
    /// symmetric, and only its lower triangle, column-major, is read).
    pub(crate) fn new(a: &[f64], n: usize) -> Leading {
        let [one] = Self::many([(a, n)]);
        one
    }

    /// [`Leading::new`] of two matrices at once: the same decompositions, their QL
    /// iterations run side by side (see [`run_together`]).
    pub(crate) fn pair(a: &[f64], na: usize, b: &[f64], nb: usize) -> (Leading, Leading) {
        let [x, y] = Self::many([(a, na), (b, nb)]);
        (x, y)
    }

    fn many<const K: usize>(mats: [(&[f64], usize); K]) -> [Leading; K] {
        let reduced = mats.map(|(a, n)| tridiagonalise(a, n));
        let values = tridiagonal_values(reduced.each_ref().map(|(_, _, d, e)| (&d[..], &e[..])));
        let mut values = values.into_iter();
        let mut i = 0;
        reduced.map(|(reflectors, tau, diag, off)| {
            let (a, n) = mats[i];
            i += 1;
            match values.next().flatten() {
                Some((values, blocks)) => Leading {
                    n,
                    values,
                    kind: Kind::Tridiagonal {
                        reflectors,
                        tau,
                        diag,
                        off,
                        blocks,
                    },
                },
                None => Self::full(a, n),
            }
        })
    }

    fn full(a: &[f64], n: usize) -> Leading {
        let (values, vecs) = symmetric_eigen(a, n);
        Leading {
            n,
            values,
            kind: Kind::Full(vecs),
        }
    }

    /// The eigenvalues, descending.
    pub(crate) fn values(&self) -> &[f64] {
        &self.values
    }

    /// The eigenvectors of the `k` largest eigenvalues (at most n), as the columns of an
    /// n × k matrix, in the order of [`Leading::values`].
    pub(crate) fn vectors(&self, k: usize) -> DMatrix<f64> {
        let (n, k) = (self.n, k.min(self.n));
        let (reflectors, tau, diag, off, blocks) = match &self.kind {
            Kind::Full(v) => return v.columns(0, k).into_owned(),
            Kind::Tridiagonal {
                reflectors,
                tau,
                diag,
                off,
                blocks,
            } => (reflectors, tau, diag, off, blocks),
        };
        let mut z = DMatrix::<f64>::zeros(n, k);
        // Vectors already made in each block, and the last one's (perturbed) eigenvalue and
        // the first of its cluster.
        let mut last: Vec<Option<(usize, f64, usize)>> = vec![None; n];
        let mut rng = crate::rng::SplitMix64::new(0x5eed);
        let mut lu = Lu::default();
        let mut x = Vec::with_capacity(n);
        for j in 0..k {
            let (b0, b1) = blocks[j];
            let norm = block_norm(&diag[b0..b1], &off[b0..b1 - 1]);
            let mut lambda = self.values[j];
            let mut cluster_start = j;
            if let Some((_, prev, start)) = last[b0] {
                if (prev - lambda).abs() < CLUSTER * norm {
                    cluster_start = start;
                }
                // Distinct shifts, so that each solve is its own (LAPACK's perturbation).
                let pert = 10.0 * f64::EPSILON * lambda.abs().max(norm * f64::EPSILON);
                if prev - lambda < pert {
                    lambda = prev - pert;
                }
            }
            let count = last[b0].map_or(0, |(c, _, _)| c + 1);
            last[b0] = Some((count, lambda, cluster_start));
            let m = b1 - b0;
            x.clear();
            x.resize(m, 0.0);
            if norm == 0.0 || m == 1 {
                // A zero block (or a 1 × 1 one): any orthonormal basis of it.
                x[count.min(m - 1)] = 1.0;
            } else {
                lu.factor(&diag[b0..b1], &off[b0..b1 - 1], lambda, norm);
                x.iter_mut().for_each(|v| *v = rng.uniform() - 0.5);
                for _ in 0..STEPS {
                    lu.solve(&mut x);
                    // Only vectors of this block are in its cluster.
                    let cluster = (cluster_start..j).filter(|&p| blocks[p] == (b0, b1));
                    for p in cluster {
                        let q = &z.as_slice()[p * n + b0..p * n + b1];
                        let dot: f64 = q.iter().zip(&x).map(|(a, b)| a * b).sum();
                        x.iter_mut().zip(q).for_each(|(v, a)| *v -= dot * a);
                    }
                    let s = x.iter().map(|v| v * v).sum::<f64>().sqrt();
                    if !(s.is_finite() && s > 0.0) {
                        return full_vectors(reflectors, tau, diag, off, k);
                    }
                    x.iter_mut().for_each(|v| *v /= s);
                }
            }
            z.column_mut(j).as_mut_slice()[b0..b1].copy_from_slice(&x);
        }
        back_transform(reflectors, tau, n, &mut z);
        z
    }
}

/// The fallback's vectors (where an inverse iteration did not give a finite vector): the
/// tridiagonal decomposed whole by nalgebra, its leading `k` vectors carried back.
fn full_vectors(
    reflectors: &[f64],
    tau: &[f64],
    diag: &[f64],
    off: &[f64],
    k: usize,
) -> DMatrix<f64> {
    let n = diag.len();
    let mut t = DMatrix::<f64>::zeros(n, n);
    for i in 0..n {
        t[(i, i)] = diag[i];
        if i + 1 < n {
            t[(i + 1, i)] = off[i];
            t[(i, i + 1)] = off[i];
        }
    }
    let (_, v) = symmetric_eigen(t.as_slice(), n);
    let mut z = v.columns(0, k).into_owned();
    back_transform(reflectors, tau, n, &mut z);
    z
}

/// Householder reduction of the symmetric `a` (lower triangle, column-major) to the
/// tridiagonal QᵀAQ, Q = H₀H₁…: the reflectors, their factors τ, the diagonal and the
/// subdiagonal (LAPACK's `dsytd2`, lower).
///
/// Each step's rank-2 update of the trailing block and the next step's product of that
/// block with its reflector read the block in one pass, column by column (the next
/// reflector comes from the first column, updated first): the reduction is bound by memory
/// traffic, not arithmetic, at these sizes.
fn tridiagonalise(a: &[f64], n: usize) -> (Vec<f64>, Vec<f64>, Vec<f64>, Vec<f64>) {
    let mut w = a[..n * n].to_vec();
    let mut tau = vec![0.0; n.saturating_sub(1)];
    let mut diag = vec![0.0; n];
    let mut off = vec![0.0; n.saturating_sub(1)];
    if n >= 3 {
        let (mut v, mut p) = (vec![0.0; n], vec![0.0; n]);
        let (mut v_next, mut p_next) = (vec![0.0; n], vec![0.0; n]);
        let (mut t, mut beta) = reflector(&mut w, n, 0, &mut v);
        // The first step's product; later ones are made during the previous update.
        let m0 = n - 1;
        for c in 0..m0 {
            let start = (1 + c) * (n + 1);
            symv_column(&w[start..start + (m0 - c)], &v[..m0], c, &mut p[..m0]);
        }
        for i in 0..n - 2 {
            let m = n - i - 1;
            diag[i] = w[i + i * n];
            tau[i] = t;
            off[i] = beta;
            let (vi, pi) = (&v[..m], &mut p[..m]);
            // p = τ A₂₂ v − (τ²/2)(vᵀ A₂₂ v) v, so that A₂₂ − v pᵀ − p vᵀ = H A₂₂ H.
            pi.iter_mut().for_each(|x| *x *= t);
            let half = -0.5 * t * dot(pi, vi);
            pi.iter_mut()
                .zip(vi.iter())
                .for_each(|(x, &vv)| *x += half * vv);
            let base = (i + 1) * (n + 1);
            let has_next = i + 3 < n;
            for c in 0..m {
                let (vc, pc) = (vi[c], pi[c]);
                let start = base + c * (n + 1);
                let colc = &mut w[start..start + (m - c)];
                for ((x, &vr), &pr) in colc.iter_mut().zip(&vi[c..]).zip(&pi[c..]) {
                    *x -= vr * pc + pr * vc;
                }
                if !has_next {
                    continue;
                }
                if c == 0 {
                    (t, beta) = reflector(&mut w, n, i + 1, &mut v_next);
                    p_next[..m - 1].fill(0.0);
                } else {
                    let col = &w[start..start + (m - c)];
                    symv_column(col, &v_next[..m - 1], c - 1, &mut p_next[..m - 1]);
                }
            }
            std::mem::swap(&mut v, &mut v_next);
            std::mem::swap(&mut p, &mut p_next);
        }
    }
    if n >= 2 {
        diag[n - 2] = w[(n - 2) + (n - 2) * n];
        off[n - 2] = w[(n - 1) + (n - 2) * n];
    }
    if n >= 1 {
        diag[n - 1] = w[(n - 1) + (n - 1) * n];
    }
    (w, tau, diag, off)
}

/// The reflector H = I − τ v vᵀ that takes column `i` below its diagonal to a multiple of
/// its first entry (LAPACK's `dlarfg`): its vector, first entry 1, stored in the column
/// below row i + 1 and copied to `v`; returns τ and the entry β left at row i + 1. τ is 0
/// (no reflection) where the column is already reduced.
fn reflector(w: &mut [f64], n: usize, i: usize, v: &mut [f64]) -> (f64, f64) {
    let m = n - i - 1;
    let col = (i + 1) + i * n;
    let alpha = w[col];
    let sigma: f64 = w[col + 1..col + m].iter().map(|x| x * x).sum();
    v[0] = 1.0;
    if sigma == 0.0 {
        v[1..m].fill(0.0);
        return (0.0, alpha);
    }
    let beta = -alpha.hypot(sigma.sqrt()).copysign(alpha);
    let scale = 1.0 / (alpha - beta);
    w[col + 1..col + m].iter_mut().for_each(|x| *x *= scale);
    w[col] = beta;
    v[1..m].copy_from_slice(&w[col + 1..col + m]);
    ((beta - alpha) / beta, beta)
}

/// One column's share of y = A v, A symmetric with only its lower triangle stored:
/// `col` is column `c` from its diagonal down. Two plain loops (an axpy and a dot), each
/// vectorised, rather than one.
fn symv_column(col: &[f64], v: &[f64], c: usize, y: &mut [f64]) {
    let vc = v[c];
    let acc = dot(&col[1..], &v[c + 1..]);
    y[c..].iter_mut().zip(col).for_each(|(y, &x)| *y += x * vc);
    y[c] += acc;
}

/// x · y over the shorter, summed in four lanes so that the compiler can vectorise it (a
/// single running sum fixes the order of the additions, which forbids that).
fn dot(x: &[f64], y: &[f64]) -> f64 {
    let n = x.len().min(y.len());
    let (x, y) = (&x[..n], &y[..n]);
    let mut acc = [0.0f64; 4];
    let (xc, yc) = (x.chunks_exact(4), y.chunks_exact(4));
    let tail: f64 = xc
        .remainder()
        .iter()
        .zip(yc.remainder())
        .map(|(a, b)| a * b)
        .sum();
    for (a, b) in xc.zip(yc) {
        for l in 0..4 {
            acc[l] += a[l] * b[l];
        }
    }
    (acc[0] + acc[1]) + (acc[2] + acc[3]) + tail
}

/// Applies Q = H₀H₁… to each column of `z`.
fn back_transform(reflectors: &[f64], tau: &[f64], n: usize, z: &mut DMatrix<f64>) {
    for i in (0..n.saturating_sub(2)).rev() {
        let t = tau[i];
        if t == 0.0 {
            continue;
        }
        let v = &reflectors[(i + 2) + i * n..(i + 1) * n];
        for mut col in z.column_iter_mut() {
            let c = &mut col.as_mut_slice()[i + 1..];
            let s = t * (c[0] + dot(v, &c[1..]));
            c[0] -= s;
            c[1..].iter_mut().zip(v).for_each(|(x, a)| *x -= s * a);
        }
    }
}

/// Each tridiagonal's eigenvalues, descending, each with its unreduced block (split where
/// an off-diagonal entry is negligible beside its diagonal neighbours); `None` for one whose
/// QL does not converge. Every block of every matrix is an independent QL iteration, run
/// two at a time ([`run_together`]).
#[allow(clippy::type_complexity)]
fn tridiagonal_values<const K: usize>(
    mats: [(&[f64], &[f64]); K],
) -> [Option<(Vec<f64>, Vec<(usize, usize)>)>; K] {
    let mut jobs: Vec<(usize, (usize, usize), Ql)> = Vec::new();
    for (k, (diag, off)) in mats.iter().enumerate() {
        let n = diag.len();
        let mut b0 = 0;
        for i in 0..n {
            let split =
                i + 1 == n || off[i].abs() <= f64::EPSILON * (diag[i].abs() + diag[i + 1].abs());
            if split {
                let mut e: Vec<f64> = off[b0..i].to_vec();
                e.push(0.0);
                jobs.push((k, (b0, i + 1), Ql::new(diag[b0..=i].to_vec(), e)));
                b0 = i + 1;
            }
        }
    }
    for pair in jobs.chunks_mut(2) {
        match pair {
            [(_, _, a), (_, _, b)] => run_together(a, b),
            [(_, _, a)] => while a.step() {},
            _ => {}
        }
    }
    let mut out: [Option<(Vec<f64>, Vec<(usize, usize)>)>; K] = std::array::from_fn(|_| None);
    for (k, slot) in out.iter_mut().enumerate() {
        let mine = jobs.iter().filter(|(j, _, _)| *j == k);
        if mine.clone().any(|(_, _, q)| q.failed) {
            continue;
        }
        let mut found: Vec<(f64, (usize, usize))> = mine
            .flat_map(|(_, b, q)| q.d.iter().map(move |&v| (v, *b)))
            .collect();
        if found.iter().any(|(v, _)| !v.is_finite()) {
            continue;
        }
        found.sort_by(|a, b| b.0.total_cmp(&a.0));
        *slot = Some(found.into_iter().unzip());
    }
    out
}

/// Two QL iterations stepped in turn, a rotation of each: each rotation waits on the one
/// before it in its own sweep (a division, then another), so one sweep alone leaves the
/// processor idle most of the time, and two independent ones overlap. Each performs the
/// same operations in the same order as alone.
fn run_together(a: &mut Ql, b: &mut Ql) {
    loop {
        let (more_a, more_b) = (a.step(), b.step());
        if !(more_a || more_b) {
            break;
        }
    }
}

/// The eigenvalues of the tridiagonal `d` (diagonal) and `e` (e[i] couples i and i + 1,
/// the last 0), left in `d`: implicit QL with Wilkinson's shift in the Pal–Walker–Kahan
/// form without square roots (LAPACK's `dsterf`, its QL branch), which works on the squares
/// of `e`. Each rotation of a sweep depends on the one before, so the sweep is bound by the
/// latency of its chain; this form's chain is a third shorter than the textbook QL's (no
/// square root on it). Stepped one rotation (or one search for the next sweep) at a time,
/// so that two can run together ([`run_together`]).
struct Ql {
    d: Vec<f64>,
    e: Vec<f64>,
    norm2: f64,
    sweeps_left: usize,
    /// The first eigenvalue not yet converged.
    l: usize,
    /// The QL did not converge within [`MAX_SWEEPS`] per eigenvalue.
    failed: bool,
    /// Whether a sweep is in progress: its end `m`, the next rotation's row + 1 (`i`; the
    /// sweep ends at `l`), and its running values.
    sweep: bool,
    m: usize,
    i: usize,
    sigma: f64,
    gamma: f64,
    p: f64,
    c: f64,
    s: f64,
}

impl Ql {
    fn new(d: Vec<f64>, mut e: Vec<f64>) -> Ql {
        let n = d.len();
        // An off-diagonal entry is negligible beside its diagonal neighbours (LAPACK's
        // test) or beside the block's norm (EISPACK's `tql1` test): the reduction has
        // already made errors of that size, and the small eigenvalues of a nearly singular
        // covariance would otherwise take sweeps to reach a relative accuracy nothing reads.
        let norm = block_norm(&d, &e[..n.saturating_sub(1)]);
        e.iter_mut().for_each(|x| *x *= *x);
        Ql {
            d,
            e,
            norm2: norm * norm,
            sweeps_left: MAX_SWEEPS * n,
            l: 0,
            failed: false,
            sweep: false,
            m: 0,
            i: 0,
            sigma: 0.0,
            gamma: 0.0,
            p: 0.0,
            c: 0.0,
            s: 0.0,
        }
    }

    /// One rotation of the sweep in progress, or else the deflations up to the next sweep
    /// and its start; false when every eigenvalue has converged (or the QL failed).
    #[inline(always)]
    fn step(&mut self) -> bool {
        let (d, e) = (&mut self.d, &mut self.e);
        let n = d.len();
        if self.sweep {
            let l = self.l;
            let i = self.i - 1;
            let bb = e[i];
            let r = self.p + bb;
            if i + 1 != self.m {
                e[i + 1] = self.s * r;
            }
            let old_c = self.c;
            let inv = 1.0 / r;
            self.c = self.p * inv;
            self.s = bb * inv;
            let old_gamma = self.gamma;
            let alpha = d[i];
            self.gamma = self.c * (alpha - self.sigma) - self.s * old_gamma;
            d[i + 1] = old_gamma + (alpha - self.gamma);
            self.p = if self.c != 0.0 {
                self.gamma * self.gamma / self.c
            } else {
                old_c * bb
            };
            self.i = i;
            if i == l {
                e[l] = self.s * self.p;
                d[l] = self.sigma + self.gamma;
                self.sweep = false;
            }
            return true;
        }
        let eps2 = f64::EPSILON * f64::EPSILON;
        let mut l = self.l;
        while l < n && !self.failed {
            let mut m = l;
            while m + 1 < n {
                if e[m] <= eps2 * (d[m] * d[m + 1]).abs().max(self.norm2) {
                    break;
                }
                m += 1;
            }
            if m + 1 < n {
                e[m] = 0.0;
            }
            if m == l {
                l += 1;
                continue;
            }
            if m == l + 1 {
                (d[l], d[l + 1]) = eigen2(d[l], e[l].sqrt(), d[l + 1]);
                e[l] = 0.0;
                l += 2;
                continue;
            }
            if self.sweeps_left == 0 {
                self.failed = true;
                break;
            }
            self.sweeps_left -= 1;
            let rte = e[l].sqrt();
            let mut sigma = (d[l + 1] - d[l]) / (2.0 * rte);
            let r = hypot(sigma, 1.0);
            sigma = d[l] - rte / (sigma + r.copysign(sigma));
            self.sigma = sigma;
            (self.c, self.s) = (1.0, 0.0);
            self.gamma = d[m] - sigma;
            self.p = self.gamma * self.gamma;
            (self.m, self.i, self.sweep, self.l) = (m, m, true, l);
            return true;
        }
        self.l = l;
        false
    }
}

/// The eigenvalues of the 2 × 2 symmetric [[a, b], [b, c]] (LAPACK's `dlae2`): the one of
/// larger magnitude directly, the other from the determinant, so that neither cancels.
fn eigen2(a: f64, b: f64, c: f64) -> (f64, f64) {
    let (sm, df) = (a + c, a - c);
    let (big, small) = if a.abs() > c.abs() { (a, c) } else { (c, a) };
    let rt = hypot(df, 2.0 * b);
    if sm == 0.0 {
        return (0.5 * rt, -0.5 * rt);
    }
    let rt1 = 0.5 * (sm + rt.copysign(sm));
    (rt1, (big / rt1) * small - (b / rt1) * b)
}

/// √(a² + b²): directly where the squares cannot overflow or underflow (every matrix the
/// fills decompose), else by the library's careful and several times slower `hypot`.
fn hypot(a: f64, b: f64) -> f64 {
    let m = a.abs().max(b.abs());
    if m < 1e150 && m > 1e-150 {
        (a * a + b * b).sqrt()
    } else {
        a.hypot(b)
    }
}

/// The largest absolute row sum of the tridiagonal block.
fn block_norm(d: &[f64], e: &[f64]) -> f64 {
    (0..d.len())
        .map(|i| {
            let left = if i > 0 { e[i - 1].abs() } else { 0.0 };
            let right = e.get(i).map_or(0.0, |x| x.abs());
            d[i].abs() + left + right
        })
        .fold(0.0, f64::max)
}

/// LU with partial pivoting of the tridiagonal less λI: U has two superdiagonals.
#[derive(Default)]
struct Lu {
    /// The pivots' reciprocals: the back substitution's chain multiplies, not divides.
    inv_u0: Vec<f64>,
    u1: Vec<f64>,
    u2: Vec<f64>,
    mult: Vec<f64>,
    swap: Vec<bool>,
}

impl Lu {
    /// Factors T − λI into this one's buffers (made once per decomposition's vectors: a
    /// vector's allocations cost about what its factorisation does).
    fn factor(&mut self, d: &[f64], e: &[f64], lambda: f64, norm: f64) {
        let m = d.len();
        let tiny = f64::EPSILON * norm;
        let Lu {
            inv_u0: u0,
            u1,
            u2,
            mult,
            swap,
        } = self;
        for v in [&mut *u0, &mut *u1, &mut *u2, &mut *mult] {
            v.clear();
            v.resize(m, 0.0);
        }
        swap.clear();
        swap.resize(m, false);
        // The row being eliminated into: its entries at columns i and i + 1.
        let (mut x0, mut x1) = (d[0] - lambda, e.first().copied().unwrap_or(0.0));
        for i in 0..m - 1 {
            let (a, b, c) = (
                e[i],
                d[i + 1] - lambda,
                e.get(i + 1).copied().unwrap_or(0.0),
            );
            if x0.abs() >= a.abs() {
                let piv = if x0.abs() < tiny {
                    tiny.copysign(x0)
                } else {
                    x0
                };
                let l = a / piv;
                (u0[i], u1[i], u2[i]) = (piv, x1, 0.0);
                mult[i] = l;
                (x0, x1) = (b - l * x1, c);
            } else {
                let l = x0 / a;
                (u0[i], u1[i], u2[i]) = (a, b, c);
                mult[i] = l;
                swap[i] = true;
                (x0, x1) = (x1 - l * b, -l * c);
            }
        }
        u0[m - 1] = if x0.abs() < tiny {
            tiny.copysign(x0)
        } else {
            x0
        };
        u0.iter_mut().for_each(|u| *u = 1.0 / *u);
    }

    /// Solves (T − λI) x = y in place.
    fn solve(&self, y: &mut [f64]) {
        let m = y.len();
        for i in 0..m - 1 {
            if self.swap[i] {
                y.swap(i, i + 1);
            }
            y[i + 1] -= self.mult[i] * y[i];
        }
        for i in (0..m).rev() {
            let mut s = y[i];
            if i + 1 < m {
                s -= self.u1[i] * y[i + 1];
            }
            if i + 2 < m {
                s -= self.u2[i] * y[i + 2];
            }
            y[i] = s * self.inv_u0[i];
        }
    }
}

/// Eigenvalues (descending) and matching eigenvectors (columns) of a symmetric matrix given
/// row-major.
pub(crate) fn symmetric_eigen(a: &[f64], n: usize) -> (Vec<f64>, DMatrix<f64>) {
    let m = DMatrix::from_row_slice(n, n, a);
    // Converged to 1e-10 rather than machine precision: principal components need no
    // more, and the QR sweeps stop sooner.
    let e = nalgebra::SymmetricEigen::try_new(m.clone(), 1e-10, 0)
        .unwrap_or_else(|| m.symmetric_eigen());
    let mut order: Vec<usize> = (0..n).collect();
    order.sort_by(|&i, &j| e.eigenvalues[j].total_cmp(&e.eigenvalues[i]));
    let vals = order.iter().map(|&i| e.eigenvalues[i]).collect();
    let vecs = DMatrix::from_fn(n, n, |r, c| e.eigenvectors[(r, order[c])]);
    (vals, vecs)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::SplitMix64;

    /// A symmetric matrix with the given eigenvalues and a random orthonormal basis.
    fn with_values(values: &[f64], seed: u64) -> DMatrix<f64> {
        let n = values.len();
        let mut rng = SplitMix64::new(seed);
        let g = DMatrix::from_fn(n, n, |_, _| rng.normal());
        let q = g.qr().q();
        &q * DMatrix::from_diagonal(&nalgebra::DVector::from_column_slice(values)) * q.transpose()
    }

    /// Checks `Leading` against nalgebra's full decomposition: every eigenvalue to 1e-10 of
    /// the largest, and the leading `k` eigenvectors orthonormal, each an eigenvector
    /// (residual under 1e-10 of the norm) and in the reference's eigenspace of its value
    /// (equal up to sign where the value is simple).
    fn check(a: &DMatrix<f64>, k: usize) {
        let n = a.nrows();
        let ours = Leading::new(a.as_slice(), n);
        let reference = a.clone().symmetric_eigen();
        let mut order: Vec<usize> = (0..n).collect();
        order.sort_by(|&i, &j| reference.eigenvalues[j].total_cmp(&reference.eigenvalues[i]));
        let scale = a.abs().max().max(f64::MIN_POSITIVE);
        for (i, &r) in order.iter().enumerate() {
            let (v, w) = (ours.values()[i], reference.eigenvalues[r]);
            assert!(
                (v - w).abs() <= 1e-10 * scale,
                "eigenvalue {i}: {v} against {w}"
            );
        }
        let z = ours.vectors(k);
        let gram = z.transpose() * &z;
        assert!(
            (gram - DMatrix::identity(k, k)).abs().max() < 1e-10,
            "not orthonormal"
        );
        for j in 0..k {
            let v = z.column(j);
            let lambda = ours.values()[j];
            let res = (a * v - v * lambda).norm();
            assert!(res < 1e-10 * scale, "vector {j}: residual {res}");
            // Its projection on the reference's vectors of the same value is the whole of it.
            let same: f64 = order
                .iter()
                .filter(|&&r| (reference.eigenvalues[r] - lambda).abs() < 1e-8 * scale)
                .map(|&r| reference.eigenvectors.column(r).dot(&v).powi(2))
                .sum();
            assert!(
                (same - 1.0).abs() < 1e-8,
                "vector {j}: {same} in its eigenspace"
            );
        }
    }

    /// Two decompositions made together ([`Leading::pair`], their QL iterations stepped in
    /// turn) equal each made alone, bit for bit: values and vectors, on matrices of
    /// different sizes, one of them splitting into blocks (a zero coupling) and one with
    /// repeated eigenvalues.
    #[test]
    fn pairs_equal_singles_bit_for_bit() {
        let mut rng = SplitMix64::new(11);
        let mut random = |n: usize| {
            let g = DMatrix::from_fn(n, n, |_, _| rng.normal());
            &g * g.transpose()
        };
        let mut split = DMatrix::<f64>::zeros(30, 30);
        split.view_mut((0, 0), (12, 12)).copy_from(&random(12));
        split.view_mut((12, 12), (18, 18)).copy_from(&random(18));
        let repeated = with_values(&[3.0, 3.0, 3.0, 1.0, 1.0, 0.5, 0.0, 0.0], 5);
        let cases = [
            (random(27), random(24)),
            (random(75), random(5)),
            (split, random(40)),
            (repeated, random(1)),
        ];
        let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<u64>>();
        for (a, b) in &cases {
            let (na, nb) = (a.nrows(), b.nrows());
            let (pa, pb) = Leading::pair(a.as_slice(), na, b.as_slice(), nb);
            for (paired, m, n) in [(pa, a, na), (pb, b, nb)] {
                let alone = Leading::new(m.as_slice(), n);
                assert_eq!(bits(paired.values()), bits(alone.values()));
                let k = n.min(6);
                assert_eq!(
                    bits(paired.vectors(k).as_slice()),
                    bits(alone.vectors(k).as_slice())
                );
            }
        }
    }

    #[test]
    fn matches_nalgebra_on_random_matrices() {
        let mut rng = SplitMix64::new(7);
        for n in [1, 2, 3, 5, 12, 40, 75] {
            let g = DMatrix::from_fn(n, n, |_, _| rng.normal());
            let a = &g + g.transpose();
            for k in [1, n / 3, n] {
                check(&a, k.max(1).min(n));
            }
        }
    }

    #[test]
    fn repeated_and_near_repeated_eigenvalues() {
        let values = [
            5.0,
            5.0,
            5.0,
            3.0,
            3.0 + 1e-12,
            3.0 - 1e-9,
            1.0,
            0.5,
            0.5,
            0.1,
        ];
        for seed in 0..5 {
            let a = with_values(&values, seed);
            check(&a, values.len());
        }
        // Exactly diagonal: every off-diagonal entry splits the tridiagonal.
        let d = DMatrix::from_diagonal(&nalgebra::DVector::from_column_slice(&[2.0, 2.0, 1.0]));
        check(&d, 3);
        check(&DMatrix::identity(6, 6), 6);
    }

    #[test]
    fn rank_deficient_and_zero_matrices() {
        let mut rng = SplitMix64::new(3);
        // Covariance-like: 60 columns from 12 rows, so rank 12 and 48 zero eigenvalues.
        let x = DMatrix::from_fn(12, 60, |_, _| rng.normal());
        let c = x.transpose() * &x / 11.0;
        check(&c, 12);
        check(&c, 20);
        // A covariance with one marker's rows and columns zeroed.
        let x = DMatrix::from_fn(200, 30, |_, _| rng.normal());
        let mut c = x.transpose() * &x / 199.0;
        for i in 6..9 {
            c.row_mut(i).fill(0.0);
            c.column_mut(i).fill(0.0);
        }
        check(&c, 30);
        check(&DMatrix::zeros(5, 5), 5);
    }
}
