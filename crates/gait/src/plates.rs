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
    /// A plate's strike is no foot strike when the plate is first loaded under the front
    /// half of the foot and the foot's heel marker had landed this long (s) before: the
    /// heel landed off the plate and the forefoot rolled onto it (walking2's left foot:
    /// heel down 91 ms before plate 2 is loaded, its centre of pressure first 180 mm ahead
    /// of the heel). The off on that plate is still the foot's. A heel landing alone is not
    /// enough: sample_25's markers lead its plates by 52 ms in both trials (a clock offset),
    /// the centre of pressure first under the heel.
    pub max_heel_lead_s: f64,
}

impl Default for PlateOptions {
    fn default() -> Self {
        PlateOptions {
            threshold_n: 20.0,
            max_foot_distance_mm: 150.0,
            min_contact_s: 0.08,
            max_heel_lead_s: 0.05,
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
                onset_along: onset_along(plate, feet, side, vertical, a, spf, analog_rate),
            });
        }
    }
    let mut out = Vec::new();
    let rate = analog_rate / plates.first().map_or(1, |p| p.samples_per_frame.max(1)) as f64;
    for f in merge_overlapping(falls) {
        for (kind, at) in [(Kind::FootStrike, f.strike), (Kind::FootOff, f.off)] {
            let Some((index, plate)) = at else { continue };
            if kind == Kind::FootStrike
                && f.onset_along >= 0.5
                && heel_down_before(feet, f.side, vertical, index, rate)
                    .is_some_and(|lead| lead > opts.max_heel_lead_s * rate)
            {
                continue;
            }
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

/// How many frames before the plate's strike at `at` the foot's heel marker landed, if it
/// did before it: the first local minimum of its height in the 0.25 s before `at` that
/// lies within 10 mm (the landing refinement's `touch_mm`) of its lowest from 0.25 s
/// before to 0.5 s after `at`. `None` where the heel is an ankle marker standing in (its
/// height says nothing of the landing), or no such minimum is seen with known samples.
fn heel_down_before(
    feet: &Feet,
    side: Side,
    vertical: axes::Vertical,
    at: f64,
    rate: f64,
) -> Option<f64> {
    const TOUCH_MM: f64 = 10.0;
    if feet.heel_is_ankle(side) {
        return None;
    }
    let (heel, _) = feet.foot(side);
    let h: Vec<f64> = heel.iter().map(|p| vertical.height(*p)).collect();
    let n = h.len();
    let back = (0.25 * rate).round() as usize;
    let end = (at.floor().max(0.0) as usize).min(n.saturating_sub(1));
    if end + 2 >= n {
        return None;
    }
    let start = end.saturating_sub(back).max(2);
    let hi = ((at + 0.5 * rate) as usize).min(n);
    let base = h[start.min(hi)..hi]
        .iter()
        .copied()
        .filter(|v| v.is_finite())
        .fold(f64::NAN, f64::min);
    if !base.is_finite() {
        return None;
    }
    (start..end).find_map(|k| {
        let known = h[k - 2..=k + 2].iter().all(|v| v.is_finite());
        let low = known && h[k] < h[k - 1] && h[k] <= h[k + 1] && h[k] - base <= TOUCH_MM;
        low.then_some(at - k as f64)
    })
}

/// Where along `side`'s foot (heel 0, toe 1, projected on the horizontal heel–toe line)
/// the centre of pressure lies over the first 20 ms of a contact from sample `a`: the
/// median; NaN where unknown.
fn onset_along(
    plate: &PlateInput,
    feet: &Feet,
    side: Side,
    vertical: axes::Vertical,
    a: usize,
    spf: usize,
    analog_rate: f64,
) -> f64 {
    let (heel, toe) = feet.foot(side);
    let m = ((0.02 * analog_rate).round() as usize).max(1);
    let t: Vec<f64> = (a..a + m)
        .filter_map(|s| {
            let f = s / spf;
            let (c, h, o) = (plate.cop.get(s)?, heel.get(f)?, toe.get(f)?);
            let (c, h, o) = (
                vertical.horizontal(*c),
                vertical.horizontal(*h),
                vertical.horizontal(*o),
            );
            let ht = [o[0] - h[0], o[1] - h[1], o[2] - h[2]];
            let hc = [c[0] - h[0], c[1] - h[1], c[2] - h[2]];
            let len2: f64 = ht.iter().map(|x| x * x).sum();
            let along = (0..3).map(|k| ht[k] * hc[k]).sum::<f64>() / len2;
            along.is_finite().then_some(along)
        })
        .collect();
    crate::signal::quantile(&t, 0.5).unwrap_or(f64::NAN)
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
    /// Where the centre of pressure first lies along the foot, heel 0 to toe 1 (median
    /// over the contact's first 20 ms; NaN unknown).
    onset_along: f64,
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
            onset_along: f64::NAN,
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
