//! Foot strike and foot off from the force plates: where a plate's load rises through a
//! threshold and falls back through it (the caller gives the load with the plate's unloaded
//! level removed, as the `c3dfix` library's push is); the
//! side is the foot whose heel–toe line lies nearest the centre of pressure while the plate
//! is loaded.
//!
//! A contact is kept only when one foot alone explains it: the nearer foot within
//! [`PlateOptions::max_foot_distance_mm`] of the centre of pressure for most of the
//! loading, and the other foot clearly farther. Contacts that begin with the trial (the
//! foot was already down) give no strike, those that end with it no off.

use crate::axes;
use crate::{Event, Feet, Kind, Side, Source};

/// One plate's data at the analog rate.
#[derive(Debug, Clone, Copy)]
pub struct PlateInput<'a> {
    /// 1-based, as FORCE_PLATFORM numbers plates.
    pub index: usize,
    /// Analog samples per point frame.
    pub samples_per_frame: usize,
    /// The push on the plate (N): the force along its normal with the plate's unloaded level
    /// removed and its sign made positive for load, as the library computes it once for
    /// every use. Taken as is: a negative value (a pull, or noise below the level) is no
    /// load, never counted by its magnitude.
    pub push: &'a [f64],
    /// The centre of pressure in the lab frame (mm), NaN where unloaded.
    pub cop: &'a [[f64; 3]],
}

/// The detector's constants.
#[derive(Debug, Clone, PartialEq)]
pub struct PlateOptions {
    /// Load (N, after removing the unloaded level) at which a foot is on the plate.
    pub threshold_n: f64,
    /// Farthest the centre of pressure may lie from the foot's heel–toe line (mm).
    pub max_foot_distance_mm: f64,
    /// Shortest contact taken as a footfall (s): a sprinting stance lasts about 0.1 s.
    pub min_contact_s: f64,
}

impl Default for PlateOptions {
    fn default() -> Self {
        PlateOptions {
            threshold_n: 20.0,
            max_foot_distance_mm: 150.0,
            min_contact_s: 0.08,
        }
    }
}

/// Horizontal distance from `p` to the segment `a`–`b` (NaN if any is unknown).
fn to_segment(p: [f64; 3], a: [f64; 3], b: [f64; 3], v: axes::Vertical) -> f64 {
    let (p, a, b) = (v.horizontal(p), v.horizontal(a), v.horizontal(b));
    let ab = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
    let ap = [p[0] - a[0], p[1] - a[1], p[2] - a[2]];
    let len2: f64 = ab.iter().map(|x| x * x).sum();
    let t = if len2 > 0.0 {
        ((0..3).map(|k| ap[k] * ab[k]).sum::<f64>() / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    let d: f64 = (0..3).map(|k| (ap[k] - t * ab[k]).powi(2)).sum();
    d.sqrt()
}

/// Events of every plate (sorted by time). `analog_rate` is in Hz.
pub fn plate_events(
    plates: &[PlateInput],
    feet: &Feet,
    analog_rate: f64,
    opts: &PlateOptions,
) -> Vec<Event> {
    if feet.check().is_err() || !(analog_rate.is_finite() && analog_rate > 0.0) {
        return Vec::new();
    }
    let Some(vertical) = feet.vertical() else {
        return Vec::new();
    };
    let frames = feet.frames();
    // Each footfall kept: side, plate, contact start and end (frames), whether the contact
    // began with the trial or ends with it.
    let mut falls: Vec<Footfall> = Vec::new();
    for plate in plates {
        let spf = plate.samples_per_frame.max(1);
        // Load only: a pull (negative push) is no load; NaN neither.
        let push: Vec<f64> = plate.push.iter().map(|v| v.max(0.0)).collect();
        let min = (opts.min_contact_s * analog_rate).ceil() as usize;
        for [a, b] in kinetics::contacts(&push, opts.threshold_n, analog_rate) {
            if b + 1 - a < min {
                continue;
            }
            let Some(side) = side_of(plate, feet, vertical, [a, b], spf, frames, opts) else {
                continue;
            };
            let thr = opts.threshold_n;
            let crossing = |lo: usize, hi: usize| {
                let (p0, p1) = (push[lo], push[hi]);
                let t = if (p1 - p0).abs() > 0.0 {
                    ((thr - p0) / (p1 - p0)).clamp(0.0, 1.0)
                } else {
                    0.5
                };
                (lo as f64 + t) / spf as f64
            };
            falls.push(Footfall {
                side,
                strike: (a > 0).then(|| (crossing(a - 1, a), plate.index)),
                off: (b + 1 < push.len()).then(|| (crossing(b, b + 1), plate.index)),
                span: [a as f64 / spf as f64, (b + 1) as f64 / spf as f64],
            });
        }
    }
    let mut out = Vec::new();
    for f in merge_overlapping(falls) {
        for (kind, at) in [(Kind::FootStrike, f.strike), (Kind::FootOff, f.off)] {
            let Some((index, plate)) = at else { continue };
            if index <= (frames.saturating_sub(1)) as f64 {
                out.push(Event {
                    side: f.side,
                    kind,
                    index,
                    source: Source::Plate,
                    plate: Some(plate),
                });
            }
        }
    }
    crate::sort_events(&mut out);
    out
}

/// One foot's contact with one plate, or with several plates at once once merged: the
/// strike and off (frame index and 1-based plate; none where the contact began or ends
/// with the recording) and the loaded span in frames.
#[derive(Debug, Clone, Copy)]
struct Footfall {
    side: Side,
    strike: Option<(f64, usize)>,
    off: Option<(f64, usize)>,
    span: [f64; 2],
}

/// One footfall per stance: a foot that lands across two plates (its heel on one, its
/// forefoot on the next) loads both at once, and each plate alone would give a strike and
/// an off, the later strike and the earlier off being no gait event (c3d-samples'
/// kyowadengyo: right strikes at 1.834 and 1.858 s, offs at 2.060 and 2.454 s). Contacts
/// of the same foot whose loaded spans overlap are one footfall: the strike of the
/// earliest, the off of the latest.
fn merge_overlapping(mut falls: Vec<Footfall>) -> Vec<Footfall> {
    falls.sort_by(|a, b| a.span[0].total_cmp(&b.span[0]));
    let mut out: Vec<Footfall> = Vec::new();
    for f in falls {
        if let Some(m) = out
            .iter_mut()
            .rev()
            .find(|m| m.side == f.side && f.span[0] < m.span[1])
        {
            if f.span[1] > m.span[1] {
                m.span[1] = f.span[1];
                m.off = f.off;
            }
            continue;
        }
        out.push(f);
    }
    out
}

/// The foot that alone stands on the plate during the contact `[a, b]` (samples), if any.
fn side_of(
    plate: &PlateInput,
    feet: &Feet,
    vertical: axes::Vertical,
    [a, b]: [usize; 2],
    spf: usize,
    frames: usize,
    opts: &PlateOptions,
) -> Option<Side> {
    // The middle of the contact: the foot is flat and the centre of pressure is under it.
    let len = b - a;
    let (s0, s1) = (a + len / 5, b - len / 5);
    let mut dist = [Vec::new(), Vec::new()];
    for s in (s0..=s1).step_by(spf) {
        let f = s / spf;
        if f >= frames {
            break;
        }
        let Some(&cop) = plate.cop.get(s) else { break };
        for (k, side) in Side::BOTH.into_iter().enumerate() {
            let (heel, toe) = feet.foot(side);
            let d = to_segment(cop, heel[f], toe[f], vertical);
            if d.is_finite() {
                dist[k].push(d);
            }
        }
    }
    let median = |v: &[f64]| crate::signal::quantile(v, 0.5).unwrap_or(f64::INFINITY);
    let (dl, dr) = (median(&dist[0]), median(&dist[1]));
    let (side, near, far, near_all) = if dl <= dr {
        (Side::Left, dl, dr, &dist[0])
    } else {
        (Side::Right, dr, dl, &dist[1])
    };
    let max = opts.max_foot_distance_mm;
    let within = near_all.iter().filter(|d| **d <= max).count();
    (near <= max && far > near + 100.0 && within * 5 >= near_all.len() * 4).then_some(side)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_footfall_on_one_plate() {
        // 10 frames at 100 Hz, 10 samples per frame; the left foot stands at x = 0, the
        // right at x = 600; the plate (COP at x = 20) is loaded from sample 25 to 74.
        let frames = 10;
        let feet = Feet {
            left_heel: vec![[-100.0, 0.0, 50.0]; frames],
            left_toe: vec![[100.0, 0.0, 30.0]; frames],
            right_heel: vec![[500.0, 0.0, 50.0]; frames],
            right_toe: vec![[700.0, 0.0, 30.0]; frames],
            pelvis: vec![[300.0, 0.0, 950.0]; frames],
            heel_is_ankle: [false; 2],
        };
        // The library's push: unloaded level removed, load positive. A pull of 300 N
        // (samples 80-94, e.g. a plate's drift or a hand pulling) is no load.
        let mut push = vec![0.0; 100];
        for (i, v) in push.iter_mut().enumerate().take(75).skip(25) {
            *v = 700.0 * ((i - 24) as f64 / 51.0 * std::f64::consts::PI).sin();
        }
        for v in push.iter_mut().take(95).skip(80) {
            *v = -300.0;
        }
        let cop: Vec<[f64; 3]> = push
            .iter()
            .map(|v| {
                if v.abs() > 10.0 {
                    [20.0, 5.0, 0.0]
                } else {
                    [f64::NAN; 3]
                }
            })
            .collect();
        let plate = PlateInput {
            index: 2,
            samples_per_frame: 10,
            push: &push,
            cop: &cop,
        };
        let ev = plate_events(
            &[plate],
            &feet,
            1000.0,
            &PlateOptions {
                min_contact_s: 0.01,
                ..PlateOptions::default()
            },
        );
        assert_eq!(ev.len(), 2, "{ev:?}");
        assert_eq!(
            (ev[0].side, ev[0].kind, ev[0].plate),
            (Side::Left, Kind::FootStrike, Some(2))
        );
        assert!(ev[0].index > 2.4 && ev[0].index < 2.6, "{ev:?}");
        assert_eq!(ev[1].kind, Kind::FootOff);
        assert!(ev[1].index > 7.3 && ev[1].index < 7.5, "{ev:?}");
    }

    #[test]
    fn a_foot_across_two_plates_is_one_footfall() {
        let f = |plate, s: f64, o: f64, span: [f64; 2]| Footfall {
            side: Side::Right,
            strike: Some((s, plate)),
            off: Some((o, plate)),
            span,
        };
        // kyowadengyo's right foot: heel on plate 2 at 1.834 s, forefoot on plate 3 from
        // 1.858 s; off plate 2 at 2.060 s, off plate 3 at 2.454 s. Then a later step.
        let merged = merge_overlapping(vec![
            f(3, 111.5, 147.2, [111.5, 147.2]),
            f(2, 110.0, 123.6, [110.0, 123.6]),
            f(1, 160.0, 190.0, [160.0, 190.0]),
        ]);
        assert_eq!(merged.len(), 2);
        assert_eq!(
            (merged[0].strike, merged[0].off),
            (Some((110.0, 2)), Some((147.2, 3)))
        );
        assert_eq!(merged[1].strike, Some((160.0, 1)));
    }
}
