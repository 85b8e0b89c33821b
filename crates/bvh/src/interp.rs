//! Interpolating a motion between key frames, in Euler angles or in quaternions.
//!
//! Position channels (and, in Euler mode, rotation channels) are interpolated linearly per
//! channel. In quaternion mode, each joint with three distinct rotation axes is slerped along
//! the shorter arc, then written back as Euler angles in the joint's own order; joints with
//! fewer or repeated rotation axes cannot always be written back after a slerp, so they stay
//! linear in their angles.

use crate::fk::LocalPose;
use crate::rotation::{euler_to_quat, quat_to_euler, slerp, Quat};
use crate::skeleton::{Bvh, Motion};

/// How rotations are interpolated between keys.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Interp {
    /// Linear in each Euler angle channel.
    Euler,
    /// Spherical linear interpolation of each joint's rotation.
    Quat,
}

impl Interp {
    pub fn name(self) -> &'static str {
        match self {
            Interp::Euler => "euler",
            Interp::Quat => "quat",
        }
    }
}

/// A motion prepared for repeated interpolation: per-frame joint quaternions are computed once.
#[derive(Debug, Clone)]
pub struct Interpolator<'a> {
    bvh: &'a Bvh,
    mode: Interp,
    /// Per joint: the Euler order when it is slerped, `None` when it stays linear.
    slerped: Vec<Option<[usize; 3]>>,
    /// `frames × joints` local rotations of the original motion (only filled in `Quat` mode).
    quats: Vec<Quat>,
}

impl<'a> Interpolator<'a> {
    pub fn new(bvh: &'a Bvh, mode: Interp) -> Self {
        let joints = &bvh.skeleton.joints;
        let slerped: Vec<Option<[usize; 3]>> = joints
            .iter()
            .map(|j| match mode {
                Interp::Quat => j.euler_order(),
                Interp::Euler => None,
            })
            .collect();
        let mut quats = Vec::new();
        if mode == Interp::Quat {
            quats.reserve(bvh.motion.frames() * joints.len());
            for f in 0..bvh.motion.frames() {
                let frame = bvh.motion.frame(f);
                for (j, joint) in joints.iter().enumerate() {
                    quats.push(match slerped[j] {
                        Some(order) => euler_to_quat(order, rotation_angles(joint, frame)),
                        None => Quat::IDENTITY,
                    });
                }
            }
        }
        Interpolator {
            bvh,
            mode,
            slerped,
            quats,
        }
    }

    pub fn bvh(&self) -> &'a Bvh {
        self.bvh
    }

    /// True when joint `j`'s rotation is slerped (rather than linear in its angles).
    pub fn is_slerped(&self, j: usize) -> bool {
        self.slerped.get(j).is_some_and(|o| o.is_some())
    }

    /// The original local rotation of joint `j` at frame `f`, when that joint is slerped.
    pub fn key_rotation(&self, f: usize, j: usize) -> Option<Quat> {
        let nj = self.bvh.skeleton.joints.len();
        self.slerped.get(j)?.as_ref()?;
        self.quats.get(f * nj + j).copied()
    }

    pub fn mode(&self) -> Interp {
        self.mode
    }

    /// The local pose at frame `t`, interpolated between key frames `a < t < b` (any `t` in
    /// `a..=b` works; the keys themselves come out unchanged up to rounding).
    pub fn local_pose(&self, a: usize, b: usize, t: usize, out: &mut LocalPose) {
        let skeleton = &self.bvh.skeleton;
        let motion = &self.bvh.motion;
        let u = weight(a, b, t);
        let (fa, fb) = (motion.frame(a), motion.frame(b));
        let nj = skeleton.joints.len();
        out.translations.clear();
        out.rotations.clear();
        for (j, joint) in skeleton.joints.iter().enumerate() {
            let mut tr = joint.offset;
            let mut q = Quat::IDENTITY;
            let slerped = self.slerped[j].is_some();
            for (k, ch) in joint.channels.iter().enumerate() {
                let c = joint.first_channel + k;
                let v = fa[c] + u * (fb[c] - fa[c]);
                if !ch.is_rotation() {
                    tr[ch.axis()] = v;
                } else if !slerped {
                    q = q * Quat::about_axis(ch.axis(), v.to_radians());
                }
            }
            if slerped {
                q = slerp(self.quats[a * nj + j], self.quats[b * nj + j], u);
            }
            out.translations.push(tr);
            out.rotations.push(q);
        }
    }

    /// The channel values of frame `t` interpolated between keys `a` and `b`, written to `out`.
    pub fn frame_values(&self, a: usize, b: usize, t: usize, out: &mut [f64]) {
        let skeleton = &self.bvh.skeleton;
        let motion = &self.bvh.motion;
        let u = weight(a, b, t);
        let (fa, fb) = (motion.frame(a), motion.frame(b));
        for (o, (x, y)) in out.iter_mut().zip(fa.iter().zip(fb)) {
            *o = x + u * (y - x);
        }
        let nj = skeleton.joints.len();
        for (j, joint) in skeleton.joints.iter().enumerate() {
            let Some(order) = self.slerped[j] else {
                continue;
            };
            let q = slerp(self.quats[a * nj + j], self.quats[b * nj + j], u);
            let euler = quat_to_euler(order, q);
            let mut r = 0;
            for (k, ch) in joint.channels.iter().enumerate() {
                if ch.is_rotation() {
                    let c = joint.first_channel + k;
                    // Same rotation, but keep each angle near the linear value, so that curves
                    // stay continuous with the source instead of jumping by 360°.
                    out[c] = unwrap_near(euler[r], out[c]);
                    r += 1;
                }
            }
        }
    }

    /// The whole motion rebuilt from `keys` (sorted frame indices; first and last frame must be
    /// among them for every frame to be covered — frames outside the keys are copied).
    pub fn resample(&self, keys: &[usize]) -> Motion {
        let motion = &self.bvh.motion;
        let mut values = motion.values.clone();
        for w in keys.windows(2) {
            let (a, b) = (w[0], w[1]);
            for t in a + 1..b {
                let range = t * motion.channels..(t + 1) * motion.channels;
                self.frame_values(a, b, t, &mut values[range]);
            }
        }
        Motion {
            values,
            ..motion.clone()
        }
    }
}

/// Interpolation weight of frame `t` between keys `a` and `b`.
fn weight(a: usize, b: usize, t: usize) -> f64 {
    if b > a {
        (t as f64 - a as f64) / (b as f64 - a as f64)
    } else {
        0.0
    }
}

/// A joint's rotation channel values in listed order (assumes three rotation channels).
fn rotation_angles(joint: &crate::skeleton::Joint, frame: &[f64]) -> [f64; 3] {
    let mut out = [0.0; 3];
    let mut r = 0;
    for (k, ch) in joint.channels.iter().enumerate() {
        if ch.is_rotation() && r < 3 {
            out[r] = frame.get(joint.first_channel + k).copied().unwrap_or(0.0);
            r += 1;
        }
    }
    out
}

/// `angle + 360°·k` closest to `near`.
fn unwrap_near(angle: f64, near: f64) -> f64 {
    angle + ((near - angle) / 360.0).round() * 360.0
}
