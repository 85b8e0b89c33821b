//! A trial's kinematic events shifted by the lead or lag the markers showed on OTHER trials
//! of the same session (or lab): markers alone with a session calibration.
//!
//! Every kinematic method lands a little before or after the contact by an amount set by
//! the lab's marker placement (the heel marker's height and lead, the toe marker's place on
//! the forefoot): held out, Zeni's heel extreme comes 33–66 ms before contact depending on
//! the lab, and no constant chosen on other labs removes that (docs/events.md). Within one
//! lab the amount spreads less than it differs between labs, so a session's trials with
//! known events (plate contacts, or the lab's own events) tell it for the trials without.
//!
//! Times here are seconds, so trials recorded at different rates can be pooled. A lag is
//! (truth − kinematic) for one truth event and the nearest kinematic event of its foot and
//! kind within a window; the offset of a kind is the median of its lags.

use crate::{Event, Kind, Side};
// The mean of the middle two for an even count: the one rule both the trial's own
// calibration and the session's use.
use ::signal::order::median;
use serde::Serialize;

/// One truth event's lag against the nearest kinematic event of its foot and kind.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Lag {
    pub side: Side,
    pub kind: Kind,
    /// Truth − kinematic, seconds.
    pub seconds: f64,
}

/// How the offsets are learned.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SessionOptions {
    /// A kind (strike, off) with fewer lags than this gets no offset: its events are left as
    /// detected (and `c3dfix events` warns). The default, [`MIN_CONTACTS`], is one.
    pub min_contacts: usize,
    /// A side with at least `min_contacts` lags of a kind gets its own offset, the other
    /// side the pooled one. Off by default: the two feet of a lab share their markers'
    /// placement, and per side the tuning labs are unchanged while held out it trades
    /// strikes against offs (`events_eval --session-per-side`, docs/events.md): the data
    /// does not support two offsets.
    pub per_side: bool,
    /// Half the window (s) within which a truth event is paired with a kinematic event.
    pub window_s: f64,
}

impl Default for SessionOptions {
    fn default() -> Self {
        SessionOptions {
            min_contacts: MIN_CONTACTS,
            per_side: false,
            window_s: WINDOW_S,
        }
    }
}

/// The default [`SessionOptions::min_contacts`]: one contact. Chosen on the tuning labs
/// (`events_eval --session-min`, docs/events.md): their only lab whose offset is large,
/// c3d-samples' sample_25 (strikes 52 ms early), has one plate strike per trial, and its two
/// trials' single lags agree within 1 ms; requiring two left it uncalibrated (tuning strikes
/// 31.6 / 52.7 ms median / p95 against 18.7 / 27.6 with one). A single step's lag carries
/// that step's noise too (the spread within a lab is 10–20 ms), so the contacts an offset
/// rests on are always reported.
pub const MIN_CONTACTS: usize = 1;

/// The default [`SessionOptions::window_s`]: the trial's own calibration's window (chosen
/// on the tuning labs; `c3dfix::events::CALIBRATE_WINDOW_S`), wider than the methods'
/// lags there, narrower than half a step.
pub const WINDOW_S: f64 = 0.06;

/// The offset learned for one event kind.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize)]
pub struct KindOffset {
    /// Seconds added to the kind's kinematic events of each side (left, right); `None` where
    /// too few contacts were found.
    pub seconds: [Option<f64>; 2],
    /// The lags it was learned from, per side (left, right).
    pub contacts: [usize; 2],
    /// Whether the two sides' offsets were learned apart.
    pub per_side: bool,
}

/// The offsets of both kinds: strike, then off.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize)]
pub struct SessionOffsets {
    pub strike: KindOffset,
    pub off: KindOffset,
}

impl SessionOffsets {
    /// The offset (s) for one side and kind, if any.
    pub fn get(&self, side: Side, kind: Kind) -> Option<f64> {
        let k = match kind {
            Kind::FootStrike => &self.strike,
            Kind::FootOff => &self.off,
        };
        k.seconds[side_index(side)]
    }
}

fn side_index(side: Side) -> usize {
    match side {
        Side::Left => 0,
        Side::Right => 1,
    }
}

/// The lags of one trial: each `truth` event with a kinematic event of the same foot and
/// kind within `window_s` (the nearest) gives (truth − kinematic) in seconds. Both are
/// fractional frame indices of the same trial at `rate` frames per second.
pub fn trial_lags(truth: &[Event], kinematic: &[Event], rate: f64, window_s: f64) -> Vec<Lag> {
    if !(rate.is_finite() && rate > 0.0) {
        return Vec::new();
    }
    truth
        .iter()
        .filter_map(|t| {
            kinematic
                .iter()
                .filter(|k| k.side == t.side && k.kind == t.kind)
                .map(|k| (t.index - k.index) / rate)
                .filter(|d| d.is_finite() && d.abs() <= window_s)
                .min_by(|a, b| a.abs().total_cmp(&b.abs()))
                .map(|seconds| Lag {
                    side: t.side,
                    kind: t.kind,
                    seconds,
                })
        })
        .collect()
}

/// The offsets learned from the lags of other trials (see [`SessionOptions`]).
pub fn session_offsets(lags: &[Lag], opts: &SessionOptions) -> SessionOffsets {
    let one = |kind: Kind| {
        let of = |side: Option<Side>| -> Vec<f64> {
            lags.iter()
                .filter(|l| l.kind == kind && side.is_none_or(|s| l.side == s))
                .map(|l| l.seconds)
                .collect()
        };
        let sides = [of(Some(Side::Left)), of(Some(Side::Right))];
        let contacts = [sides[0].len(), sides[1].len()];
        let min = opts.min_contacts.max(1);
        let mut pooled = of(None);
        let pooled = if pooled.len() >= min {
            median(&mut pooled)
        } else {
            None
        };
        let per_side = opts.per_side && contacts.iter().any(|&n| n >= min);
        let seconds = if per_side {
            [0, 1].map(|k| {
                if contacts[k] >= min {
                    median(&mut sides[k].clone())
                } else {
                    pooled
                }
            })
        } else {
            [pooled; 2]
        };
        KindOffset {
            seconds,
            contacts,
            per_side,
        }
    };
    SessionOffsets {
        strike: one(Kind::FootStrike),
        off: one(Kind::FootOff),
    }
}

/// `kinematic` (a trial at `rate` frames per second) with each event moved by its side's
/// and kind's offset (none: left as it is), sorted by time.
pub fn apply(kinematic: &[Event], offsets: &SessionOffsets, rate: f64) -> Vec<Event> {
    crate::shifted(kinematic, |k| {
        offsets.get(k.side, k.kind).unwrap_or(0.0) * rate
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Source;

    fn ev(side: Side, kind: Kind, index: f64) -> Event {
        Event {
            side,
            kind,
            index,
            source: Source::Kinematics,
            plate: None,
        }
    }

    #[test]
    fn lags_pair_each_truth_event_with_the_nearest_kinematic_one_in_seconds() {
        use Kind::*;
        use Side::*;
        let kin = [
            ev(Left, FootStrike, 100.0),
            ev(Left, FootStrike, 200.0),
            ev(Right, FootOff, 150.0),
        ];
        let truth = [
            ev(Left, FootStrike, 103.0),  // +3 frames
            ev(Right, FootOff, 148.0),    // −2 frames
            ev(Right, FootStrike, 103.0), // no right strike detected
            ev(Left, FootStrike, 300.0),  // too far
        ];
        let lags = trial_lags(&truth, &kin, 100.0, 0.06);
        let s: Vec<(Side, Kind, f64)> = lags
            .iter()
            .map(|l| (l.side, l.kind, (l.seconds * 1000.0).round()))
            .collect();
        assert_eq!(s, vec![(Left, FootStrike, 30.0), (Right, FootOff, -20.0)]);
        assert!(trial_lags(&truth, &kin, 0.0, 0.06).is_empty());
    }

    fn lag(side: Side, kind: Kind, ms: f64) -> Lag {
        Lag {
            side,
            kind,
            seconds: ms / 1000.0,
        }
    }

    #[test]
    fn offsets_are_medians_per_kind_and_need_the_minimum_of_contacts() {
        use Kind::*;
        use Side::*;
        let lags = [
            lag(Left, FootStrike, 20.0),
            lag(Right, FootStrike, 30.0),
            lag(Left, FootStrike, 40.0),
            lag(Right, FootStrike, 10.0),
            lag(Left, FootOff, -15.0),
        ];
        let two = SessionOptions {
            min_contacts: 2,
            ..SessionOptions::default()
        };
        let o = session_offsets(&lags, &two);
        // Pooled strikes: median of 10, 20, 30, 40 = 25 ms.
        assert_eq!(o.strike.contacts, [2, 2]);
        for s in o.strike.seconds {
            assert!((s.unwrap_or(f64::NAN) - 0.025).abs() < 1e-12);
        }
        // One off: below the minimum of two, so no offset.
        assert_eq!(o.off.seconds, [None, None]);
        assert_eq!(o.off.contacts, [1, 0]);

        let per = session_offsets(
            &lags,
            &SessionOptions {
                per_side: true,
                ..two
            },
        );
        let ms = per
            .strike
            .seconds
            .map(|s| (s.unwrap_or(f64::NAN) * 1000.0).round());
        assert_eq!(ms, [30.0, 20.0]);
        assert!(per.strike.per_side);
    }

    #[test]
    fn apply_moves_each_event_by_its_kind_in_frames_of_its_own_rate() {
        use Kind::*;
        use Side::*;
        let lags = [
            lag(Left, FootStrike, 20.0),
            lag(Right, FootStrike, 20.0),
            lag(Left, FootOff, -10.0),
        ];
        let o = session_offsets(
            &lags,
            &SessionOptions {
                min_contacts: 1,
                ..SessionOptions::default()
            },
        );
        let kin = [ev(Right, FootStrike, 10.0), ev(Left, FootOff, 20.0)];
        let out = apply(&kin, &o, 200.0);
        let idx: Vec<f64> = out.iter().map(|e| e.index).collect();
        // +20 ms = +4 frames at 200 Hz, −10 ms = −2 frames.
        assert_eq!(idx, vec![14.0, 18.0]);
    }
}
