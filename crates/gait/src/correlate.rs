//! Kinematic events moved to where the foot repeats what it did at the trial's own plate
//! events, as Vicon Nexus' "Autocorrelate Events" does: around each plate event of a foot
//! and kind, a marker's height over a short window is the template; each of that foot's
//! kinematic events of that kind is moved, within a small search range, to where the same
//! marker's height matches the template best (least squares).
//!
//! Why: [`crate::calibrate()`] shifts every kinematic event of a kind by one median lag, but
//! within a trial the methods' lag is not constant (a heel that lands flatter on one step
//! than on the next moves its forward extreme, not the contact). The plate step shows what
//! the foot's markers look like at the contact *in this trial*; a step off the plates that
//! looks the same is at the same phase of its contact. Nothing is learned from another
//! trial or from the file's own events.
//!
//! Measured, not used by default (docs/events.md): the setting chosen on the tuning labs
//! was no worse there than the median shift alone, but worse on the held-out labs' plates
//! (leave-one-out strikes 4.1 / 29.4 → 6.5 / 38.7 ms, median / p95).

use crate::axes::Vertical;
use crate::{Event, Feet, Kind, Side};

/// Which marker's height is matched.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Part {
    Heel,
    Toe,
    /// Heel and toe together (their squared differences summed).
    Both,
}

impl std::str::FromStr for Part {
    type Err = crate::Error;
    fn from_str(s: &str) -> crate::Result<Self> {
        match s.to_ascii_lowercase().as_str() {
            "heel" => Ok(Part::Heel),
            "toe" => Ok(Part::Toe),
            "both" => Ok(Part::Both),
            _ => Err(crate::Error::Input(format!(
                "part {s}: expected heel, toe or both"
            ))),
        }
    }
}

/// The matching's constants (chosen on the tuning labs, docs/events.md).
#[derive(Debug, Clone, PartialEq)]
pub struct CorrelateOptions {
    /// The marker matched for strikes.
    pub strike_part: Part,
    /// The marker matched for offs.
    pub off_part: Part,
    /// Half the template's width (s) around the plate event.
    pub half_window_s: f64,
    /// How far (s) either side of the (calibrated) kinematic event the match is searched:
    /// the calibration has already removed the trial's median lag, so only the step's own
    /// departure from it is left.
    pub search_s: f64,
    /// Compare the heights after removing each window's mean: a floor level that differs
    /// between the plate and the walkway (a plate a few millimetres proud, a thicker mat)
    /// does not move the match.
    pub remove_mean: bool,
}

impl Default for CorrelateOptions {
    fn default() -> Self {
        CorrelateOptions {
            strike_part: Part::Both,
            off_part: Part::Toe,
            half_window_s: 0.1,
            search_s: 0.08,
            remove_mean: true,
        }
    }
}

/// Linear interpolation of `x` at the fractional index `t` (NaN outside or next to a gap).
fn at(x: &[f64], t: f64) -> f64 {
    if t < 0.0 {
        return f64::NAN;
    }
    let i = t.floor() as usize;
    let f = t - t.floor();
    match (x.get(i), x.get(i + 1)) {
        (Some(a), Some(b)) => a * (1.0 - f) + b * f,
        (Some(a), None) if f == 0.0 => *a,
        _ => f64::NAN,
    }
}

/// The heights of one foot's matched markers (one or two signals).
fn signals(feet: &Feet, side: Side, part: Part, v: Vertical) -> Vec<Vec<f64>> {
    let (heel, toe) = feet.foot(side);
    let h = |t: &[[f64; 3]]| t.iter().map(|p| v.height(*p)).collect::<Vec<f64>>();
    match part {
        Part::Heel => vec![h(heel)],
        Part::Toe => vec![h(toe)],
        Part::Both => vec![h(heel), h(toe)],
    }
}

/// Mean squared difference between the signals around `centre` and the templates (each
/// window's mean removed when asked); `None` when a sample is missing.
fn cost(
    sig: &[Vec<f64>],
    templates: &[Vec<f64>],
    centre: f64,
    half: usize,
    remove_mean: bool,
) -> Option<f64> {
    let mut total = 0.0;
    let mut n = 0usize;
    for (x, tpl) in sig.iter().zip(templates) {
        let w: Vec<f64> = (0..=2 * half)
            .map(|j| at(x, centre + j as f64 - half as f64))
            .collect();
        if w.iter().any(|v| !v.is_finite()) {
            return None;
        }
        let shift = if remove_mean {
            w.iter().sum::<f64>() / w.len() as f64 - tpl.iter().sum::<f64>() / tpl.len() as f64
        } else {
            0.0
        };
        for (a, b) in w.iter().zip(tpl) {
            total += (a - shift - b).powi(2);
            n += 1;
        }
    }
    (n > 0).then(|| total / n as f64)
}

/// `kinematic` with each event moved to the best match of its foot's plate events of the same
/// kind (the costs of several plate events summed), searched within
/// [`CorrelateOptions::search_s`] of where it is. An event is left where it is when its foot
/// has no plate event of its kind, when a sample is missing, or when the best match lies at
/// the search's edge (no minimum inside). Sorted by time.
pub fn correlate(
    feet: &Feet,
    rate: f64,
    plates: &[Event],
    kinematic: &[Event],
    opts: &CorrelateOptions,
) -> Vec<Event> {
    let Some(v) = feet.vertical() else {
        return kinematic.to_vec();
    };
    let half = ((opts.half_window_s * rate).round() as usize).max(1);
    let reach = ((opts.search_s * rate).round() as isize).max(1);
    let mut out: Vec<Event> = Vec::with_capacity(kinematic.len());
    for side in Side::BOTH {
        for kind in [Kind::FootStrike, Kind::FootOff] {
            let part = match kind {
                Kind::FootStrike => opts.strike_part,
                Kind::FootOff => opts.off_part,
            };
            let sig = signals(feet, side, part, v);
            // One template per plate event: each signal's window around it.
            let templates: Vec<Vec<Vec<f64>>> = plates
                .iter()
                .filter(|p| p.side == side && p.kind == kind)
                .map(|p| {
                    sig.iter()
                        .map(|x| {
                            (0..=2 * half)
                                .map(|j| at(x, p.index + j as f64 - half as f64))
                                .collect::<Vec<f64>>()
                        })
                        .collect::<Vec<_>>()
                })
                .filter(|t| t.iter().flatten().all(|v| v.is_finite()))
                .collect();
            for k in kinematic
                .iter()
                .filter(|k| k.side == side && k.kind == kind)
            {
                let moved = if templates.is_empty() {
                    None
                } else {
                    best_match(&sig, &templates, k.index, half, reach, opts.remove_mean)
                };
                out.push(Event {
                    index: moved.unwrap_or(k.index),
                    ..*k
                });
            }
        }
    }
    crate::sort_events(&mut out);
    out
}

/// The index near `from` (within `reach` frames) whose windows match the templates best,
/// refined between frames by a parabola through the three costs around the best.
fn best_match(
    sig: &[Vec<f64>],
    templates: &[Vec<Vec<f64>>],
    from: f64,
    half: usize,
    reach: isize,
    remove_mean: bool,
) -> Option<f64> {
    let costs: Vec<Option<f64>> = (-reach..=reach)
        .map(|d| {
            let centre = from + d as f64;
            templates
                .iter()
                .map(|t| cost(sig, t, centre, half, remove_mean))
                .sum::<Option<f64>>()
        })
        .collect();
    let (best, c) = costs
        .iter()
        .enumerate()
        .filter_map(|(i, c)| c.map(|c| (i, c)))
        .min_by(|a, b| a.1.total_cmp(&b.1))?;
    // A minimum at the edge of the search is no match inside it.
    if best == 0 || best + 1 == costs.len() {
        return None;
    }
    let (a, b) = (costs[best - 1]?, costs[best + 1]?);
    let denom = a - 2.0 * c + b;
    let frac = if denom > 0.0 {
        (0.5 * (a - b) / denom).clamp(-0.5, 0.5)
    } else {
        0.0
    };
    Some(from + (best as isize - reach) as f64 + frac)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Source;

    /// A foot whose heel and toe heights are bumps repeating every 100 frames; the "plate"
    /// event sits at frame 250 (the bump's landing), the kinematic events 6 frames early.
    #[test]
    fn events_move_to_the_plate_steps_pattern() {
        let n = 600;
        let bump = |i: usize| {
            let ph = (i % 100) as f64 / 100.0;
            100.0 * (std::f64::consts::PI * ph).sin().powi(4)
        };
        let heel: Vec<[f64; 3]> = (0..n).map(|i| [i as f64, 0.0, 20.0 + bump(i)]).collect();
        let toe: Vec<[f64; 3]> = (0..n)
            .map(|i| [i as f64 + 200.0, 0.0, 30.0 + bump(i + 10)])
            .collect();
        let pelvis: Vec<[f64; 3]> = (0..n).map(|i| [i as f64, 0.0, 1000.0]).collect();
        let feet = Feet {
            left_heel: heel.clone(),
            left_toe: toe.clone(),
            right_heel: heel,
            right_toe: toe,
            pelvis,
            heel_is_ankle: [false; 2],
        };
        let ev = |index: f64, source| Event {
            side: Side::Left,
            kind: Kind::FootStrike,
            index,
            source,
            plate: None,
        };
        let plates = [ev(250.0, Source::Plate)];
        let kin = [ev(144.0, Source::Kinematics), ev(344.5, Source::Kinematics)];
        let out = correlate(&feet, 100.0, &plates, &kin, &CorrelateOptions::default());
        let idx: Vec<f64> = out.iter().map(|e| e.index).collect();
        assert_eq!(idx.len(), 2);
        assert!((idx[0] - 150.0).abs() < 0.05, "{idx:?}");
        assert!((idx[1] - 350.0).abs() < 0.05, "{idx:?}");
    }

    #[test]
    fn an_event_without_a_template_or_with_a_gap_stays() {
        let n = 300;
        let z = |i: usize| 20.0 + 50.0 * ((i as f64) / 15.0).sin();
        let mut heel: Vec<[f64; 3]> = (0..n).map(|i| [i as f64, 0.0, z(i)]).collect();
        for p in heel.iter_mut().skip(180).take(10) {
            *p = [f64::NAN; 3];
        }
        let pelvis: Vec<[f64; 3]> = (0..n).map(|i| [i as f64, 0.0, 1000.0]).collect();
        let feet = Feet {
            left_heel: heel.clone(),
            left_toe: heel.clone(),
            right_heel: heel.clone(),
            right_toe: heel,
            pelvis,
            heel_is_ankle: [false; 2],
        };
        let ev = |side, index: f64, source| Event {
            side,
            kind: Kind::FootStrike,
            index,
            source,
            plate: None,
        };
        let plates = [ev(Side::Left, 60.0, Source::Plate)];
        let kin = [
            ev(Side::Left, 183.0, Source::Kinematics),
            ev(Side::Right, 90.0, Source::Kinematics),
        ];
        let out = correlate(&feet, 100.0, &plates, &kin, &CorrelateOptions::default());
        assert_eq!(out[0].index, 90.0);
        assert_eq!(out[1].index, 183.0);
    }
}
