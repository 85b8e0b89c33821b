//! A session's calibration as one trial's events take it: the offsets learned from the other
//! trials ([`crate::events_session`] learns them), and how they are reported with the
//! trial's events. Apart from the learning, so that detecting a trial's events and learning
//! from a session's trials each import this vocabulary and not each other.

use gait::SessionOffsets;
use serde::Serialize;

/// A session's offsets as applied to one trial.
#[derive(Debug, Clone, PartialEq)]
pub struct SessionCalibration {
    pub offsets: SessionOffsets,
    /// Reference trials that gave lags (the trial itself excluded).
    pub trials: usize,
    pub min_contacts: usize,
}

/// One kind's session offset as reported with a trial's events.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct KindReport {
    /// The offset added to the left and the right foot's kinematic events, ms (null: none).
    pub left_ms: Option<f64>,
    pub right_ms: Option<f64>,
    /// The contacts it was learned from.
    pub contacts: usize,
    /// Whether it moved this trial's events: not when too few contacts were found, nor in
    /// `auto` where the trial's own plates calibrate this kind.
    pub used: bool,
}

/// The session calibration as reported with a trial's events.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SessionReport {
    /// The reference trials that gave contacts (the trial itself never counts).
    pub trials: usize,
    pub min_contacts: usize,
    pub strike: KindReport,
    pub off: KindReport,
}

impl SessionCalibration {
    /// The report, with `own` saying which kinds (strike, off) the trial's own plates
    /// calibrated instead.
    pub fn report(&self, own: [bool; 2]) -> SessionReport {
        let k = |o: &gait::session::KindOffset, own: bool| {
            let ms = |s: Option<f64>| s.map(|v| (v * 10_000.0).round() / 10.0);
            KindReport {
                left_ms: ms(o.seconds[0]),
                right_ms: ms(o.seconds[1]),
                contacts: o.contacts[0] + o.contacts[1],
                used: !own && o.seconds.iter().any(Option::is_some),
            }
        };
        SessionReport {
            trials: self.trials,
            min_contacts: self.min_contacts,
            strike: k(&self.offsets.strike, own[0]),
            off: k(&self.offsets.off, own[1]),
        }
    }

    /// What the report's readers should know, in words: the kinds left uncalibrated.
    pub fn warnings(&self) -> Vec<String> {
        let mut w = Vec::new();
        for (name, o) in [
            ("strikes", &self.offsets.strike),
            ("offs", &self.offsets.off),
        ] {
            if o.seconds.iter().all(Option::is_none) {
                w.push(format!(
                    "session calibration: {} contact(s) for {name} in {} other trial(s), fewer than {}: {name} are left as the markers give them",
                    o.contacts[0] + o.contacts[1],
                    self.trials,
                    self.min_contacts
                ));
            }
        }
        w
    }
}
