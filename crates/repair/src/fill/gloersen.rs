//! Gløersen & Federolf's PCA fill as published (PLOS ONE 11(3): e0152616, 2016, strategy
//! R2 of its supplementary code, with its defaults): the whole trial, every marker, their
//! distance weighting and their reconstruction, and no tie to the gap's anchors.
//!
//! 1. The mean trajectory of the markers recorded on every frame is subtracted from every
//!    marker (a frame moving with the subject).
//! 2. Markers farther from the target than half the mean distance of all markers to it,
//!    and missing somewhere, are left out, as are markers missing on any of the target's
//!    missing frames.
//! 3. On the frames where every remaining marker is recorded, each coordinate is
//!    normalised to zero mean and unit variance and weighted by exp(−d² / 2σ²), d the
//!    marker's mean distance to the target and σ = 200 mm; the target's own weight is
//!    0.02.
//! 4. Principal components of these frames, and of the same frames with the target set to
//!    zero, each kept up to 99 % of the cumulative sum of singular values (the larger count
//!    of the two). The target's missing frames, with the target set to zero, are projected
//!    on the second set, carried into the first by their product (Federolf 2013), and read
//!    back with the normalisation and weights undone.
//!
//! It differs from `pca`, which fits the nearest markers over a window around the gap and
//! ties the prediction to the gap's anchors.

use super::{SkipReason, Span, Target};
use crate::linalg::symmetric_eigen;

/// σ of the distance weighting, in mm (the paper's default).
const WEIGHT_SCALE_MM: f64 = 200.0;
/// The target's own weight (the paper's default).
const MM_WEIGHT: f64 = 0.02;
/// Markers farther than this share of the mean distance are left out when they miss
/// samples (the paper's default).
const DISTAL_THRESHOLD: f64 = 0.5;
/// Share of the cumulative sum of singular values the kept components reach.
const MIN_CUM_SV: f64 = 0.99;

/// The target's fill over `span` (`mm_per_unit` converts σ to the data's units).
pub(super) fn fill(t: &Target, span: Span, mm_per_unit: f64) -> Result<Vec<[f64; 3]>, SkipReason> {
    let d = t.data;
    let (n, markers) = (d.frames, d.xyz.len());
    let ok = |j: usize, f: usize| if j == t.m { t.ok(f) } else { d.ok(j, f) };
    let complete: Vec<bool> = (0..markers).map(|j| (0..n).all(|f| ok(j, f))).collect();
    // 1. The mean trajectory of the markers recorded throughout.
    let whole: Vec<usize> = (0..markers).filter(|&j| complete[j] && j != t.m).collect();
    if whole.is_empty() {
        return Err(SkipReason::NoDonors);
    }
    let mean_trj: Vec<[f64; 3]> = (0..n)
        .map(|f| {
            let mut s = [0.0; 3];
            for &j in &whole {
                let p = d.at(j, f);
                (0..3).for_each(|k| s[k] += p[k]);
            }
            s.map(|v| v / whole.len() as f64)
        })
        .collect();
    let at = |j: usize, f: usize| {
        let p = d.at(j, f);
        [0, 1, 2].map(|k| p[k] - mean_trj[f][k])
    };
    let dist = |a: [f64; 3], b: [f64; 3]| {
        ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
    };
    // Mean distance of each marker to the target over the frames both are recorded.
    let mean_dist = |j: usize, frames: &mut dyn Iterator<Item = usize>| -> Option<f64> {
        let (mut s, mut c) = (0.0, 0usize);
        for f in frames {
            if ok(j, f) && ok(t.m, f) {
                s += dist(at(j, f), at(t.m, f));
                c += 1;
            }
        }
        (c > 0).then(|| s / c as f64)
    };
    let dists: Vec<Option<f64>> = (0..markers)
        .map(|j| {
            if j == t.m {
                Some(0.0)
            } else {
                mean_dist(j, &mut (0..n))
            }
        })
        .collect();
    let known: Vec<f64> = dists.iter().flatten().copied().collect();
    let thresh = DISTAL_THRESHOLD * known.iter().sum::<f64>() / known.len().max(1) as f64;
    // 2. The markers kept: the target, and every other marker that is near or recorded
    // throughout, and recorded on each of the target's missing frames.
    let missing: Vec<usize> = (0..n).filter(|&f| !ok(t.m, f)).collect();
    let kept: Vec<usize> = (0..markers)
        .filter(|&j| {
            j == t.m
                || (dists[j].is_some_and(|x| x <= thresh || complete[j])
                    && missing.iter().all(|&f| ok(j, f)))
        })
        .collect();
    if kept.len() < 2 {
        return Err(SkipReason::NoDonors);
    }
    let rows: Vec<usize> = (0..n).filter(|&f| kept.iter().all(|&j| ok(j, f))).collect();
    if rows.len() < 2 {
        return Err(SkipReason::NoContext);
    }
    // 3. Weights from distances over the frames of the reconstruction (the complete rows
    // and the target's missing ones).
    let sigma = WEIGHT_SCALE_MM / mm_per_unit;
    let w: Vec<f64> = kept
        .iter()
        .map(|&j| {
            if j == t.m {
                return MM_WEIGHT;
            }
            let dj = mean_dist(j, &mut rows.iter().copied()).unwrap_or(f64::INFINITY);
            (-(dj * dj) / (2.0 * sigma * sigma)).exp()
        })
        .collect();
    let cols = 3 * kept.len();
    let ti = kept.iter().position(|&j| j == t.m).unwrap_or(0);
    let raw = |f: usize| -> Vec<f64> { kept.iter().flat_map(|&j| at(j, f)).collect() };
    let mut mean = vec![0.0; cols];
    let xs: Vec<Vec<f64>> = rows.iter().map(|&f| raw(f)).collect();
    for x in &xs {
        mean.iter_mut().zip(x).for_each(|(m, v)| *m += v);
    }
    mean.iter_mut().for_each(|m| *m /= xs.len() as f64);
    let mut sd = vec![0.0; cols];
    for x in &xs {
        sd.iter_mut()
            .zip(x.iter().zip(&mean))
            .for_each(|(s, (v, m))| *s += (v - m).powi(2));
    }
    sd.iter_mut().for_each(|s| {
        *s = (*s / xs.len() as f64).sqrt();
        if *s == 0.0 {
            *s = 1.0;
        }
    });
    let wc = |c: usize| w[c / 3];
    let is_target = |c: usize| c / 3 == ti;
    // Normalised, weighted rows; with the target zeroed (its mean with it, as the paper's
    // matrices with zeros have zero mean there).
    let norm = |x: &[f64], zero: bool| -> Vec<f64> {
        (0..cols)
            .map(|c| {
                if zero && is_target(c) {
                    0.0
                } else {
                    (x[c] - mean[c]) / sd[c] * wc(c)
                }
            })
            .collect()
    };
    let n_no: Vec<Vec<f64>> = xs.iter().map(|x| norm(x, false)).collect();
    let n_zero: Vec<Vec<f64>> = xs.iter().map(|x| norm(x, true)).collect();
    // 4. Principal components by the eigenvectors of YᵀY, Y = X / √(n − 1): its singular
    // values are the square roots of the eigenvalues.
    let pca = |m: &[Vec<f64>]| {
        let mut c = vec![0.0; cols * cols];
        let s = 1.0 / (m.len() as f64 - 1.0);
        for r in m {
            for i in 0..cols {
                if r[i] == 0.0 {
                    continue;
                }
                let ri = r[i] * s;
                for j in i..cols {
                    c[i * cols + j] += ri * r[j];
                }
            }
        }
        for i in 0..cols {
            for j in 0..i {
                c[i * cols + j] = c[j * cols + i];
            }
        }
        let (vals, vecs) = symmetric_eigen(&c, cols);
        let sv: Vec<f64> = vals.iter().map(|v| v.max(0.0).sqrt()).collect();
        let total: f64 = sv.iter().sum();
        let mut acc = 0.0;
        let k = sv
            .iter()
            .position(|v| {
                acc += v;
                acc >= MIN_CUM_SV * total
            })
            .unwrap_or(cols - 1);
        (vecs, k)
    };
    let (p_no, k1) = pca(&n_no);
    let (p_zero, k2) = pca(&n_zero);
    let k = k1.max(k2) + 1;
    // T = P_noᵀ P_zero (k × k).
    let mut tm = vec![0.0; k * k];
    for a in 0..k {
        for b in 0..k {
            tm[a * k + b] = (0..cols).map(|c| p_no[(c, a)] * p_zero[(c, b)]).sum();
        }
    }
    let out = (span.first..=span.last)
        .map(|f| {
            if !missing.contains(&f) {
                return Err(SkipReason::NoContext);
            }
            let mz = norm(&raw_zeroed(&kept, t.m, f, &at), true);
            // Scores on the zeroed components, carried into the complete ones.
            let s: Vec<f64> = (0..k)
                .map(|b| (0..cols).map(|c| mz[c] * p_zero[(c, b)]).sum())
                .collect();
            let u: Vec<f64> = (0..k)
                .map(|a| (0..k).map(|b| tm[a * k + b] * s[b]).sum())
                .collect();
            let mut p = [0.0; 3];
            for (ax, v) in p.iter_mut().enumerate() {
                let c = 3 * ti + ax;
                let r: f64 = (0..k).map(|a| u[a] * p_no[(c, a)]).sum();
                *v = mean[c] + r * sd[c] / wc(c) + mean_trj[f][ax];
            }
            Ok(p)
        })
        .collect::<Result<Vec<_>, _>>()?;
    Ok(out)
}

/// The kept markers' centred coordinates at frame `f`, the target's set to zero (it is
/// missing there).
fn raw_zeroed(
    kept: &[usize],
    m: usize,
    f: usize,
    at: &dyn Fn(usize, usize) -> [f64; 3],
) -> Vec<f64> {
    kept.iter()
        .flat_map(|&j| if j == m { [0.0; 3] } else { at(j, f) })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::super::test_util::{fill, max_err, with_gap};
    use super::super::FillMethod;

    /// Markers that move together (a segment swinging while the body walks on, with two
    /// independent motions) are reconstructed from the others' correlations across a
    /// 60-frame gap, far from where a line across the gap would put the target.
    #[test]
    fn reconstructs_a_marker_from_the_others_correlations() {
        let n = 400;
        let truth = |m: usize, f: usize| {
            let t = f as f64 / 100.0;
            let (a, b) = ((2.0 * t).sin(), (3.1 * t).cos());
            let offs = [
                [0.0, 100.0, 0.0],
                [80.0, 0.0, 20.0],
                [-60.0, 40.0, 90.0],
                [30.0, -70.0, 50.0],
                [10.0, 10.0, -80.0],
            ];
            let o = offs[m];
            [
                1000.0 * t + o[0] * (1.0 + 0.3 * a) + 5.0 * b * o[2] / 100.0,
                o[1] * (1.0 + 0.2 * b) + 3.0 * a,
                900.0 + o[2] + 40.0 * a * o[0] / 100.0,
            ]
        };
        let xyz: Vec<Vec<[f64; 3]>> = (0..5)
            .map(|m| (0..n).map(|f| truth(m, f)).collect())
            .collect();
        let (xyz, valid) = with_gap(xyz, 170, 229);
        let v = fill(&xyz, &valid, 170, 229, FillMethod::Gloersen).expect("filled");
        let err = max_err(&v, |f| truth(0, f), 170);
        assert!(err < 1.0, "largest error {err} mm");
        let line = fill(&xyz, &valid, 170, 229, FillMethod::Linear).expect("line");
        assert!(max_err(&line, |f| truth(0, f), 170) > 20.0 * err);
    }
}
