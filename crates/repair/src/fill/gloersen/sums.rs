//! The published PCA's covariances by downdate: sums over every frame of a pass's data,
//! built once and shared by the pass's models, from which each model's covariance over its
//! own training rows is the sums minus the rows it leaves out.
//!
//! A model trains on the frames where all its kept markers are recorded (and its target
//! outside its holes); it leaves out the target's missing frames, its artificial holes and
//! the other kept markers' gaps, usually a small part of a long trial. Its product XᵀX over
//! the training rows was the model's largest cost after the decompositions (a product over
//! every row, 2 500 on nimblephysics' squat, for each of its 90 models); summed over every
//! frame once, with a missing sample counted as 0, it is the sum over the rows left out that
//! each model computes, and the column means and standard deviations follow from Σx and Σx²
//! over the same rows. The published weights are a diagonal scaling applied afterwards.
//!
//! Two things keep this exact to rounding. Cancellation: each column is shifted by a fixed
//! value (its mean over the frames it is recorded on) before summing, so the sums hold
//! deviations, not positions metres from the origin. The mean trajectory: a model subtracts
//! the mean of the markers recorded on every frame *of its own data*, which lacks the
//! target (and, in the second pass, the marker read as recorded) when the pass's data has
//! them complete; removing markers R from that mean adds Σ_R y_r / |whole| to every
//! column of the same axis (y the coordinates centred on the pass's mean trajectory), so
//! the model's sums follow from the pass's sums of R's columns.

use super::super::data::Data;
use nalgebra::DMatrix;
use std::sync::OnceLock;

/// The sums over every frame of one pass's data (its coordinates and its validity, the
/// marker read as recorded in the second pass apart, see [`Sums::covariance`]).
pub(super) struct Sums {
    /// The markers recorded on every frame, by the pass's validity.
    whole: Vec<usize>,
    /// Per marker and frame, its coordinates minus the mean trajectory of `whole` and minus
    /// the column's shift; 0 where it is missing.
    z: Vec<Vec<[f64; 3]>>,
    /// Per marker, the columns' shifts (their means over the frames they are recorded on).
    shift: Vec<[f64; 3]>,
    /// Per marker, Σ z over every frame.
    z1: Vec<[f64; 3]>,
    /// Per pair of markers (the first ≤ the second), Σ z zᵀ over every frame (3 × 3,
    /// row-major), made when a model first needs it: a model reads the pairs of its kept
    /// markers, seldom all of a trial's.
    pairs: Vec<OnceLock<[f64; 9]>>,
}

/// One model's column statistics and covariance from [`Sums::covariance`].
pub(super) struct Moments {
    /// Per column (three per kept marker), its mean over the training rows, centred on the
    /// model's own mean trajectory.
    pub mean: Vec<f64>,
    /// Per column, its standard deviation over the rows (÷ rows; 1 for a constant column).
    pub sd: Vec<f64>,
    /// Σ over the rows of the columns' deviations from their means, products pairwise
    /// (cols × cols, column-major).
    pub cross: Vec<f64>,
}

impl Sums {
    /// The pass's sums: the mean trajectory and shifts now, the pairs' products on demand.
    pub(super) fn new(d: &Data) -> Sums {
        let (n, markers) = (d.frames, d.xyz.len());
        let whole: Vec<usize> = (0..markers)
            .filter(|&j| d.valid[j].iter().all(|&v| v))
            .collect();
        let mean_trj = super::frame::mean_trajectory(d, &whole);
        let mut z = Vec::with_capacity(markers);
        let mut shift = Vec::with_capacity(markers);
        let mut z1 = Vec::with_capacity(markers);
        for j in 0..markers {
            let valid = &d.valid[j];
            let y = |f: usize| {
                let (p, m) = (d.xyz[j][f], mean_trj[f]);
                [p[0] - m[0], p[1] - m[1], p[2] - m[2]]
            };
            let (mut s, mut c) = ([0.0; 3], 0usize);
            for f in (0..n).filter(|&f| valid[f]) {
                let v = y(f);
                (0..3).for_each(|k| s[k] += v[k]);
                c += 1;
            }
            let sh = s.map(|v| v / c.max(1) as f64);
            let zj: Vec<[f64; 3]> = (0..n)
                .map(|f| {
                    if valid[f] {
                        let v = y(f);
                        [v[0] - sh[0], v[1] - sh[1], v[2] - sh[2]]
                    } else {
                        [0.0; 3]
                    }
                })
                .collect();
            let mut t = [0.0; 3];
            for v in &zj {
                (0..3).for_each(|k| t[k] += v[k]);
            }
            z.push(zj);
            shift.push(sh);
            z1.push(t);
        }
        Sums {
            whole,
            z,
            shift,
            z1,
            pairs: (0..markers * markers).map(|_| OnceLock::new()).collect(),
        }
    }

    /// Σ z_a z_bᵀ over every frame for markers `a` and `b` (3 × 3, row-major).
    fn pair(&self, a: usize, b: usize) -> [f64; 9] {
        let m = self.z.len();
        let (lo, hi) = if a <= b { (a, b) } else { (b, a) };
        let s = *self.pairs[lo * m + hi].get_or_init(|| {
            let mut s = [0.0; 9];
            for (p, q) in self.z[lo].iter().zip(&self.z[hi]) {
                for r in 0..3 {
                    for c in 0..3 {
                        s[3 * r + c] += p[r] * q[c];
                    }
                }
            }
            s
        });
        if a <= b {
            s
        } else {
            [s[0], s[3], s[6], s[1], s[4], s[7], s[2], s[5], s[8]]
        }
    }

    /// The column statistics and cross products over `rows` (the frames where `on_rows` is
    /// true) of the `kept` markers, centred on the mean trajectory of `whole` (the markers
    /// the model finds recorded throughout). `None` when the downdate does not apply
    /// (`whole` holds a marker the pass's data misses somewhere) or would cost more than the
    /// product over the rows (more frames left out than kept).
    pub(super) fn covariance(
        &self,
        kept: &[usize],
        whole: &[usize],
        on_rows: &[bool],
    ) -> Option<Moments> {
        let n = on_rows.len();
        let left: Vec<usize> = (0..n).filter(|&f| !on_rows[f]).collect();
        let rn = n - left.len();
        if left.len() >= rn || whole.iter().any(|j| self.whole.binary_search(j).is_err()) {
            return None;
        }
        // The pass's whole-trial markers the model's mean trajectory lacks.
        let removed: Vec<usize> = self
            .whole
            .iter()
            .copied()
            .filter(|j| whole.binary_search(j).is_err())
            .collect();
        // The columns summed: the kept markers', then the removed markers' summed per axis
        // (e, three columns), as one list of markers with a weight each.
        let ext: Vec<usize> = kept.iter().chain(&removed).copied().collect();
        let k = kept.len();
        let c = 3 * (k + 1);
        // Full-trial sums over the kept markers and e, then the rows left out subtracted.
        let slot = |i: usize| i.min(k);
        let mut s = DMatrix::<f64>::zeros(c, c);
        let mut s1 = vec![0.0; c];
        for (i, &a) in ext.iter().enumerate() {
            for (l, &b) in ext.iter().enumerate() {
                let p = self.pair(a, b);
                let (ia, lb) = (3 * slot(i), 3 * slot(l));
                for r in 0..3 {
                    for q in 0..3 {
                        s[(ia + r, lb + q)] += p[3 * r + q];
                    }
                }
            }
            for r in 0..3 {
                s1[3 * slot(i) + r] += self.z1[a][r];
            }
        }
        // The rows left out, with the missing samples as the sums counted them (0).
        let mut zl = DMatrix::<f64>::zeros(left.len(), c);
        for (i, &a) in ext.iter().enumerate() {
            for r in 0..3 {
                let mut col = zl.column_mut(3 * slot(i) + r);
                for (v, &f) in col.iter_mut().zip(&left) {
                    *v += self.z[a][f][r];
                }
            }
        }
        s -= zl.transpose() * &zl;
        for (t, col) in s1.iter_mut().zip(zl.column_iter()) {
            *t -= col.iter().sum::<f64>();
        }
        // The model's columns: u_a = z_a + g e_ax, g = 1 / |whole|, its coordinates less a
        // constant (the shift and g Σ_R shift).
        let g = if removed.is_empty() {
            0.0
        } else {
            1.0 / whole.len() as f64
        };
        let cols = 3 * k;
        let e = |ax: usize| 3 * k + ax;
        let mut u1 = vec![0.0; cols];
        let mut cross = vec![0.0; cols * cols];
        for a in 0..cols {
            u1[a] = s1[a] + g * s1[e(a % 3)];
        }
        for a in 0..cols {
            for b in 0..cols {
                let (ea, eb) = (e(a % 3), e(b % 3));
                let uu = s[(a, b)] + g * (s[(a, eb)] + s[(ea, b)]) + g * g * s[(ea, eb)];
                cross[b * cols + a] = uu - u1[a] * u1[b] / rn as f64;
            }
        }
        let h: Vec<f64> = (0..3)
            .map(|ax| removed.iter().map(|&j| self.shift[j][ax]).sum::<f64>())
            .collect();
        let mean: Vec<f64> = (0..cols)
            .map(|a| u1[a] / rn as f64 + self.shift[kept[a / 3]][a % 3] + g * h[a % 3])
            .collect();
        // A constant column's variance comes out as rounding, not 0 (a kept marker that is
        // the model's whole mean trajectory, for one, is 0 throughout only in exact
        // arithmetic): below 1e-12 of the terms it was summed from, it is taken as constant,
        // as the product over the rows finds it (standard deviation 1, no cross products).
        let constant: Vec<bool> = (0..cols)
            .map(|a| {
                let ea = e(a % 3);
                let terms = s[(a, a)] + 2.0 * g * s[(a, ea)].abs() + g * g * s[(ea, ea)];
                cross[a * cols + a] <= 1e-12 * terms
            })
            .collect();
        for a in (0..cols).filter(|&a| constant[a]) {
            for b in 0..cols {
                cross[a * cols + b] = 0.0;
                cross[b * cols + a] = 0.0;
            }
        }
        let sd: Vec<f64> = (0..cols)
            .map(|a| {
                if constant[a] {
                    1.0
                } else {
                    (cross[a * cols + a] / rn as f64).sqrt()
                }
            })
            .collect();
        Some(Moments { mean, sd, cross })
    }
}

#[cfg(test)]
mod tests {
    use super::super::super::data::Data;
    use super::Sums;

    /// The downdated statistics equal those over the rows directly, to rounding: on a walking
    /// trial with gaps in several markers, a model whose mean trajectory lacks two of the
    /// pass's complete markers (as the target and, in the second pass, the marker read as
    /// recorded make it) and whose rows leave out a tenth of the frames.
    #[test]
    fn downdate_equals_the_sums_over_the_rows() {
        let trial = crate::synth::gait_like(12, 6, 600, 100.0, 0.3, 5);
        let mut valid = trial.valid.clone();
        valid[0][100..140].fill(false);
        valid[3][300..320].fill(false);
        valid[5][50..55].fill(false);
        let steps = vec![f64::INFINITY; 12];
        let d = Data::new(&trial.xyz, &valid, &steps);
        let sums = Sums::new(&d);
        let n = 600;
        // The model's view: marker 7 (complete in the pass) has an artificial hole, so the
        // mean trajectory lacks it and marker 9 (as a second pass's own marker would be).
        let whole: Vec<usize> = sums
            .whole
            .iter()
            .copied()
            .filter(|&j| j != 7 && j != 9)
            .collect();
        assert_eq!(whole.len(), sums.whole.len() - 2);
        let kept = [0, 2, 3, 7, 9];
        let on_rows: Vec<bool> = (0..n)
            .map(|f| kept.iter().all(|&j| valid[j][f]) && !(400..430).contains(&f))
            .collect();
        let rows: Vec<usize> = (0..n).filter(|&f| on_rows[f]).collect();
        let got = sums.covariance(&kept, &whole, &on_rows).expect("applies");
        // Directly: coordinates less the model's mean trajectory, over the rows.
        let y = |j: usize, f: usize, ax: usize| {
            let m = whole.iter().map(|&w| trial.xyz[w][f][ax]).sum::<f64>() / whole.len() as f64;
            trial.xyz[j][f][ax] - m
        };
        let cols = 3 * kept.len();
        let rn = rows.len() as f64;
        let col =
            |c: usize| -> Vec<f64> { rows.iter().map(|&f| y(kept[c / 3], f, c % 3)).collect() };
        let cs: Vec<Vec<f64>> = (0..cols).map(col).collect();
        let mean: Vec<f64> = cs.iter().map(|v| v.iter().sum::<f64>() / rn).collect();
        let sd: Vec<f64> = (0..cols)
            .map(|a| (cs[a].iter().map(|v| (v - mean[a]).powi(2)).sum::<f64>() / rn).sqrt())
            .collect();
        for a in 0..cols {
            assert!(
                (got.mean[a] - mean[a]).abs() < 1e-9 * (1.0 + mean[a].abs()),
                "mean {a}"
            );
            assert!((got.sd[a] - sd[a]).abs() < 1e-9 * sd[a], "sd {a}");
            for b in 0..cols {
                let want: f64 = cs[a]
                    .iter()
                    .zip(&cs[b])
                    .map(|(p, q)| (p - mean[a]) * (q - mean[b]))
                    .sum();
                let g = got.cross[b * cols + a];
                assert!(
                    (g - want).abs() < 1e-9 * rn * sd[a] * sd[b],
                    "cross {a} {b}: {g} {want}"
                );
            }
        }
        // A model whose mean trajectory is one kept marker: its columns are 0 throughout, so
        // constant (standard deviation 1, no cross products), as over the rows directly.
        let one = [sums.whole[0]];
        let kept1 = [0, one[0]];
        let got1 = sums.covariance(&kept1, &one, &on_rows).expect("applies");
        for a in 3..6 {
            assert_eq!(got1.sd[a], 1.0);
            assert!(got1.mean[a].abs() < 1e-9, "{}", got1.mean[a]);
            for b in 0..6 {
                assert_eq!(got1.cross[b * 6 + a], 0.0);
            }
        }
        assert!(got1.sd[..3].iter().all(|&v| v > 1.0));
        // More frames left out than kept: the product over the rows is cheaper.
        let few: Vec<bool> = (0..n).map(|f| f < 200).collect();
        assert!(sums.covariance(&kept, &whole, &few).is_none());
    }
}
