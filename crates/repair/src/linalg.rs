//! Small dense helpers: Gaussian elimination, Kabsch, symmetric eigen (via nalgebra).

use nalgebra::{DMatrix, Matrix3, Vector3};

/// Solves `a x = rhs` in place for `n` unknowns and `r` right-hand sides by Gaussian
/// elimination with partial pivoting. `a` is row-major n×n, `rhs` row-major n×r. Returns
/// false when the matrix is singular to working precision.
pub(crate) fn solve_in_place(a: &mut [f64], n: usize, rhs: &mut [f64], r: usize) -> bool {
    let scale = a
        .iter()
        .fold(0.0f64, |m, v| m.max(v.abs()))
        .max(f64::MIN_POSITIVE);
    for col in 0..n {
        let mut piv = col;
        for row in col + 1..n {
            if a[row * n + col].abs() > a[piv * n + col].abs() {
                piv = row;
            }
        }
        if a[piv * n + col].abs() <= 1e-13 * scale {
            return false;
        }
        if piv != col {
            for k in 0..n {
                a.swap(piv * n + k, col * n + k);
            }
            for k in 0..r {
                rhs.swap(piv * r + k, col * r + k);
            }
        }
        let d = a[col * n + col];
        for row in col + 1..n {
            let f = a[row * n + col] / d;
            if f == 0.0 {
                continue;
            }
            for k in col..n {
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
            for j in col + 1..n {
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
    let svd = h.svd(true, true);
    let (u, vt) = (svd.u?, svd.v_t?);
    let v = vt.transpose();
    let d = (v * u.transpose()).determinant().signum();
    let fix = Matrix3::from_diagonal(&Vector3::new(1.0, 1.0, if d < 0.0 { -1.0 } else { 1.0 }));
    let rot = v * fix * u.transpose();
    let trans = cq - rot * cp;
    Some(Rigid { rot, trans })
}

/// Eigenvalues (descending) and matching eigenvectors (columns) of a symmetric matrix given
/// row-major.
pub(crate) fn symmetric_eigen(a: &[f64], n: usize) -> (Vec<f64>, DMatrix<f64>) {
    let m = DMatrix::from_row_slice(n, n, a);
    let e = m.symmetric_eigen();
    let mut order: Vec<usize> = (0..n).collect();
    order.sort_by(|&i, &j| e.eigenvalues[j].total_cmp(&e.eigenvalues[i]));
    let vals = order.iter().map(|&i| e.eigenvalues[i]).collect();
    let vecs = DMatrix::from_fn(n, n, |r, c| e.eigenvectors[(r, order[c])]);
    (vals, vecs)
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
        assert!((k.rot.determinant() - 1.0).abs() < 1e-12);
    }
}
