//! What every model of one target in one pass's data shares before its own holes enter:
//! the markers recorded throughout (step 1's frame), their mean trajectory, and each other
//! marker's distance to the target summed over the frames both are recorded on.
//!
//! A model's holes take frames from its target only, so they change neither which other
//! markers are recorded throughout nor where they are; they change only which frames a
//! marker's mean distance to the target is taken over. Each model summed the distances
//! over every frame again (on 03_rolling, 68 markers × 2 305 frames per model, the models'
//! largest part after the covariance, `docs/price.md`), for the handful of models a target
//! has per pass. Here the sums over every frame the target is recorded on are made once
//! per target, and a model takes off its holes' frames (a few per cent of the trial, their
//! distances worked out again): the same means to rounding, not to the bit (the held-apart
//! evaluation's figures are in `docs/price.md`). Only the sums are kept, not the distances
//! frame by frame, so a pass holds every target's frame.

use super::super::data::Data;
use std::sync::Arc;

/// One target's frame in one pass's data (see the module's documentation).
pub(super) struct TargetFrame {
    /// Per marker, whether the pass's data records it on every frame (the target's own
    /// entry is not read: a model's target has its holes).
    pub complete: Vec<bool>,
    /// The markers other than the target recorded on every frame.
    pub whole: Vec<usize>,
    /// Their mean trajectory, per frame.
    pub mean_trj: Arc<Vec<[f64; 3]>>,
    /// The target's coordinates less the mean trajectory, per frame.
    target: Vec<[f64; 3]>,
    /// Per marker, the sum of its distances to the target (see [`TargetFrame::dist`]) over
    /// the frames both are recorded on, in frame order, and their count; (0, 0) for the
    /// target itself.
    total: Vec<(f64, usize)>,
    /// The frames the target is recorded on.
    recorded: Vec<bool>,
}

impl TargetFrame {
    /// Target `m`'s frame in `d`; `None` when no other marker is recorded throughout (the
    /// model has no frame to subtract).
    pub(super) fn new(d: &Data, m: usize) -> Option<TargetFrame> {
        let (n, markers) = (d.frames, d.xyz.len());
        let complete: Vec<bool> = (0..markers).map(|j| d.row(j).iter().all(|&o| o)).collect();
        let whole: Vec<usize> = (0..markers).filter(|&j| complete[j] && j != m).collect();
        if whole.is_empty() {
            return None;
        }
        let mean_trj = mean_trajectory(d, &whole);
        let target: Vec<[f64; 3]> = (0..n)
            .map(|f| {
                let (p, mt) = (d.xyz[m][f], mean_trj[f]);
                [p[0] - mt[0], p[1] - mt[1], p[2] - mt[2]]
            })
            .collect();
        let mut frame = TargetFrame {
            complete,
            whole,
            mean_trj: Arc::new(mean_trj),
            target,
            total: Vec::new(),
            recorded: d.row(m).to_vec(),
        };
        frame.total = (0..markers)
            .map(|j| {
                if j == m {
                    return (0.0, 0);
                }
                let (mut s, mut c) = (0.0, 0usize);
                for (f, (&t, &v)) in frame.recorded.iter().zip(d.row(j)).enumerate() {
                    if t && v {
                        s += frame.dist(d.xyz, j, f);
                        c += 1;
                    }
                }
                (s, c)
            })
            .collect();
        Some(frame)
    }

    /// Marker `j`'s distance to the target at frame `f`, both less the mean trajectory.
    fn dist(&self, xyz: &[Vec<[f64; 3]>], j: usize, f: usize) -> f64 {
        let (p, mt, q) = (xyz[j][f], self.mean_trj[f], self.target[f]);
        let a = [p[0] - mt[0], p[1] - mt[1], p[2] - mt[2]];
        ((a[0] - q[0]).powi(2) + (a[1] - q[1]).powi(2) + (a[2] - q[2]).powi(2)).sqrt()
    }

    /// Bytes the frame holds, for the cache's bound.
    pub(super) fn bytes(&self) -> usize {
        self.mean_trj.len() * 49 + self.total.len() * 17
    }

    /// Each marker's mean distance to target `m` over the frames both are recorded
    /// (`valid`: each marker's validity as the model reads it, the target's `target_ok`,
    /// which lies within the frames the target is recorded on; `xyz` the coordinates of the
    /// data the frame was made from): the sums over every such frame less the frames
    /// `target_ok` takes away. The target's own is 0, and a marker never recorded with it
    /// has none.
    pub(super) fn mean_distances(
        &self,
        xyz: &[Vec<[f64; 3]>],
        valid: &[&[bool]],
        m: usize,
        target_ok: &[bool],
    ) -> Vec<Option<f64>> {
        let removed: Vec<usize> = (0..target_ok.len())
            .filter(|&f| self.recorded[f] && !target_ok[f])
            .collect();
        (0..self.total.len())
            .map(|j| {
                if j == m {
                    return Some(0.0);
                }
                let (mut s, mut c) = self.total[j];
                for &f in &removed {
                    if valid[j][f] {
                        s -= self.dist(xyz, j, f);
                        c -= 1;
                    }
                }
                (c > 0).then(|| s.max(0.0) / c as f64)
            })
            .collect()
    }
}

/// The mean trajectory of the markers `whole` (recorded on every frame): step 1's frame moving
/// with the subject, which the pass's sums ([`super::sums`]) and each model's own preparation both
/// subtract. An empty `whole` gives zeros.
pub(super) fn mean_trajectory(d: &Data, whole: &[usize]) -> Vec<[f64; 3]> {
    (0..d.frames)
        .map(|f| {
            let mut s = [0.0; 3];
            for &j in whole {
                let p = d.xyz[j][f];
                (0..3).for_each(|k| s[k] += p[k]);
            }
            s.map(|v| v / whole.len().max(1) as f64)
        })
        .collect()
}
