//! The data model: a joint tree with channels, and the motion as one flat table of values.

/// A three-component vector (x, y, z).
pub type Vec3 = [f64; 3];

/// One animated degree of freedom of a joint, as named in `CHANNELS`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Channel {
    Xposition,
    Yposition,
    Zposition,
    Xrotation,
    Yrotation,
    Zrotation,
}

impl Channel {
    /// The spelling used in BVH files.
    pub fn name(self) -> &'static str {
        match self {
            Channel::Xposition => "Xposition",
            Channel::Yposition => "Yposition",
            Channel::Zposition => "Zposition",
            Channel::Xrotation => "Xrotation",
            Channel::Yrotation => "Yrotation",
            Channel::Zrotation => "Zrotation",
        }
    }

    /// Parse a channel name (case-insensitive, as some exporters vary the case).
    pub fn from_name(s: &str) -> Option<Channel> {
        Some(match s.to_ascii_lowercase().as_str() {
            "xposition" => Channel::Xposition,
            "yposition" => Channel::Yposition,
            "zposition" => Channel::Zposition,
            "xrotation" => Channel::Xrotation,
            "yrotation" => Channel::Yrotation,
            "zrotation" => Channel::Zrotation,
            _ => return None,
        })
    }

    /// The axis index (0 = X, 1 = Y, 2 = Z).
    pub fn axis(self) -> usize {
        match self {
            Channel::Xposition | Channel::Xrotation => 0,
            Channel::Yposition | Channel::Yrotation => 1,
            Channel::Zposition | Channel::Zrotation => 2,
        }
    }

    /// True for the three rotation channels.
    pub fn is_rotation(self) -> bool {
        matches!(
            self,
            Channel::Xrotation | Channel::Yrotation | Channel::Zrotation
        )
    }
}

/// One joint of the hierarchy (ROOT or JOINT).
#[derive(Debug, Clone, PartialEq)]
pub struct Joint {
    pub name: String,
    /// Index of the parent joint; `None` for a root.
    pub parent: Option<usize>,
    /// OFFSET from the parent, in file units.
    pub offset: Vec3,
    /// Channels in file order: rotations are applied in this order.
    pub channels: Vec<Channel>,
    /// Column of this joint's first channel in a frame.
    pub first_channel: usize,
    /// The End Site's OFFSET, when the joint has one.
    pub end_site: Option<Vec3>,
}

impl Joint {
    /// The rotation axes in listed order, when the joint has exactly three distinct ones
    /// (the case where rotations can round-trip through quaternions losslessly).
    pub fn euler_order(&self) -> Option<[usize; 3]> {
        let axes: Vec<usize> = self
            .channels
            .iter()
            .filter(|c| c.is_rotation())
            .map(|c| c.axis())
            .collect();
        match axes.as_slice() {
            &[a, b, c] if a != b && b != c && a != c => Some([a, b, c]),
            _ => None,
        }
    }
}

/// The joint tree. Joints are stored depth-first in file order, so a parent always precedes
/// its children: forward kinematics is then one pass.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Skeleton {
    pub joints: Vec<Joint>,
}

impl Skeleton {
    /// Total number of channels, i.e. values per frame.
    pub fn channel_count(&self) -> usize {
        self.joints.iter().map(|j| j.channels.len()).sum()
    }

    /// Number of End Sites.
    pub fn end_site_count(&self) -> usize {
        self.joints.iter().filter(|j| j.end_site.is_some()).count()
    }

    /// Joints that have no child joint.
    pub fn is_leaf(&self) -> Vec<bool> {
        let mut leaf = vec![true; self.joints.len()];
        for j in &self.joints {
            if let Some(p) = j.parent {
                leaf[p] = false;
            }
        }
        leaf
    }

    /// Number of roots (BVH allows several).
    pub fn root_count(&self) -> usize {
        self.joints.iter().filter(|j| j.parent.is_none()).count()
    }
}

/// The MOTION section: `frames × channels` values, row-major.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Motion {
    /// Seconds per frame.
    pub frame_time: f64,
    /// Number of frames (kept apart from `values` so that a skeleton without channels
    /// still reports its frame count).
    pub frames: usize,
    /// Values per frame (equals the skeleton's channel count).
    pub channels: usize,
    pub values: Vec<f64>,
}

impl Motion {
    /// Number of frames.
    pub fn frames(&self) -> usize {
        self.frames
    }

    /// The values of frame `i`.
    ///
    /// # Panics
    /// When `i >= frames()` (a caller error, not an input error).
    pub fn frame(&self, i: usize) -> &[f64] {
        &self.values[i * self.channels..(i + 1) * self.channels]
    }

    /// Frames per second, when the frame time is positive.
    pub fn rate(&self) -> Option<f64> {
        (self.frame_time > 0.0).then(|| 1.0 / self.frame_time)
    }
}

/// A whole BVH file.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Bvh {
    pub skeleton: Skeleton,
    pub motion: Motion,
}
