//! Forward kinematics: world position and rotation of every joint and End Site.
//!
//! Local transform = translation(OFFSET, with any position channel replacing its component)
//! · rotations in listed channel order; world = parent world · local.

use crate::rotation::Quat;
use crate::skeleton::{Bvh, Skeleton, Vec3};

/// Each joint's transform relative to its parent, for one frame.
#[derive(Debug, Clone, PartialEq)]
pub struct LocalPose {
    pub translations: Vec<Vec3>,
    pub rotations: Vec<Quat>,
}

/// World transforms for one frame.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Pose {
    /// World position of each joint (its origin).
    pub positions: Vec<Vec3>,
    /// World rotation of each joint.
    pub rotations: Vec<Quat>,
    /// World position of each joint's End Site, when it has one.
    pub end_sites: Vec<Option<Vec3>>,
}

/// The local transforms that one frame's channel values describe.
pub fn local_pose(skeleton: &Skeleton, frame: &[f64]) -> LocalPose {
    let mut translations = Vec::with_capacity(skeleton.joints.len());
    let mut rotations = Vec::with_capacity(skeleton.joints.len());
    for joint in &skeleton.joints {
        let mut t = joint.offset;
        let mut q = Quat::IDENTITY;
        for (k, ch) in joint.channels.iter().enumerate() {
            let v = frame.get(joint.first_channel + k).copied().unwrap_or(0.0);
            if ch.is_rotation() {
                q = q * Quat::about_axis(ch.axis(), v.to_radians());
            } else {
                t[ch.axis()] = v;
            }
        }
        translations.push(t);
        rotations.push(q);
    }
    LocalPose {
        translations,
        rotations,
    }
}

/// Compose local transforms into world transforms, reusing `out`'s buffers.
pub fn world_pose(skeleton: &Skeleton, local: &LocalPose, out: &mut Pose) {
    let n = skeleton.joints.len();
    out.positions.clear();
    out.rotations.clear();
    out.end_sites.clear();
    for i in 0..n {
        let joint = &skeleton.joints[i];
        let (p, q) = match joint.parent {
            // Parents precede children, so the parent's world transform is already known.
            Some(pi) if pi < i => {
                let pq = out.rotations[pi];
                let pp = out.positions[pi];
                let t = pq.rotate(local.translations[i]);
                (
                    [pp[0] + t[0], pp[1] + t[1], pp[2] + t[2]],
                    pq * local.rotations[i],
                )
            }
            _ => (local.translations[i], local.rotations[i]),
        };
        out.positions.push(p);
        out.rotations.push(q);
        out.end_sites.push(joint.end_site.map(|e| {
            let t = q.rotate(e);
            [p[0] + t[0], p[1] + t[1], p[2] + t[2]]
        }));
    }
}

/// World transforms of frame `frame` of a file.
///
/// # Panics
/// When `frame` is out of range (a caller error).
pub fn forward(bvh: &Bvh, frame: usize) -> Pose {
    let local = local_pose(&bvh.skeleton, bvh.motion.frame(frame));
    let mut pose = Pose::default();
    world_pose(&bvh.skeleton, &local, &mut pose);
    pose
}

/// Every joint and End Site of a file as points, for drawing the skeleton.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Positions {
    /// Joint names, End Sites as `<joint>_End`, in file order (each End Site right after its
    /// joint).
    pub labels: Vec<String>,
    /// Bones as point index pairs: parent joint → joint, joint → its End Site.
    pub bones: Vec<(usize, usize)>,
    /// Indices of the End Site points.
    pub end_sites: Vec<usize>,
    /// World positions, frame-major: point `p` of frame `f` is at `f * labels.len() + p`.
    pub xyz: Vec<Vec3>,
}

/// World positions of every joint and End Site in every frame (forward kinematics), with the
/// bones that join them: what a viewer needs to draw the skeleton move.
pub fn all_positions(bvh: &Bvh) -> Positions {
    let skeleton = &bvh.skeleton;
    let mut labels = Vec::new();
    let mut bones = Vec::new();
    let mut end_sites = Vec::new();
    // Point index of each joint, so children can name their parent's point.
    let mut point_of = Vec::with_capacity(skeleton.joints.len());
    for joint in &skeleton.joints {
        let p = labels.len();
        point_of.push(p);
        labels.push(joint.name.clone());
        if let Some(&parent) = joint.parent.and_then(|q| point_of.get(q)) {
            bones.push((parent, p));
        }
        if joint.end_site.is_some() {
            bones.push((p, labels.len()));
            end_sites.push(labels.len());
            labels.push(format!("{}_End", joint.name));
        }
    }
    let frames = bvh.motion.frames();
    let mut xyz = Vec::with_capacity(frames * labels.len());
    let mut pose = Pose::default();
    for f in 0..frames {
        let local = local_pose(skeleton, bvh.motion.frame(f));
        world_pose(skeleton, &local, &mut pose);
        for (p, e) in pose.positions.iter().zip(&pose.end_sites) {
            xyz.push(*p);
            if let Some(e) = e {
                xyz.push(*e);
            }
        }
    }
    Positions {
        labels,
        bones,
        end_sites,
        xyz,
    }
}
