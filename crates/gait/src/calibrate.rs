//! A trial's kinematic events shifted by their own lead or lag against the trial's plate
//! events.
//!
//! Every kinematic method lands a little before or after the contact, by an amount that
//! depends on the lab's marker placement, the shoe, the speed and the gait (docs/events.md
//! lists labs from −33 to +70 ms). Where a trial also has plates, the steps that land on
//! them show that amount for this trial: the median of (plate − kinematic) over the matched
//! pairs of each event kind is added to every kinematic event of that kind. The plates are
//! part of the trial, so nothing is learned from another trial or from the lab's events.

use crate::{Event, Kind};

/// The shift (frames) of each kind, strike then off: the median of (plate − kinematic)
/// over the plate events that have a kinematic event of the same foot and kind within
/// `window` frames (the nearest), `None` for a kind without such a pair.
pub fn plate_offsets(plates: &[Event], kinematic: &[Event], window: f64) -> [Option<f64>; 2] {
    [Kind::FootStrike, Kind::FootOff].map(|kind| {
        let mut d: Vec<f64> = plates
            .iter()
            .filter(|p| p.kind == kind)
            .filter_map(|p| {
                kinematic
                    .iter()
                    .filter(|k| k.side == p.side && k.kind == kind)
                    .map(|k| p.index - k.index)
                    .filter(|d| d.abs() <= window)
                    .min_by(|a, b| a.abs().total_cmp(&b.abs()))
            })
            .collect();
        ::signal::order::median(&mut d)
    })
}

/// `kinematic` shifted by [`plate_offsets`] (a kind without a pair is left as it is); the
/// events stay sorted by time.
pub fn calibrate(plates: &[Event], kinematic: &[Event], window: f64) -> Vec<Event> {
    let offsets = plate_offsets(plates, kinematic, window);
    crate::shifted(kinematic, |k| {
        match k.kind {
            Kind::FootStrike => offsets[0],
            Kind::FootOff => offsets[1],
        }
        .unwrap_or(0.0)
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Side, Source};

    fn ev(side: Side, kind: Kind, index: f64, source: Source) -> Event {
        Event {
            side,
            kind,
            index,
            source,
            plate: None,
        }
    }

    #[test]
    fn kinematic_events_move_by_the_median_lag_of_their_kind() {
        use Kind::*;
        use Side::*;
        let k = Source::Kinematics;
        let p = Source::Plate;
        let kin = vec![
            ev(Left, FootStrike, 100.0, k),
            ev(Right, FootStrike, 150.0, k),
            ev(Left, FootStrike, 200.0, k),
            ev(Left, FootOff, 160.0, k),
        ];
        let plates = vec![
            // Strikes 3 and 5 frames after the markers: median 4.
            ev(Left, FootStrike, 103.0, p),
            ev(Right, FootStrike, 155.0, p),
            // Too far from any kinematic strike of that foot: no pair.
            ev(Right, FootStrike, 400.0, p),
        ];
        assert_eq!(plate_offsets(&plates, &kin, 20.0), [Some(4.0), None]);
        let out = calibrate(&plates, &kin, 20.0);
        let idx: Vec<f64> = out.iter().map(|e| e.index).collect();
        assert_eq!(idx, vec![104.0, 154.0, 160.0, 204.0]);
    }
}
