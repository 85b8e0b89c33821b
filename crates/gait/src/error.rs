//! What detecting events can fail with, each worded for a person.

/// Why no events could be detected at all (a trial that merely has fewer events than
/// expected is no error).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// A marker needed by the method is not in the trial under any known name.
    #[error("no {what} marker: looked for {looked_for}")]
    NoMarker { what: String, looked_for: String },
    /// No marker of either foot under any known name: a marker set that leaves the feet
    /// out (an upper-body set), so the trial has no gait events to give.
    #[error("no foot markers: {}", if *markers == 0 { "the trial has no markers".to_string() } else { format!("none of the trial's {markers} markers is a heel, ankle, toe or foot marker under any known name (the marker set leaves the feet out, or names them as no known set does)") })]
    NoFootMarkers { markers: usize },
    /// A name given by a person is no marker of the trial (each front names the setting its
    /// own way).
    #[error("markers {role}={name}: the trial has no marker of that name")]
    UnknownMarker { role: String, name: String },
    /// A malformed item of the marker names a person gave.
    #[error("markers {0}: expected ROLE=NAME with ROLE one of lheel, rheel, ltoe, rtoe, pelvis (NAME+NAME… for a mean)")]
    BadMarkerSpec(String),
    /// Too few frames to see a step.
    #[error("{frames} frame(s): events need at least {needed} frames")]
    TooShort { frames: usize, needed: usize },
    /// Every sample of the named markers is missing or not finite.
    #[error("every sample of the {0} markers is missing")]
    AllMissing(String),
    /// The pelvis never moves at walking speed, so there is no walking direction.
    #[error("no walking: the pelvis never moves faster than {min_speed_m_s} m/s over {window_s} s, and the feet do not swing back and forth under it as on a treadmill")]
    NoWalking { min_speed_m_s: f64, window_s: f64 },
    /// The arrays given do not fit together, or a rate is not a positive number.
    #[error("{0}")]
    Input(String),
}

/// The crate's result type.
pub type Result<T> = std::result::Result<T, Error>;
