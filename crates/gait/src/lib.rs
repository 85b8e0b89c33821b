//! Gait events on plain arrays: foot strike and foot off, from the markers
//! ([`kinematic`]: Zeni et al. 2008, O'Connor et al. 2007, Desailly et al. 2009) and from
//! the force plates ([`plates`]).
//!
//! Nothing here knows about C3D: trajectories are `[x, y, z]` per frame in millimetres with
//! NaN where a sample is missing, plate loads are newtons per analog sample. Event times are
//! fractional 0-based frame indices ([`Event::index`]), so the caller maps them to its own
//! frame numbering and time base (the `c3dfix` crate uses the file's).
//!
//! [`params`] computes the gait-cycle parameters Vicon Nexus reports from the events and
//! the toe markers.
//!
//! The markers come from their labels through [`markers`], which knows the common marker
//! sets and takes names given by a person instead.
//!
//! A session's trials with known events calibrate the kinematic events of its other trials
//! ([`session`]).
//!
//! Cycles (foot strike to the next foot strike of the same foot) and signals time-normalised
//! to 0–100 % of them are in [`cycles`].

pub mod axes;
pub mod calibrate;
pub mod correlate;
pub mod cycles;
pub mod desailly;
mod error;
pub mod impact;
pub mod kinematic;
mod kinematic_options;
pub mod landing;
pub mod markers;
pub mod oconnor;
pub mod params;
pub mod plates;
pub mod running;
pub mod session;
mod signal;
pub mod touchdown;
pub mod treadmill;
pub mod velocity;

pub use calibrate::calibrate;
pub use correlate::{correlate, CorrelateOptions};
pub use error::{Error, Result};
pub use kinematic::{kinematic_events, Estimate, KinematicOptions, Method};
pub use markers::{find_markers, MarkerChoice, MarkerNames};
pub use params::{gait_parameters, GaitParameters, TimedEvent, Toes};
pub use plates::{plate_events, PlateInput, PlateOptions};
pub use session::{session_offsets, SessionOffsets, SessionOptions};

use serde::Serialize;

/// Which foot.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize)]
pub enum Side {
    Left,
    Right,
}

impl Side {
    /// Both sides, left first.
    pub const BOTH: [Side; 2] = [Side::Left, Side::Right];

    /// The EVENT group's context: "Left" or "Right".
    pub fn context(self) -> &'static str {
        match self {
            Side::Left => "Left",
            Side::Right => "Right",
        }
    }
}

/// What happened to the foot.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize)]
pub enum Kind {
    FootStrike,
    FootOff,
}

impl Kind {
    /// The label Vicon Nexus writes in EVENT:LABELS.
    pub fn label(self) -> &'static str {
        match self {
            Kind::FootStrike => "Foot Strike",
            Kind::FootOff => "Foot Off",
        }
    }
}

/// Where an event was found.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Source {
    Plate,
    Kinematics,
}

impl Source {
    /// As the JSON output spells it.
    pub fn name(self) -> &'static str {
        match self {
            Source::Plate => "plate",
            Source::Kinematics => "kinematics",
        }
    }
}

/// One foot strike or foot off.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Event {
    pub side: Side,
    pub kind: Kind,
    /// When, in point frames from the first stored frame (0-based, fractional: a plate's
    /// crossing falls between frames, a marker's extremum is interpolated between samples).
    pub index: f64,
    pub source: Source,
    /// For plate events, the 1-based plate.
    pub plate: Option<usize>,
}

/// Sort events by time, then side, then kind (the order they are printed and written in).
pub fn sort_events(events: &mut [Event]) {
    events.sort_by(|a, b| {
        a.index
            .total_cmp(&b.index)
            .then(a.side.cmp(&b.side))
            .then(a.kind.cmp(&b.kind))
    });
}

/// `events` each moved by `shift(event)` frames, sorted by time: what a calibration does to a
/// trial's kinematic events, whichever offsets it has found.
pub(crate) fn shifted(events: &[Event], shift: impl Fn(&Event) -> f64) -> Vec<Event> {
    let mut out: Vec<Event> = events
        .iter()
        .map(|e| Event {
            index: e.index + shift(e),
            ..*e
        })
        .collect();
    sort_events(&mut out);
    out
}

/// The trajectories the detectors read, each one `[x, y, z]` per frame in millimetres in
/// the lab frame, NaN where missing; all of the same length.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Feet {
    pub left_heel: Vec<[f64; 3]>,
    pub left_toe: Vec<[f64; 3]>,
    pub right_heel: Vec<[f64; 3]>,
    pub right_toe: Vec<[f64; 3]>,
    /// The sacrum, or the mean of the pelvis markers.
    pub pelvis: Vec<[f64; 3]>,
    /// Left and right: the "heel" is the lateral malleolus standing in for a missing heel
    /// marker (its height says nothing of the landing, so strikes are not refined by it).
    pub heel_is_ankle: [bool; 2],
}

impl Feet {
    /// Frames (the length of the pelvis trajectory).
    pub fn frames(&self) -> usize {
        self.pelvis.len()
    }

    /// Whether `side`'s heel is an ankle marker standing in.
    pub fn heel_is_ankle(&self, side: Side) -> bool {
        self.heel_is_ankle[match side {
            Side::Left => 0,
            Side::Right => 1,
        }]
    }

    /// Heel and toe of one side.
    pub fn foot(&self, side: Side) -> (&[[f64; 3]], &[[f64; 3]]) {
        match side {
            Side::Left => (&self.left_heel, &self.left_toe),
            Side::Right => (&self.right_heel, &self.right_toe),
        }
    }

    /// The lab's vertical from the pelvis and all four foot markers (see [`axes::vertical`]);
    /// `None` when no frame has the pelvis with a foot marker. Every detector finds it so.
    pub(crate) fn vertical(&self) -> Option<axes::Vertical> {
        axes::vertical(
            &self.pelvis,
            &[
                &self.left_heel,
                &self.right_heel,
                &self.left_toe,
                &self.right_toe,
            ],
        )
    }

    /// An error unless every trajectory has the pelvis' length.
    pub fn check(&self) -> Result<()> {
        let n = self.frames();
        for (name, t) in [
            ("left heel", &self.left_heel),
            ("left toe", &self.left_toe),
            ("right heel", &self.right_heel),
            ("right toe", &self.right_toe),
        ] {
            if t.len() != n {
                return Err(Error::Input(format!(
                    "the {name} trajectory has {} frames, the pelvis {n}",
                    t.len()
                )));
            }
        }
        Ok(())
    }
}
