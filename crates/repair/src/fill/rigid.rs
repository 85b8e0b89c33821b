//! Rigid-body fill: the target keeps its place in the frame of donor markers that move
//! rigidly with it. Its position in that frame is averaged over reference frames near the
//! gap; each gap frame gets a least-squares (Kabsch) donor transform; the remaining drift is
//! removed by blending the anchor errors across the gap.

use super::anchor::Raw;
use super::data::{Span, Target};
use super::donors::Donors;
use super::outcome::SkipReason;
use crate::linalg::kabsch;

/// Reference frames per side.
const REFS: usize = 10;
/// How far from the gap reference frames are looked for.
const REF_REACH: usize = 200;

/// The rigid prediction over the span, with residuals at up to `per_side` frames per side
/// (see [`Raw`]).
pub(super) fn raw(
    t: &Target,
    span: Span,
    plan: &Donors,
    per_side: usize,
) -> Result<Raw, SkipReason> {
    let donors = &plan.rigid;
    let d = t.data;
    let (lo, hi) = span.outer();
    if donors.len() < 3 || !donors.iter().all(|&j| d.ok_through(j, lo, hi)) {
        return Err(SkipReason::NoDonors);
    }
    let usable = |f: usize| t.ok(f) && donors.iter().all(|&j| d.ok(j, f));
    let mut refs: Vec<usize> = (span.first.saturating_sub(REF_REACH)..span.first)
        .rev()
        .filter(|&f| usable(f))
        .take(REFS)
        .collect();
    refs.extend(
        (span.last + 1..(span.last + 1 + REF_REACH).min(d.frames))
            .filter(|&f| usable(f))
            .take(REFS),
    );
    let Some(&r0) = refs.first() else {
        return Err(SkipReason::NoContext);
    };
    let cluster = |f: usize, out: &mut Vec<[f64; 3]>| {
        out.clear();
        out.extend(donors.iter().map(|&j| d.at(j, f)));
    };
    let mut canon = Vec::with_capacity(donors.len());
    cluster(r0, &mut canon);
    let mut buf = Vec::with_capacity(donors.len());
    let mut local = [0.0; 3];
    // The reference frames' transforms, kept: they are the residual frames next to the gap.
    let mut known = Vec::with_capacity(refs.len());
    for &r in &refs {
        cluster(r, &mut buf);
        let tr = kabsch(&canon, &buf).ok_or(SkipReason::Degenerate)?;
        let l = tr.apply_inverse(t.at(r));
        for k in 0..3 {
            local[k] += l[k] / refs.len() as f64;
        }
        known.push((r, tr));
    }
    let predict = |f: usize| {
        if let Some((_, tr)) = known.iter().find(|x| x.0 == f) {
            return Some(tr.apply(local));
        }
        if !donors.iter().all(|&j| d.ok(j, f)) {
            return None;
        }
        cluster(f, &mut buf);
        kabsch(&canon, &buf).map(|tr| tr.apply(local))
    };
    Raw::gather(t, span, per_side, predict).ok_or(SkipReason::Degenerate)
}

#[cfg(test)]
pub(crate) mod tests {
    use super::super::test_util::*;
    use super::super::FillMethod;
    use nalgebra::{Rotation3, Vector3};

    /// Five markers of one rigid body under a random-looking rotation and translation per
    /// frame; marker 0 is the target.
    pub fn rigid_cluster(frames: usize) -> Vec<Vec<[f64; 3]>> {
        let local = [
            [10.0, 20.0, 30.0],
            [0.0, 0.0, 0.0],
            [100.0, 0.0, 0.0],
            [0.0, 80.0, 10.0],
            [-30.0, 40.0, 90.0],
        ];
        let mut out = vec![Vec::with_capacity(frames); local.len()];
        let mut s = 0x1234_5678_u64;
        let mut next = || {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (s >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        };
        for f in 0..frames {
            let tt = f as f64 * 0.05;
            let rot = Rotation3::from_euler_angles(
                tt.sin() + 0.3 * next(),
                0.5 * tt.cos() + 0.3 * next(),
                tt + 0.3 * next(),
            );
            let tr = Vector3::new(500.0 * tt.sin(), 300.0 * next(), 1000.0 + 50.0 * next());
            for (m, l) in local.iter().enumerate() {
                let p = rot * Vector3::from(*l) + tr;
                out[m].push([p.x, p.y, p.z]);
            }
        }
        out
    }

    #[test]
    fn rigid_cluster_is_exact() {
        let truth = rigid_cluster(200);
        let (xyz, valid) = with_gap(truth.clone(), 80, 139);
        let v = fill(&xyz, &valid, 80, 139, FillMethod::Rigid).unwrap();
        assert!(max_err(&v, |f| truth[0][f], 80) < 1e-9);
        let s = fill(&xyz, &valid, 80, 139, FillMethod::Spline).unwrap();
        assert!(max_err(&s, |f| truth[0][f], 80) > 10.0);
        // At the trial's start: no polynomial, but rigid fills from the following frames.
        let (xyz, valid) = with_gap(truth.clone(), 0, 29);
        let v = fill(&xyz, &valid, 0, 29, FillMethod::Rigid).unwrap();
        assert!(max_err(&v, |f| truth[0][f], 0) < 1e-9);
    }

    #[test]
    fn pca_reconstructs_rigid_cluster() {
        let truth = rigid_cluster(400);
        let (xyz, valid) = with_gap(truth.clone(), 150, 209);
        let v = fill(&xyz, &valid, 150, 209, FillMethod::Pca).unwrap();
        let e = max_err(&v, |f| truth[0][f], 150);
        assert!(e < 2.0, "pca max error {e}");
        let s = fill(&xyz, &valid, 150, 209, FillMethod::Spline).unwrap();
        assert!(max_err(&s, |f| truth[0][f], 150) > 10.0 * e.max(0.1));
    }

    #[test]
    fn pattern_follows_donor_shape() {
        // Target = donor + 5 mm offset changing linearly: pattern is exact.
        let n = 100;
        let donor: Vec<[f64; 3]> = (0..n)
            .map(|f| {
                let x = f as f64 * 0.1;
                [50.0 * x.sin(), 20.0 * (2.0 * x).cos(), x]
            })
            .collect();
        let target: Vec<[f64; 3]> = donor
            .iter()
            .enumerate()
            .map(|(f, p)| [p[0] + 5.0 + 0.01 * f as f64, p[1], p[2] - 3.0])
            .collect();
        let far: Vec<[f64; 3]> = (0..n).map(|f| [1000.0, f as f64, 0.0]).collect();
        let truth = vec![target, donor.clone(), far.clone(), far];
        let (xyz, valid) = with_gap(truth.clone(), 40, 69);
        let v = fill(&xyz, &valid, 40, 69, FillMethod::Pattern).unwrap();
        assert!(max_err(&v, |f| truth[0][f], 40) < 1e-9);
    }
}
