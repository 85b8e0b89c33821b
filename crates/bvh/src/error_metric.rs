//! How far an interpolated motion is from the original: per frame, the sum of squared
//! Euclidean distances between matching points (End Sites, or all joints and End Sites).
//!
//! Leaf joints without an End Site count as end effectors, so that skeletons written without
//! End Sites still have something to measure.

use crate::fk::{world_pose, LocalPose, Pose};
use crate::interp::Interpolator;
use crate::skeleton::{Skeleton, Vec3};

/// Which points the error compares.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Effectors {
    /// End Sites, plus leaf joints that have none.
    EndSites,
    /// Every joint and every End Site.
    AllJoints,
}

/// Append the compared points of `pose` to `out`.
pub fn effector_points(
    skeleton: &Skeleton,
    leaf: &[bool],
    pose: &Pose,
    which: Effectors,
    out: &mut Vec<Vec3>,
) {
    for (j, joint) in skeleton.joints.iter().enumerate() {
        let all = which == Effectors::AllJoints;
        if all || (leaf[j] && joint.end_site.is_none()) {
            out.push(pose.positions[j]);
        }
        if let Some(e) = pose.end_sites[j] {
            out.push(e);
        }
    }
}

/// Sum of squared distances between two equally long point lists.
pub fn squared_distance_sum(a: &[Vec3], b: &[Vec3]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(p, q)| {
            let d = [p[0] - q[0], p[1] - q[1], p[2] - q[2]];
            d[0] * d[0] + d[1] * d[1] + d[2] * d[2]
        })
        .sum()
}

/// Per-frame error of an interpolated motion, with the original's points computed once.
#[derive(Debug, Clone)]
pub struct Evaluator<'a> {
    interp: Interpolator<'a>,
    which: Effectors,
    leaf: Vec<bool>,
    /// Points per frame.
    points: usize,
    /// `frames × points` original positions.
    original: Vec<Vec3>,
}

/// Reusable buffers, so evaluating a frame does not allocate.
#[derive(Debug, Clone, Default)]
pub struct Scratch {
    local: Option<LocalPose>,
    pose: Pose,
    points: Vec<Vec3>,
}

impl<'a> Evaluator<'a> {
    pub fn new(interp: Interpolator<'a>, which: Effectors) -> Self {
        let bvh = interp.bvh();
        let skeleton = &bvh.skeleton;
        let leaf = skeleton.is_leaf();
        let mut original = Vec::new();
        let mut pose = Pose::default();
        let mut points = 0;
        for f in 0..bvh.motion.frames() {
            let local = crate::fk::local_pose(skeleton, bvh.motion.frame(f));
            world_pose(skeleton, &local, &mut pose);
            let before = original.len();
            effector_points(skeleton, &leaf, &pose, which, &mut original);
            points = original.len() - before;
        }
        Evaluator {
            interp,
            which,
            leaf,
            points,
            original,
        }
    }

    pub fn interpolator(&self) -> &Interpolator<'a> {
        &self.interp
    }

    /// Number of compared points per frame.
    pub fn points_per_frame(&self) -> usize {
        self.points
    }

    pub fn frames(&self) -> usize {
        self.interp.bvh().motion.frames()
    }

    /// Error of frame `t` when interpolated between keys `a` and `b`.
    pub fn frame_error(&self, a: usize, b: usize, t: usize, s: &mut Scratch) -> f64 {
        let skeleton = &self.interp.bvh().skeleton;
        let local = s.local.get_or_insert_with(|| LocalPose {
            translations: Vec::new(),
            rotations: Vec::new(),
        });
        self.interp.local_pose(a, b, t, local);
        world_pose(skeleton, local, &mut s.pose);
        s.points.clear();
        effector_points(skeleton, &self.leaf, &s.pose, self.which, &mut s.points);
        let orig = &self.original[t * self.points..(t + 1) * self.points];
        squared_distance_sum(orig, &s.points)
    }

    /// Total error of the frames strictly between keys `a` and `b`. Stops early and returns a
    /// value above `bound` once the partial sum exceeds it (pass `f64::INFINITY` for the exact
    /// sum). Frames are visited from the middle outwards, where errors are usually largest, so
    /// that hopeless segments are rejected after few evaluations.
    pub fn segment_cost(&self, a: usize, b: usize, bound: f64, s: &mut Scratch) -> f64 {
        if b <= a + 1 {
            return 0.0;
        }
        let mid = (a + b) / 2;
        let mut sum = 0.0;
        let (mut lo, mut hi) = (mid, mid + 1);
        loop {
            let mut moved = false;
            if lo > a {
                sum += self.frame_error(a, b, lo, s);
                lo -= 1;
                moved = true;
            }
            if hi < b {
                sum += self.frame_error(a, b, hi, s);
                hi += 1;
                moved = true;
            }
            if !moved || sum > bound {
                return sum;
            }
        }
    }

    /// Per-frame errors of the motion rebuilt from `keys` (sorted, first and last frame
    /// included); key frames have zero error.
    pub fn frame_errors(&self, keys: &[usize]) -> Vec<f64> {
        let mut out = vec![0.0; self.frames()];
        let mut s = Scratch::default();
        for w in keys.windows(2) {
            for (t, slot) in out.iter_mut().enumerate().take(w[1]).skip(w[0] + 1) {
                *slot = self.frame_error(w[0], w[1], t, &mut s);
            }
        }
        out
    }
}
