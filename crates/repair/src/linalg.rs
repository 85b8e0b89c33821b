//! Small dense helpers: Gaussian elimination, Kabsch, symmetric eigen (via nalgebra, and
//! [`Leading`] where only the leading eigenvectors are used).

use nalgebra::{Matrix3, Matrix4, Vector3, Vector4};

mod eigen;

/// The whole decomposition, the oracle the published PCA's tests compare with.
#[cfg(test)]
pub(crate) use eigen::symmetric_eigen;
pub(crate) use eigen::Leading;

/// Solves `a x = rhs` in place for `n` unknowns and `r` right-hand sides by Gaussian
/// elimination with partial pivoting. `a` is row-major n×n, `rhs` row-major n×r. Returns
/// false when the matrix is singular to working precision.
pub(crate) fn solve_in_place(a: &mut [f64], n: usize, rhs: &mut [f64], r: usize) -> bool {
    solve_band_in_place(a, n, rhs, r, n)
}

/// [`solve_in_place`] for a matrix whose nonzeros lie within `band` places of the diagonal
/// (a spline's near-tridiagonal system): pivots are searched and rows eliminated only
/// inside the band, whose upper side pivoting can widen to `2 × band`, so the work grows
/// with `n`, not `n³`.
pub(crate) fn solve_band_in_place(
    a: &mut [f64],
    n: usize,
    rhs: &mut [f64],
    r: usize,
    band: usize,
) -> bool {
    let reach = |col: usize, w: usize| (col + w + 1).min(n);
    let mut scale = f64::MIN_POSITIVE;
    for row in 0..n {
        for v in &a[row * n + row.saturating_sub(band)..row * n + reach(row, band)] {
            scale = scale.max(v.abs());
        }
    }
    for col in 0..n {
        let mut piv = col;
        for row in col + 1..reach(col, band) {
            if a[row * n + col].abs() > a[piv * n + col].abs() {
                piv = row;
            }
        }
        if a[piv * n + col].abs() <= 1e-13 * scale {
            return false;
        }
        if piv != col {
            for k in col..reach(col, 2 * band) {
                a.swap(piv * n + k, col * n + k);
            }
            for k in 0..r {
                rhs.swap(piv * r + k, col * r + k);
            }
        }
        let d = a[col * n + col];
        for row in col + 1..reach(col, band) {
            let f = a[row * n + col] / d;
            if f == 0.0 {
                continue;
            }
            for k in col..reach(col, 2 * band) {
                a[row * n + k] -= f * a[col * n + k];
            }
            for k in 0..r {
                rhs[row * r + k] -= f * rhs[col * r + k];
            }
        }
    }
    for col in (0..n).rev() {
        let d = a[col * n + col];
        for k in 0..r {
            let mut s = rhs[col * r + k];
            for j in col + 1..reach(col, 2 * band) {
                s -= a[col * n + j] * rhs[j * r + k];
            }
            rhs[col * r + k] = s / d;
        }
    }
    true
}

/// A rotation and translation, `q = rot * p + trans`.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Rigid {
    pub rot: Matrix3<f64>,
    pub trans: Vector3<f64>,
}

impl Rigid {
    pub fn apply(&self, p: [f64; 3]) -> [f64; 3] {
        let q = self.rot * Vector3::from(p) + self.trans;
        [q.x, q.y, q.z]
    }

    /// The inverse transform applied to `q`.
    pub fn apply_inverse(&self, q: [f64; 3]) -> [f64; 3] {
        let p = self.rot.transpose() * (Vector3::from(q) - self.trans);
        [p.x, p.y, p.z]
    }
}

/// Least-squares rigid transform mapping points `p` onto `q` (Kabsch, SVD of the cross
/// covariance, with the sign fix that rules out reflections). `None` when SVD fails.
pub(crate) fn kabsch(p: &[[f64; 3]], q: &[[f64; 3]]) -> Option<Rigid> {
    let n = p.len().min(q.len());
    if n == 0 {
        return None;
    }
    let mean = |s: &[[f64; 3]]| {
        let mut c = Vector3::zeros();
        for v in &s[..n] {
            c += Vector3::from(*v);
        }
        c / n as f64
    };
    let (cp, cq) = (mean(p), mean(q));
    let mut h = Matrix3::zeros();
    for i in 0..n {
        h += (Vector3::from(p[i]) - cp) * (Vector3::from(q[i]) - cq).transpose();
    }
    if n == 3 {
        // Three points span a plane, so H has rank 2 and no polar factor. Adding the
        // outer product of the two planes' unit normals (oriented by the point order) fills
        // the null space without changing the other singular pairs, so the polar factor is
        // still Kabsch's rotation.
        let normal = |s: &[[f64; 3]]| {
            let (a, b, c) = (
                Vector3::from(s[0]),
                Vector3::from(s[1]),
                Vector3::from(s[2]),
            );
            (b - a).cross(&(c - a)).try_normalize(1e-12)
        };
        if let (Some(np), Some(nq)) = (normal(p), normal(q)) {
            h += np * nq.transpose() * h.norm();
        }
    }
    let rot = quaternion_rotation(&h)
        .or_else(|| polar_rotation(&h.transpose()))
        .or_else(|| {
            let svd = h.svd(true, true);
            let (u, vt) = (svd.u?, svd.v_t?);
            let v = vt.transpose();
            let d = (v * u.transpose()).determinant().signum();
            let fix =
                Matrix3::from_diagonal(&Vector3::new(1.0, 1.0, if d < 0.0 { -1.0 } else { 1.0 }));
            Some(v * fix * u.transpose())
        })?;
    let trans = cq - rot * cp;
    Some(Rigid { rot, trans })
}

/// Kabsch's rotation from the cross-covariance `h` (Σ (p − p̄)(q − q̄)ᵀ) by Horn's
/// quaternion method: the rotation is the unit quaternion that is the eigenvector of the
/// largest eigenvalue of a traceless symmetric 4 × 4 matrix made from `h`. That eigenvalue
/// is found by Newton's method on the characteristic quartic from an upper bound (the
/// quaternion characteristic polynomial method of Theobald 2005), the eigenvector as a
/// column of the adjugate of K − λI. It is always a proper rotation, the one Kabsch's sign
/// fix gives, at under half the cost of the polar iteration: the rigid fill makes one per
/// frame, and they were an eighth of `auto`'s time (single-threaded `auto` on the synthetic
/// 100-marker trial: 1.35 s against 1.48–1.62 s). `None` when the largest eigenvalue is
/// (nearly) repeated, so the rotation is not determined by the eigenvector alone.
fn quaternion_rotation(h: &Matrix3<f64>) -> Option<Matrix3<f64>> {
    let (sxx, sxy, sxz) = (h[(0, 0)], h[(0, 1)], h[(0, 2)]);
    let (syx, syy, syz) = (h[(1, 0)], h[(1, 1)], h[(1, 2)]);
    let (szx, szy, szz) = (h[(2, 0)], h[(2, 1)], h[(2, 2)]);
    #[rustfmt::skip]
    let k = Matrix4::new(
        sxx + syy + szz, syz - szy, szx - sxz, sxy - syx,
        syz - szy, sxx - syy - szz, sxy + syx, szx + sxz,
        szx - sxz, sxy + syx, -sxx + syy - szz, syz + szy,
        sxy - syx, szx + sxz, syz + szy, -sxx - syy + szz,
    );
    // det(λI − K) = λ⁴ − (tr K² / 2) λ² − (tr K³ / 3) λ + det K, as K is traceless.
    let k2 = k * k;
    let t2 = k2.trace();
    let t3 = k2.component_mul(&k).sum();
    let det = det4(&k);
    let norm = h.norm();
    if !(norm.is_finite() && norm > 0.0) {
        return None;
    }
    // The largest eigenvalue is at most the sum of h's singular values, ≤ √3 ‖h‖.
    let mut l = 3f64.sqrt() * norm;
    for i in 0.. {
        let p = ((l * l - 0.5 * t2) * l - t3 / 3.0) * l + det;
        let dp = (4.0 * l * l - t2) * l - t3 / 3.0;
        if dp == 0.0 || i == 60 {
            return None;
        }
        let step = p / dp;
        l -= step;
        if step.abs() <= 1e-13 * norm {
            break;
        }
    }
    // A column of adj(K − λI) spans its null space when it has rank 3: the largest one.
    let adj = adjugate4(&(k - Matrix4::identity() * l));
    let mut best = (0.0, Vector4::zeros());
    for c in 0..4 {
        let v: Vector4<f64> = adj.column(c).into();
        let n2 = v.norm_squared();
        if n2 > best.0 {
            best = (n2, v);
        }
    }
    // A repeated top eigenvalue (collinear donors: the rotation about their line is not
    // determined) leaves every column nearly zero, and Newton's method reaches a double
    // root only to about √ε; those are left to the polar factor and the SVD.
    if best.0.sqrt() < 1e-6 * norm.powi(3) {
        return None;
    }
    let q = best.1 / best.0.sqrt();
    let (w, x, y, z) = (q[0], q[1], q[2], q[3]);
    #[rustfmt::skip]
    let r = Matrix3::new(
        w * w + x * x - y * y - z * z, 2.0 * (x * y - w * z), 2.0 * (x * z + w * y),
        2.0 * (x * y + w * z), w * w - x * x + y * y - z * z, 2.0 * (y * z - w * x),
        2.0 * (x * z - w * y), 2.0 * (y * z + w * x), w * w - x * x - y * y + z * z,
    );
    Some(r)
}

/// The 2 × 2 minors of a 4 × 4 matrix's top row pair (`s`) and bottom row pair (`c`), from
/// which both its determinant and its adjugate follow (Laplace expansion).
fn pair_minors(a: &Matrix4<f64>) -> ([f64; 6], [f64; 6]) {
    let e = |r: usize, c: usize| a[(r, c)];
    let top = |i: usize, j: usize| e(0, i) * e(1, j) - e(1, i) * e(0, j);
    let bottom = |i: usize, j: usize| e(2, i) * e(3, j) - e(3, i) * e(2, j);
    (
        [
            top(0, 1),
            top(0, 2),
            top(0, 3),
            top(1, 2),
            top(1, 3),
            top(2, 3),
        ],
        [
            bottom(0, 1),
            bottom(0, 2),
            bottom(0, 3),
            bottom(1, 2),
            bottom(1, 3),
            bottom(2, 3),
        ],
    )
}

/// The determinant of a 4 × 4 matrix (see [`pair_minors`]).
fn det4(a: &Matrix4<f64>) -> f64 {
    let ([s0, s1, s2, s3, s4, s5], [c0, c1, c2, c3, c4, c5]) = pair_minors(a);
    s0 * c5 - s1 * c4 + s2 * c3 + s3 * c2 - s4 * c1 + s5 * c0
}

/// The adjugate of a 4 × 4 matrix (`a · adj = det · I`; see [`pair_minors`]).
fn adjugate4(a: &Matrix4<f64>) -> Matrix4<f64> {
    let e = |r: usize, c: usize| a[(r, c)];
    let ([s0, s1, s2, s3, s4, s5], [c0, c1, c2, c3, c4, c5]) = pair_minors(a);
    #[rustfmt::skip]
    let adj = Matrix4::new(
        e(1, 1) * c5 - e(1, 2) * c4 + e(1, 3) * c3,
        -e(0, 1) * c5 + e(0, 2) * c4 - e(0, 3) * c3,
        e(3, 1) * s5 - e(3, 2) * s4 + e(3, 3) * s3,
        -e(2, 1) * s5 + e(2, 2) * s4 - e(2, 3) * s3,
        -e(1, 0) * c5 + e(1, 2) * c2 - e(1, 3) * c1,
        e(0, 0) * c5 - e(0, 2) * c2 + e(0, 3) * c1,
        -e(3, 0) * s5 + e(3, 2) * s2 - e(3, 3) * s1,
        e(2, 0) * s5 - e(2, 2) * s2 + e(2, 3) * s1,
        e(1, 0) * c4 - e(1, 1) * c2 + e(1, 3) * c0,
        -e(0, 0) * c4 + e(0, 1) * c2 - e(0, 3) * c0,
        e(3, 0) * s4 - e(3, 1) * s2 + e(3, 3) * s0,
        -e(2, 0) * s4 + e(2, 1) * s2 - e(2, 3) * s0,
        -e(1, 0) * c3 + e(1, 1) * c1 - e(1, 2) * c0,
        e(0, 0) * c3 - e(0, 1) * c1 + e(0, 2) * c0,
        -e(3, 0) * s3 + e(3, 1) * s1 - e(3, 2) * s0,
        e(2, 0) * s3 - e(2, 1) * s1 + e(2, 2) * s0,
    );
    adj
}

/// The orthogonal polar factor of `a` when it is a proper rotation, by scaled Newton
/// iteration (Higham): for `a = Hᵀ` with `det > 0` it equals Kabsch's `V Uᵀ`, an order of
/// magnitude faster than a 3×3 SVD. `None` when `det(a) <= 0` (the reflection case needs
/// the SVD's sign fix) or the iteration does not settle (near-singular donors).
fn polar_rotation(a: &Matrix3<f64>) -> Option<Matrix3<f64>> {
    let scale = a.norm();
    if scale.is_nan() || scale <= 0.0 || a.determinant() <= 1e-12 * scale.powi(3) {
        return None;
    }
    let mut x = a / scale;
    for _ in 0..40 {
        let inv_t = x.try_inverse()?.transpose();
        let g = (inv_t.norm() / x.norm()).sqrt();
        let next = (x * g + inv_t / g) * 0.5;
        let delta = (next - x).norm();
        x = next;
        if delta < 1e-10 {
            // Convergence is quadratic: one more unscaled step reaches full precision.
            let inv_t = x.try_inverse()?.transpose();
            return Some((x + inv_t) * 0.5);
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn solves_small_system() {
        let mut a = vec![2.0, 1.0, 1.0, 3.0];
        let mut b = vec![3.0, 5.0];
        assert!(solve_in_place(&mut a, 2, &mut b, 1));
        assert!((b[0] - 0.8).abs() < 1e-12 && (b[1] - 1.4).abs() < 1e-12);
        let mut s = vec![1.0, 2.0, 2.0, 4.0];
        assert!(!solve_in_place(&mut s, 2, &mut [1.0, 1.0], 1));
    }

    /// The banded solver agrees with the dense one on a banded system whose pivoting
    /// swaps rows (small diagonal).
    #[test]
    fn banded_solve_matches_dense() {
        let n = 12;
        let mut a = vec![0.0; n * n];
        let mut seed = 7u64;
        let mut next = || {
            seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1);
            (seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        };
        for i in 0..n {
            for j in i.saturating_sub(2)..(i + 3).min(n) {
                a[i * n + j] = if i == j { 0.01 * next() } else { next() };
            }
        }
        let b: Vec<f64> = (0..2 * n).map(|_| next()).collect();
        let (mut a1, mut b1) = (a.clone(), b.clone());
        assert!(solve_in_place(&mut a1, n, &mut b1, 2));
        let (mut a2, mut b2) = (a, b);
        assert!(solve_band_in_place(&mut a2, n, &mut b2, 2, 2));
        for (x, y) in b1.iter().zip(&b2) {
            assert!((x - y).abs() < 1e-9 * x.abs().max(1.0), "{x} {y}");
        }
    }

    fn centroid(s: &[[f64; 3]]) -> Vector3<f64> {
        s.iter().map(|v| Vector3::from(*v)).sum::<Vector3<f64>>() / s.len() as f64
    }

    /// Horn's quaternion rotation equals the polar factor (Kabsch's rotation) on noisy and
    /// planar clusters, and on ones whose best fit without the sign fix is a reflection.
    #[test]
    fn quaternion_rotation_matches_polar_factor() {
        let mut rng = crate::rng::SplitMix64::new(11);
        let mut next = || rng.uniform() - 0.5;
        let mut checked = 0;
        for case in 0..400 {
            let n = 3 + case % 5;
            let p: Vec<[f64; 3]> = (0..n)
                .map(|_| {
                    [
                        100.0 * next(),
                        100.0 * next(),
                        if case % 7 == 0 { 0.0 } else { 100.0 * next() },
                    ]
                })
                .collect();
            let rot =
                nalgebra::Rotation3::from_euler_angles(6.0 * next(), 6.0 * next(), 6.0 * next())
                    .into_inner();
            let mirror = case % 3 == 0;
            let q: Vec<[f64; 3]> = p
                .iter()
                .map(|&x| {
                    let mut v = rot * Vector3::from(x);
                    if mirror {
                        v.x = -v.x;
                    }
                    [v.x + 5.0 * next(), v.y + 5.0 * next(), v.z + 5.0 * next()]
                })
                .collect();
            let (cp, cq) = (centroid(&p), centroid(&q));
            let mut h = Matrix3::zeros();
            for (a, b) in p.iter().zip(&q) {
                h += (Vector3::from(*a) - cp) * (Vector3::from(*b) - cq).transpose();
            }
            let reference = polar_rotation(&h.transpose()).or_else(|| {
                let svd = h.svd(true, true);
                let (u, v) = (svd.u?, svd.v_t?.transpose());
                let d = (v * u.transpose()).determinant().signum();
                Some(v * Matrix3::from_diagonal(&Vector3::new(1.0, 1.0, d)) * u.transpose())
            });
            if let (Some(a), Some(b)) = (quaternion_rotation(&h), reference) {
                assert!((a - b).norm() < 1e-8, "case {case}: {a} vs {b}");
                assert!((a.determinant() - 1.0).abs() < 1e-12);
                checked += 1;
            }
        }
        assert!(checked > 390, "{checked}");
    }

    #[test]
    fn adjugate_times_matrix_is_determinant() {
        let a = Matrix4::new(
            2.0, -1.0, 0.5, 3.0, 0.0, 4.0, 1.0, -2.0, 1.5, 2.0, -3.0, 0.5, -1.0, 0.0, 2.0, 1.0,
        );
        let (det, adj) = (det4(&a), adjugate4(&a));
        assert!((det - a.determinant()).abs() < 1e-9);
        assert!((a * adj - Matrix4::identity() * det).norm() < 1e-9);
    }

    #[test]
    fn kabsch_recovers_rotation_without_reflection() {
        let p = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 2.0, 0.0],
            [0.0, 0.0, 3.0],
        ];
        let rot = nalgebra::Rotation3::from_euler_angles(0.3, -0.7, 1.1).into_inner();
        let t = Rigid {
            rot,
            trans: Vector3::new(5.0, -2.0, 1.0),
        };
        let q: Vec<[f64; 3]> = p.iter().map(|&x| t.apply(x)).collect();
        let k = kabsch(&p, &q).unwrap();
        assert!((k.rot - rot).norm() < 1e-12);
        assert!((k.trans - t.trans).norm() < 1e-12);
        // A reflected cloud still gives a proper rotation (the SVD path with the sign fix).
        let m: Vec<[f64; 3]> = q.iter().map(|v| [v[0], v[1], -v[2]]).collect();
        let r = kabsch(&p, &m).unwrap();
        assert!((r.rot.determinant() - 1.0).abs() < 1e-12);
        // Noisy points: the polar path equals the SVD solution.
        let noisy: Vec<[f64; 3]> = q
            .iter()
            .enumerate()
            .map(|(i, v)| {
                [
                    v[0] + 0.01 * i as f64,
                    v[1] - 0.02,
                    v[2] + 0.003 * (i * i) as f64,
                ]
            })
            .collect();
        let k = kabsch(&p, &noisy).unwrap();
        let (cp, cq) = (centroid(&p), centroid(&noisy));
        let mut h = Matrix3::zeros();
        for i in 0..p.len() {
            h += (Vector3::from(p[i]) - cp) * (Vector3::from(noisy[i]) - cq).transpose();
        }
        let svd = h.svd(true, true);
        let (u, vt) = (svd.u.unwrap(), svd.v_t.unwrap());
        assert!((k.rot - vt.transpose() * u.transpose()).norm() < 1e-12);
        // Three noisy points (rank-2 cross-covariance): same as the SVD with its sign fix.
        let k3 = kabsch(&p[1..], &noisy[1..]).unwrap();
        let (cp, cq) = (centroid(&p[1..]), centroid(&noisy[1..]));
        let mut h = Matrix3::zeros();
        for i in 1..p.len() {
            h += (Vector3::from(p[i]) - cp) * (Vector3::from(noisy[i]) - cq).transpose();
        }
        let svd = h.svd(true, true);
        let (u, vt) = (svd.u.unwrap(), svd.v_t.unwrap());
        let v = vt.transpose();
        let d = (v * u.transpose()).determinant().signum();
        let want = v * Matrix3::from_diagonal(&Vector3::new(1.0, 1.0, d)) * u.transpose();
        assert!((k3.rot - want).norm() < 1e-10, "{}", (k3.rot - want).norm());
        assert!((k3.rot.determinant() - 1.0).abs() < 1e-12);
    }
}
