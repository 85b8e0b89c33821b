//! The gait-cycle parameters Vicon Nexus reports ("Generate Gait Cycle Parameters"), per
//! side, from a trial's foot strikes and foot offs and the toe markers, on plain arrays.
//!
//! Definitions (Vicon, "How does Nexus (Plug-in Gait) and Polygon calculate Gait Cycle
//! Parameters", support FAQ; checked value by value against the ANALYSIS group Nexus wrote
//! into `sample_11/2198928.c3d` and `HansUniVie__MuscleLength__test.c3d`):
//!
//! - **the cycle**: Nexus uses the *first* cycle of each side where all the events it needs
//!   are found: a Foot Strike, the next Foot Strike of the same side, and between them a
//!   Foot Off of that side and a Foot Off and a Foot Strike of the other side. Later cycles
//!   are not averaged (Polygon can average; Nexus does not).
//! - **a side's stride alone**: where no such cycle is found but a side has two Foot
//!   Strikes with its Foot Off between them (a trial whose events were marked on one foot),
//!   Nexus reports what needs no other foot: Cadence, Walking Speed, Stride Time, Foot Off
//!   and Stride Length (the ANALYSIS group of c3d-labs' `BMClab__BMC__C_S05_T08_3_Cycle.c3d`,
//!   Left, held apart from the rule's making); so does this module, and says what is left out.
//! - **Stride Time** (s): from the cycle's foot strike to the next of the same side.
//! - **Cadence** (steps/min): 120 / stride time (two steps per stride; Nexus' 150.94 for a
//!   0.795 s stride in `2198928.c3d`).
//! - **Step Time** (s): from the other foot's strike inside the cycle to the cycle's
//!   closing strike.
//! - **Opposite Foot Off**, **Opposite Foot Contact**, **Foot Off** (%): the other foot's
//!   off and strike and this foot's off inside the cycle, as % of the stride time.
//! - **Single Support** (s): opposite foot contact − opposite foot off.
//! - **Double Support** (s): (opposite foot off − strike) + (foot off − opposite foot contact).
//! - **Stride Length** (m): the distance between the toe marker's positions at the cycle's
//!   two foot strikes (Nexus' default marker is LTOE / RTOE).
//! - **Step Length** (m): the toe at the cycle's closing strike against the other toe at its
//!   strike inside the cycle, measured along the stride (the horizontal direction from the
//!   toe's first to its second position).
//! - *Worked out from the data* (the FAQ says only "the marker position at the time"): the
//!   positions are taken [`NEXUS_LAG_FRAMES`] frame after each event time, interpolated
//!   between frames. Nexus' lengths in `HansUniVie…test` (a float file) are reproduced to
//!   0.4 mm by the toe at the frame after the event's nearest frame; `2198928.c3d` (an
//!   integer DEC file) follows no single rule tried. One frame late, interpolated, keeps
//!   all eight reference lengths within 3.8 mm; at the event time itself one step is 6.0 mm
//!   off, at the nearest frame one stride 6.1 mm. The step along a lab axis instead of the
//!   stride is up to 14 mm off, along the pelvis' travel 6.2 mm (at the event time).
//! - **Walking Speed** (m/s): stride length / stride time.
//! - **Step Width** (m, not in the reference files): the other toe at its strike inside the
//!   cycle, its horizontal distance from the line of this toe's two positions (the line of
//!   progression of this foot).
//! - **Limp Index** (no unit, not in the reference files): this foot's contact time over the
//!   other foot's, both from the cycle's events: foot off / (100 − opposite foot contact +
//!   opposite foot off), percentages of the cycle; 1 for a symmetric gait.

use crate::axes::Vertical;
use crate::error::{Error, Result};
use crate::{Kind, Side};
use serde::Serialize;

/// How many frames after an event time the toe positions are taken (see the module's
/// documentation: worked out from Nexus' values, not from its documentation).
pub const NEXUS_LAG_FRAMES: f64 = 1.0;

/// A foot strike or foot off at a time (seconds, on the trial's time base).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct TimedEvent {
    pub side: Side,
    pub kind: Kind,
    pub time: f64,
}

/// The toe trajectories lengths are measured on: `[x, y, z]` per frame in millimetres, NaN
/// where missing, frame `i` at `start + i / rate` seconds.
#[derive(Debug, Clone, Copy)]
pub struct Toes<'a> {
    pub left: &'a [[f64; 3]],
    pub right: &'a [[f64; 3]],
    /// Seconds of frame 0.
    pub start: f64,
    /// Frames per second.
    pub rate: f64,
    /// The lab's vertical (steps and widths are horizontal).
    pub vertical: Vertical,
}

impl Toes<'_> {
    fn of(&self, side: Side) -> &[[f64; 3]] {
        match side {
            Side::Left => self.left,
            Side::Right => self.right,
        }
    }

    /// The toe of `side` at `time`, linearly interpolated between the two frames around it;
    /// `None` where either is missing or the time lies outside the frames.
    pub fn at(&self, side: Side, time: f64) -> Option<[f64; 3]> {
        let t = self.of(side);
        let f = (time - self.start) * self.rate;
        if !f.is_finite() || f < 0.0 || t.is_empty() || f > (t.len() - 1) as f64 {
            return None;
        }
        let i = (f.floor() as usize).min(t.len() - 1);
        let j = (i + 1).min(t.len() - 1);
        let w = f - i as f64;
        let (a, b) = (t[i], t[j]);
        let p = [0, 1, 2].map(|k| a[k] + (b[k] - a[k]) * w);
        p.iter().all(|v| v.is_finite()).then_some(p)
    }
}

/// The events of one side's cycle (seconds). The other side's are `None` for a stride of
/// one side alone (no cycle of the side holds them).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Cycle {
    pub side: Side,
    pub strike: f64,
    pub next_strike: f64,
    pub foot_off: f64,
    pub opposite_off: Option<f64>,
    pub opposite_strike: Option<f64>,
}

/// One side's parameters (times in seconds, percentages of the cycle, lengths in metres;
/// `None` where the toe markers could not give a length, and for what needs the other
/// foot's events on a stride of one side alone).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct SideParameters {
    pub cycle: Cycle,
    pub cadence: f64,
    pub walking_speed: Option<f64>,
    pub stride_time: f64,
    pub step_time: Option<f64>,
    pub opposite_foot_off: Option<f64>,
    pub opposite_foot_contact: Option<f64>,
    pub foot_off: f64,
    pub single_support: Option<f64>,
    pub double_support: Option<f64>,
    pub stride_length: Option<f64>,
    pub step_length: Option<f64>,
    pub step_width: Option<f64>,
    pub limp_index: Option<f64>,
}

/// One reported value, named as Nexus names it in the ANALYSIS group.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Parameter {
    /// "Left" or "Right".
    pub context: &'static str,
    pub name: &'static str,
    pub value: f64,
    pub unit: &'static str,
}

/// Nexus' parameter names and units, in the order its ANALYSIS group lists them, then
/// the two this crate adds (Nexus' later versions name them so).
pub const NAMES: [(&str, &str); 13] = [
    ("Cadence", "steps/min"),
    ("Walking Speed", "m/s"),
    ("Stride Time", "s"),
    ("Step Time", "s"),
    ("Opposite Foot Off", "%"),
    ("Opposite Foot Contact", "%"),
    ("Foot Off", "%"),
    ("Single Support", "s"),
    ("Double Support", "s"),
    ("Stride Length", "m"),
    ("Step Length", "m"),
    ("Step Width", "m"),
    ("Limp Index", ""),
];

impl SideParameters {
    /// The values in [`NAMES`]' order, lengths left out where unknown.
    pub fn parameters(&self) -> Vec<Parameter> {
        let values = [
            Some(self.cadence),
            self.walking_speed,
            Some(self.stride_time),
            self.step_time,
            self.opposite_foot_off,
            self.opposite_foot_contact,
            Some(self.foot_off),
            self.single_support,
            self.double_support,
            self.stride_length,
            self.step_length,
            self.step_width,
            self.limp_index,
        ];
        NAMES
            .iter()
            .zip(values)
            .filter_map(|(&(name, unit), v)| {
                v.map(|value| Parameter {
                    context: self.cycle.side.context(),
                    name,
                    value,
                    unit,
                })
            })
            .collect()
    }
}

/// Both sides' parameters, and what could not be reported, in words.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct GaitParameters {
    /// Left first; a side without a complete cycle is absent (and named in `warnings`).
    pub sides: Vec<SideParameters>,
    pub warnings: Vec<String>,
}

impl GaitParameters {
    /// Every value, Left's then Right's, each side in [`NAMES`]' order.
    pub fn parameters(&self) -> Vec<Parameter> {
        self.sides.iter().flat_map(|s| s.parameters()).collect()
    }
}

/// The first complete cycle of `side` among `events` (sorted by time), as Nexus chooses it.
pub fn first_cycle(events: &[TimedEvent], side: Side) -> Option<Cycle> {
    let other = match side {
        Side::Left => Side::Right,
        Side::Right => Side::Left,
    };
    let strikes: Vec<f64> = events
        .iter()
        .filter(|e| e.side == side && e.kind == Kind::FootStrike)
        .map(|e| e.time)
        .collect();
    let first_between = |s: Side, k: Kind, a: f64, b: f64| {
        events
            .iter()
            .find(|e| e.side == s && e.kind == k && e.time > a && e.time < b)
            .map(|e| e.time)
    };
    strikes.windows(2).find_map(|w| {
        let (a, b) = (w[0], w[1]);
        Some(Cycle {
            side,
            strike: a,
            next_strike: b,
            foot_off: first_between(side, Kind::FootOff, a, b)?,
            opposite_off: Some(first_between(other, Kind::FootOff, a, b)?),
            opposite_strike: Some(first_between(other, Kind::FootStrike, a, b)?),
        })
    })
}

/// The first stride of `side` alone among `events` (sorted by time): a Foot Strike, the
/// next of the same side and a Foot Off of that side between them, the other side's
/// events left out; what Nexus reports from when a side has no complete cycle.
pub fn first_stride(events: &[TimedEvent], side: Side) -> Option<Cycle> {
    let strikes: Vec<f64> = events
        .iter()
        .filter(|e| e.side == side && e.kind == Kind::FootStrike)
        .map(|e| e.time)
        .collect();
    strikes.windows(2).find_map(|w| {
        let (a, b) = (w[0], w[1]);
        let off = events
            .iter()
            .find(|e| e.side == side && e.kind == Kind::FootOff && e.time > a && e.time < b)?;
        Some(Cycle {
            side,
            strike: a,
            next_strike: b,
            foot_off: off.time,
            opposite_off: None,
            opposite_strike: None,
        })
    })
}

/// Horizontal unit vector of `d`, `None` when it has no horizontal length.
fn horizontal_unit(d: [f64; 3], v: Vertical) -> Option<[f64; 3]> {
    let h = v.horizontal(d);
    let n = (h[0] * h[0] + h[1] * h[1] + h[2] * h[2]).sqrt();
    (n > 0.0 && n.is_finite()).then(|| h.map(|x| x / n))
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// Stride length, and step length and step width (mm) of `c` from the toes: `None` when a
/// toe is missing at one of the times needed, the step `None` for a stride of one side
/// alone (no other foot's strike to measure it from).
fn lengths(c: &Cycle, toes: &Toes) -> Option<(f64, Option<(f64, f64)>)> {
    let other = match c.side {
        Side::Left => Side::Right,
        Side::Right => Side::Left,
    };
    // A frame after the event, or the trial's last frame when the event is on it (a trial
    // cut at its closing strike, as c3d-labs' BMC cycle: Nexus still gives its length).
    let lag = NEXUS_LAG_FRAMES / toes.rate;
    let last = toes.start + toes.of(c.side).len().saturating_sub(1) as f64 / toes.rate;
    let at = |side: Side, t: f64| toes.at(side, (t + lag).min(last.max(t)));
    let a = at(c.side, c.strike)?;
    let b = at(c.side, c.next_strike)?;
    let stride = sub(b, a);
    let step = match c.opposite_strike {
        None => None,
        Some(t) => {
            let o = at(other, t)?;
            let dir = horizontal_unit(stride, toes.vertical)?;
            let step = toes.vertical.horizontal(sub(b, o));
            let along = dot(step, dir);
            let lateral = sub(step, dir.map(|x| x * along));
            Some((along, dot(lateral, lateral).sqrt()))
        }
    };
    Some((dot(stride, stride).sqrt(), step))
}

/// The parameters of both sides from `events` (any order) and, for lengths, the toes.
///
/// Errors: no foot strike or foot off at all, a time that is not finite, or no side with a
/// complete cycle (the message says what each side lacks). A side without a cycle, or
/// lengths the toes cannot give, are left out and said in `warnings`.
pub fn gait_parameters(events: &[TimedEvent], toes: Option<&Toes>) -> Result<GaitParameters> {
    if events.is_empty() {
        return Err(Error::Input(
            "no Foot Strike or Foot Off events (detect them, or write them into the trial first)"
                .into(),
        ));
    }
    if let Some(e) = events.iter().find(|e| !e.time.is_finite()) {
        return Err(Error::Input(format!(
            "a {} {} event has no finite time",
            e.side.context(),
            e.kind.label()
        )));
    }
    let mut sorted = events.to_vec();
    sorted.sort_by(|a, b| a.time.total_cmp(&b.time));
    let mut sides = Vec::new();
    let mut warnings = Vec::new();
    for side in Side::BOTH {
        let Some(cycle) = first_cycle(&sorted, side).or_else(|| {
            first_stride(&sorted, side).inspect(|_| {
                warnings.push(format!(
                    "{}: no complete cycle (the other side's Foot Off and Foot Strike between \
                     two {0} Foot Strikes): from the {0} stride alone, as Nexus does, without \
                     Step Time, the opposite foot's percentages, Single and Double Support, \
                     Step Length, Step Width and Limp Index",
                    side.context()
                ))
            })
        }) else {
            warnings.push(format!(
                "{}: no complete cycle (two {0} Foot Strikes with a {0} Foot Off and the other \
                 side's Foot Off and Foot Strike between them)",
                side.context()
            ));
            continue;
        };
        sides.push(side_parameters(cycle, toes, &mut warnings));
    }
    if sides.is_empty() {
        return Err(Error::Input(warnings.join("; ")));
    }
    Ok(GaitParameters { sides, warnings })
}

/// One side's parameters from its `cycle` (or stride alone) and, for lengths, the toes; what
/// the toes cannot give is said in `warnings`.
fn side_parameters(
    cycle: Cycle,
    toes: Option<&Toes>,
    warnings: &mut Vec<String>,
) -> SideParameters {
    let stride_time = cycle.next_strike - cycle.strike;
    let pct = |t: f64| 100.0 * (t - cycle.strike) / stride_time;
    let (opposite_foot_off, opposite_foot_contact, foot_off) = (
        cycle.opposite_off.map(pct),
        cycle.opposite_strike.map(pct),
        pct(cycle.foot_off),
    );
    let lengths = match toes {
        Some(t) => {
            let l = lengths(&cycle, t);
            if l.is_none() {
                warnings.push(format!(
                    "{}: no lengths: a toe marker is missing a frame after one of the \
                     cycle's foot strikes",
                    cycle.side.context()
                ));
            }
            l
        }
        None => None,
    };
    let stride_length = lengths.map(|l| l.0 / 1000.0);
    let step = lengths.and_then(|l| l.1);
    let both = cycle.opposite_off.zip(cycle.opposite_strike);
    SideParameters {
        cycle,
        cadence: 120.0 / stride_time,
        walking_speed: stride_length.map(|s| s / stride_time),
        stride_time,
        step_time: cycle.opposite_strike.map(|o| cycle.next_strike - o),
        opposite_foot_off,
        opposite_foot_contact,
        foot_off,
        single_support: both.map(|(off, strike)| strike - off),
        double_support: both.map(|(off, strike)| (off - cycle.strike) + (cycle.foot_off - strike)),
        stride_length,
        step_length: step.map(|s| s.0 / 1000.0),
        step_width: step.map(|s| s.1 / 1000.0),
        limp_index: opposite_foot_off
            .zip(opposite_foot_contact)
            .map(|(off, contact)| foot_off / (100.0 - contact + off)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ev(side: Side, kind: Kind, time: f64) -> TimedEvent {
        TimedEvent { side, kind, time }
    }

    /// `2198928.c3d`'s events (Nexus' own), in the file's order.
    fn sample_events() -> Vec<TimedEvent> {
        use Kind::*;
        use Side::*;
        vec![
            ev(Left, FootStrike, 0.288_333),
            ev(Left, FootOff, 0.731_667),
            ev(Right, FootStrike, 0.675),
            ev(Right, FootOff, 1.133_333),
            ev(Left, FootStrike, 1.083_333),
            ev(Left, FootOff, 1.516_667),
            ev(Right, FootStrike, 1.45),
            ev(Right, FootOff, 0.333_333),
        ]
    }

    #[test]
    fn temporal_values_are_nexus_values() {
        let p = gait_parameters(&sample_events(), None).unwrap();
        let l = &p.sides[0];
        // Nexus' ANALYSIS:VALUES of the file, Left.
        assert!((l.cadence - 150.943_39).abs() < 1e-3);
        assert!((l.stride_time - 0.795).abs() < 1e-5);
        assert!((l.step_time.unwrap() - 0.408_333).abs() < 1e-5);
        assert!((l.opposite_foot_off.unwrap() - 5.660_377).abs() < 1e-3);
        assert!((l.opposite_foot_contact.unwrap() - 48.637_318).abs() < 1e-3);
        assert!((l.foot_off - 55.765_198).abs() < 1e-3);
        assert!((l.single_support.unwrap() - 0.341_667).abs() < 1e-5);
        assert!((l.double_support.unwrap() - 0.101_667).abs() < 1e-5);
        let r = &p.sides[1];
        assert!((r.cadence - 154.838_71).abs() < 1e-3);
        assert!((r.opposite_foot_off.unwrap() - 7.311_828).abs() < 1e-3);
        assert!((r.double_support.unwrap() - 0.106_667).abs() < 1e-5);
        // No toes: no lengths, no speed.
        assert_eq!((l.stride_length, l.walking_speed), (None, None));
        assert!(p.parameters().iter().all(|x| x.name != "Stride Length"));
        // Symmetric enough: contact times alike.
        assert!((l.limp_index.unwrap() - 55.765 / (100.0 - 48.637 + 5.660)).abs() < 1e-3);
    }

    #[test]
    fn lengths_from_the_toes() {
        // Toes moving 1.2 m/s along +x (linear, so interpolation is exact), 100 mm apart
        // across; 10 Hz.
        let rate = 10.0;
        let toe = |y: f64| -> Vec<[f64; 3]> {
            (0..40)
                .map(|i| [1200.0 * i as f64 / rate, y, 20.0])
                .collect()
        };
        let (left, right) = (toe(100.0), toe(0.0));
        use Kind::*;
        use Side::*;
        let events = vec![
            ev(Left, FootStrike, 1.0),
            ev(Right, FootOff, 1.1),
            ev(Right, FootStrike, 1.5),
            ev(Left, FootOff, 1.6),
            ev(Left, FootStrike, 2.0),
            ev(Right, FootOff, 2.1),
            ev(Right, FootStrike, 2.5),
            ev(Left, FootOff, 2.6),
        ];
        let toes = Toes {
            left: &left,
            right: &right,
            start: 0.0,
            rate,
            vertical: Vertical { axis: 2, sign: 1.0 },
        };
        let p = gait_parameters(&events, Some(&toes)).unwrap();
        let l = &p.sides[0];
        assert!((l.stride_length.unwrap() - 1.2).abs() < 1e-9, "{l:?}");
        assert!((l.step_length.unwrap() - 0.6).abs() < 1e-9, "{l:?}");
        assert!((l.step_width.unwrap() - 0.1).abs() < 1e-9, "{l:?}");
        assert!((l.walking_speed.unwrap() - 1.2).abs() < 1e-9);
        assert_eq!(p.sides.len(), 2);
        assert_eq!(p.parameters().len(), 26);
        assert_eq!(p.parameters()[0].name, "Cadence");
        assert_eq!(p.parameters()[13].context, "Right");
    }

    #[test]
    fn one_side_only_and_errors() {
        use Kind::*;
        use Side::*;
        let events = vec![
            ev(Left, FootStrike, 1.0),
            ev(Right, FootOff, 1.1),
            ev(Right, FootStrike, 1.5),
            ev(Left, FootOff, 1.6),
            ev(Left, FootStrike, 2.0),
        ];
        let p = gait_parameters(&events, None).unwrap();
        assert_eq!(p.sides.len(), 1);
        assert!(p.warnings[0].starts_with("Right: no complete cycle"));
        let e = gait_parameters(&events[..3], None).unwrap_err();
        assert!(e.to_string().contains("Left: no complete cycle"), "{e}");
        // One side's events alone: its stride, without what needs the other foot.
        let left: Vec<TimedEvent> = events.iter().copied().filter(|e| e.side == Left).collect();
        let p = gait_parameters(&left, None).unwrap();
        let l = &p.sides[0];
        assert_eq!((p.sides.len(), l.stride_time, l.cadence), (1, 1.0, 120.0));
        assert!((l.foot_off - 60.0).abs() < 1e-9);
        assert_eq!(
            (l.step_time, l.opposite_foot_off, l.limp_index),
            (None, None, None)
        );
        let names: Vec<_> = p.parameters().iter().map(|x| x.name).collect();
        assert_eq!(names, ["Cadence", "Stride Time", "Foot Off"]);
        assert!(
            p.warnings[0].contains("from the Left stride alone"),
            "{:?}",
            p.warnings
        );
        assert!(gait_parameters(&[], None).is_err());
        assert!(gait_parameters(&[ev(Left, FootOff, f64::NAN)], None).is_err());
    }
}
