//! How far an interpolated motion is from the original: per frame, the sum of squared
//! Euclidean distances between matching points (End Sites, or all joints and End Sites).
//!
//! Leaf joints without an End Site count as end effectors, so that skeletons written without
//! End Sites still have something to measure.

use crate::fk::{world_pose, LocalPose, Pose};
use crate::interp::Interpolator;
use crate::rotation::{shortest_relative, Quat};
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
    /// The compared points as (joint, End Site offset or `None` for the joint itself), in the
    /// order of `effector_points`.
    effectors: Vec<(usize, Option<Vec3>)>,
    /// Per joint, its range in the list of rotation factors (see [`Factor`]).
    factor_range: Vec<std::ops::Range<usize>>,
    factors: Vec<Factor>,
}

/// One quaternion factor of a joint's interpolated local rotation. Along a segment each factor
/// turns by the same step every frame, which is what lets a segment be walked with one
/// quaternion product per factor instead of trigonometry per frame.
#[derive(Debug, Clone, Copy)]
enum Factor {
    /// The joint's whole rotation, slerped.
    Slerp { joint: usize },
    /// One Euler channel (column in the frame, axis), interpolated linearly in degrees.
    Angle { column: usize, axis: usize },
}

/// Reusable buffers, so evaluating a frame does not allocate.
#[derive(Debug, Clone, Default)]
pub struct Scratch {
    local: Option<LocalPose>,
    pose: Pose,
    points: Vec<Vec3>,
    /// Segment walk: per joint, local translation at the first key and its change to the last.
    t0: Vec<Vec3>,
    dt: Vec<Vec3>,
    /// Per factor: the rotation step per sample, and the current value of each walker.
    step: Vec<Quat>,
    down: Vec<Quat>,
    up: Vec<Quat>,
    /// World transforms of the frame being evaluated.
    pos: Vec<Vec3>,
    rot: Vec<Quat>,
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
        let mut effectors = Vec::new();
        let mut factor_range = Vec::new();
        let mut factors = Vec::new();
        for (j, joint) in skeleton.joints.iter().enumerate() {
            if which == Effectors::AllJoints || (leaf[j] && joint.end_site.is_none()) {
                effectors.push((j, None));
            }
            if let Some(e) = joint.end_site {
                effectors.push((j, Some(e)));
            }
            let start = factors.len();
            if interp.is_slerped(j) {
                factors.push(Factor::Slerp { joint: j });
            } else {
                for (k, ch) in joint.channels.iter().enumerate() {
                    if ch.is_rotation() {
                        factors.push(Factor::Angle {
                            column: joint.first_channel + k,
                            axis: ch.axis(),
                        });
                    }
                }
            }
            factor_range.push(start..factors.len());
        }
        Evaluator {
            interp,
            which,
            leaf,
            points,
            original,
            effectors,
            factor_range,
            factors,
        }
    }

    /// Set up the walk along segment `a..b`, sampled every `stride` frames from `a`: the
    /// translations, each factor's rotation per sample step (`step`), and its value at the two
    /// samples the walk starts from, `first` and `first + 1` (`down`, `up`). One arctangent and
    /// two sine–cosine pairs per factor; the rest of the walk is quaternion products.
    fn plan(&self, a: usize, b: usize, stride: usize, first: usize, s: &mut Scratch) {
        let bvh = self.interp.bvh();
        let (fa, fb) = (bvh.motion.frame(a), bvh.motion.frame(b));
        let frames = (b - a) as f64;
        s.t0.clear();
        s.dt.clear();
        for joint in &bvh.skeleton.joints {
            let (mut ta, mut tb) = (joint.offset, joint.offset);
            for (k, ch) in joint.channels.iter().enumerate() {
                if !ch.is_rotation() {
                    ta[ch.axis()] = fa[joint.first_channel + k];
                    tb[ch.axis()] = fb[joint.first_channel + k];
                }
            }
            s.t0.push(ta);
            s.dt.push([tb[0] - ta[0], tb[1] - ta[1], tb[2] - ta[2]]);
        }
        let u_step = stride as f64 / frames;
        let u_first = (first * stride) as f64 / frames;
        s.step.clear();
        s.down.clear();
        s.up.clear();
        for f in &self.factors {
            let (start, step) = match *f {
                Factor::Slerp { joint } => {
                    let qa = self.interp.key_rotation(a, joint).unwrap_or(Quat::IDENTITY);
                    let qb = self.interp.key_rotation(b, joint).unwrap_or(Quat::IDENTITY);
                    let r = shortest_relative(qa, qb);
                    let half = r.x * r.x + r.y * r.y + r.z * r.z;
                    let half = half.sqrt().atan2(r.w);
                    (qa * pow_angle(r, half, u_first), pow_angle(r, half, u_step))
                }
                Factor::Angle { column, axis } => {
                    let d = fb[column] - fa[column];
                    (
                        Quat::about_axis(axis, (fa[column] + u_first * d).to_radians()),
                        Quat::about_axis(axis, (u_step * d).to_radians()),
                    )
                }
            };
            s.step.push(step);
            s.down.push(start);
            s.up.push(start * step);
        }
    }

    /// Error of frame `t` of the segment walk, with rotation factors `factors`.
    fn walk_error(&self, a: usize, b: usize, t: usize, factors: &[Quat], s: &mut Scratch) -> f64 {
        let skeleton = &self.interp.bvh().skeleton;
        let u = (t - a) as f64 / (b - a) as f64;
        let (pos, rot, t0, dt) = (&mut s.pos, &mut s.rot, &s.t0, &s.dt);
        pos.clear();
        rot.clear();
        for (j, joint) in skeleton.joints.iter().enumerate() {
            let range = self.factor_range[j].clone();
            let q = match range.len() {
                1 => factors[range.start],
                _ => factors[range].iter().fold(Quat::IDENTITY, |q, f| q * *f),
            };
            let tr = [
                t0[j][0] + u * dt[j][0],
                t0[j][1] + u * dt[j][1],
                t0[j][2] + u * dt[j][2],
            ];
            match joint.parent {
                Some(p) if p < j => {
                    let (pp, pq) = (pos[p], rot[p]);
                    let d = pq.rotate(tr);
                    pos.push([pp[0] + d[0], pp[1] + d[1], pp[2] + d[2]]);
                    rot.push(pq * q);
                }
                _ => {
                    pos.push(tr);
                    rot.push(q);
                }
            }
        }
        let orig = &self.original[t * self.points..(t + 1) * self.points];
        let mut sum = 0.0;
        for (&(j, end), o) in self.effectors.iter().zip(orig) {
            let p = match end {
                None => pos[j],
                Some(e) => {
                    let d = rot[j].rotate(e);
                    [pos[j][0] + d[0], pos[j][1] + d[1], pos[j][2] + d[2]]
                }
            };
            let d = [p[0] - o[0], p[1] - o[1], p[2] - o[2]];
            sum += d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
        }
        sum
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
        self.sampled_segment_cost(a, b, 1, bound, s)
    }

    /// An estimate of [`Evaluator::segment_cost`] from every `stride`-th frame only: the frames
    /// `a + stride, a + 2·stride, … < b`, each standing for `stride` frames (so `stride` 1 is the
    /// exact cost). It costs about `1/stride` of the exact sum, which is what makes a search over
    /// a coarse grid of keys cheap. Like the exact cost, it stops early once above `bound`.
    pub fn sampled_segment_cost(
        &self,
        a: usize,
        b: usize,
        stride: usize,
        bound: f64,
        s: &mut Scratch,
    ) -> f64 {
        let stride = stride.max(1);
        if b <= a + stride {
            return 0.0;
        }
        // Samples m = 1..=last sit at frames a + m·stride; the walk starts at the middle one.
        let last = (b - a - 1) / stride;
        let mid = last.div_ceil(2);
        // Every rotation factor turns by a fixed step per sample, so the samples are reached by
        // one quaternion product per factor, outwards from the middle.
        self.plan(a, b, stride, mid, s);
        let mut down = std::mem::take(&mut s.down);
        let mut up = std::mem::take(&mut s.up);
        let scale = stride as f64;
        let mut sum = 0.0;
        let (mut lo, mut hi) = (mid, mid + 1);
        loop {
            let mut moved = false;
            if lo >= 1 {
                sum += scale * self.walk_error(a, b, a + lo * stride, &down, s);
                for (f, st) in down.iter_mut().zip(&s.step) {
                    *f = *f * st.conj();
                }
                lo -= 1;
                moved = true;
            }
            if hi <= last {
                sum += scale * self.walk_error(a, b, a + hi * stride, &up, s);
                for (f, st) in up.iter_mut().zip(&s.step) {
                    *f = *f * *st;
                }
                hi += 1;
                moved = true;
            }
            if !moved || sum > bound {
                break;
            }
        }
        s.down = down;
        s.up = up;
        sum
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

/// `q^t` for a unit quaternion `q` whose half-angle `atan2(|v|, w)` is `half`: the same axis,
/// `t` times the angle (as [`crate::rotation::pow`], with the arctangent shared by the callers).
fn pow_angle(q: Quat, half: f64, t: f64) -> Quat {
    let s = (q.x * q.x + q.y * q.y + q.z * q.z).sqrt();
    let (sin, cos) = (t * half).sin_cos();
    // sin(t·φ)/sin(φ) tends to t as φ → 0.
    let k = if s > 1e-12 { sin / s } else { t };
    Quat {
        w: cos,
        x: q.x * k,
        y: q.y * k,
        z: q.z * k,
    }
}
