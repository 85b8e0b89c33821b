//! Foot strike and foot off from how far the foot has come down or gone up, as a fraction
//! of its own swing: the landing is where the heel (or the toe, whichever is first) comes
//! within a fraction of its swing's height above the level it then stands at, and the
//! foot's forward speed within a fraction of its swing's peak; the lift-off is where the
//! toe leaves its stance level by a fraction of the height it then swings to, or its
//! forward speed rises through a fraction of the swing's peak.
//!
//! Why fractions: a marker's height above the sole differs by lab (a heel marker on the
//! calcaneus' back or low on the shoe, a toe marker on the second metatarsal head or the
//! shoe's tip), so a fixed millimetre threshold (the landing refinement's 10 mm) or a
//! position extreme (Zeni) falls where the placement puts it; the fraction of the marker's
//! own excursion is the same for every placement that moves with the foot.
//!
//! Measured, not used (docs/events.md, "Landing and lift-off as fractions of the swing"):
//! the heel approaches the floor slowly over its last few centimetres and its descent
//! slows when the knee extends, so height and vertical-speed fractions fall 40–125 ms
//! before contact; the forward speed's fraction marks the labs' own strikes well and the
//! plates' badly; a metatarsal marker rises as the heel lifts, well before the toe leaves.

use crate::kinematic_options::{KinematicOptions, Prepared};
use crate::signal::{self, lowest, Pass};
use crate::{Feet, Side};

/// Per frame: each part's height, and the foot centre's speed (mm/s) along the walking
/// direction in the lab (NaN where unknown).
struct Foot {
    heel: Vec<f64>,
    toe: Vec<f64>,
    forward: Vec<f64>,
    /// The toe's own speed (mm/s) along the walking direction: it leaves the floor when the
    /// foot centre, still rolling over it, is already moving.
    toe_forward: Vec<f64>,
    /// Each part's vertical velocity (mm/s), low-passed at 10 Hz (O'Connor's cut-off).
    heel_up: Vec<f64>,
    toe_up: Vec<f64>,
}

fn foot(feet: &Feet, side: Side, prep: &Prepared) -> Foot {
    let (heel, toe) = feet.foot(side);
    let v = prep.vertical;
    let n = heel.len();
    let centre: Vec<[f64; 3]> = heel
        .iter()
        .zip(toe)
        .map(|(h, t)| {
            [
                0.5 * (h[0] + t[0]),
                0.5 * (h[1] + t[1]),
                0.5 * (h[2] + t[2]),
            ]
        })
        .collect();
    let along = |x: &[[f64; 3]]| -> Vec<f64> {
        (0..n)
            .map(|i| {
                if i == 0 || i + 1 >= n {
                    return f64::NAN;
                }
                let d = prep.dir[i];
                let (a, b) = (x[i - 1], x[i + 1]);
                (0..3).map(|k| (b[k] - a[k]) * d[k]).sum::<f64>() * prep.rate / 2.0
            })
            .collect()
    };
    let forward = along(&centre);
    let toe_forward = along(toe);
    let heel: Vec<f64> = heel.iter().map(|p| v.height(*p)).collect();
    let toe: Vec<f64> = toe.iter().map(|p| v.height(*p)).collect();
    let up = |h: &[f64]| {
        signal::derivative(
            &signal::butterworth(h, prep.rate, 10.0, Pass::Low),
            prep.rate,
        )
    };
    Foot {
        heel_up: up(&heel),
        toe_up: up(&toe),
        heel,
        toe,
        forward,
        toe_forward,
    }
}

/// Index of the largest finite value of `x` over `[a, b)` (clamped), with the value.
fn highest(x: &[f64], a: f64, b: f64) -> Option<(usize, f64)> {
    let n = x.len();
    let (a, b) = ((a.max(0.0) as usize).min(n), (b.max(0.0) as usize).min(n));
    (a..b)
        .filter(|&k| x[k].is_finite())
        .max_by(|&i, &j| x[i].total_cmp(&x[j]))
        .map(|k| (k, x[k]))
}

/// The first `k` in `from..to` where `x` falls through `thr` (interpolated), both samples
/// known.
fn falls_through(x: &[f64], thr: f64, from: usize, to: usize) -> Option<f64> {
    let to = to.min(x.len().saturating_sub(1));
    (from..to).find_map(|k| {
        let (a, b) = (x[k], x[k + 1]);
        (a.is_finite() && b.is_finite() && a > thr && b <= thr)
            .then(|| k as f64 + (a - thr) / (a - b))
    })
}

/// The last `k` in `from..to` where `x` rises through `thr` (interpolated), both samples
/// known.
fn last_rise_through(x: &[f64], thr: f64, from: usize, to: usize) -> Option<f64> {
    let to = to.min(x.len().saturating_sub(1));
    (from..to).rev().find_map(|k| {
        let (a, b) = (x[k], x[k + 1]);
        (a.is_finite() && b.is_finite() && a <= thr && b > thr)
            .then(|| k as f64 + (thr - a) / (b - a))
    })
}

/// Where one part comes down to within `frac` of its swing's height above its stance
/// level: the swing's highest point in the 0.5 s before `i0`, the stance level the lowest
/// in the 0.5 s after it; searched from that highest point to 0.3 s after `i0`.
fn part_lands(h: &[f64], i0: f64, rate: f64, frac: f64) -> Option<f64> {
    let (_, peak) = highest(h, i0 - 0.5 * rate, i0 + 1.0)?;
    // The search starts at the part's highest point in terminal swing: a toe passes close
    // to the floor in mid-swing (its minimum clearance), rises as the foot reaches out,
    // and comes down only after the heel.
    let (peak_at, _) = highest(h, i0 - 0.2 * rate, i0 + 1.0)?;
    let stance = lowest(h, i0, i0 + 0.5 * rate);
    // A part that does not rise (a marker lost over the swing, or standing) shows no
    // landing; 5 mm is under any swing's clearance.
    if !(stance.is_finite() && peak - stance > 5.0) {
        return None;
    }
    falls_through(
        h,
        stance + frac * (peak - stance),
        peak_at,
        (i0 + 0.3 * rate) as usize,
    )
}

/// Where one part's descent slows to `frac` of its fastest in terminal swing (the 0.2 s
/// before `i0` to 0.1 s after it), searched to 0.3 s after `i0`.
fn part_stops(up: &[f64], i0: f64, rate: f64, frac: f64) -> Option<f64> {
    let down: Vec<f64> = up.iter().map(|v| -v).collect();
    let (at, peak) = highest(&down, i0 - 0.2 * rate, i0 + 0.1 * rate)?;
    if peak <= 0.0 {
        return None;
    }
    falls_through(&down, frac * peak, at, (i0 + 0.3 * rate) as usize)
}

/// The strikes of one foot (fractional frame indices, before the options' offset), one for
/// each of Zeni's strikes `i0`: the later of (a) the first of heel and toe to come down
/// within [`KinematicOptions::landing_height_frac`] of its swing height above its stance
/// level and (b) the foot centre's forward speed falling through
/// [`KinematicOptions::landing_speed_frac`] of its peak in the 0.5 s before `i0` (unused
/// when 0). `i0` itself where neither part shows a landing.
pub fn strikes(
    feet: &Feet,
    side: Side,
    prep: &Prepared,
    zeni_strikes: &[f64],
    opts: &KinematicOptions,
) -> Vec<f64> {
    let f = foot(feet, side, prep);
    let rate = prep.rate;
    zeni_strikes
        .iter()
        .map(|&i0| {
            let frac = opts.landing_height_frac;
            let height = match (
                part_lands(&f.heel, i0, rate, frac),
                part_lands(&f.toe, i0, rate, frac),
            ) {
                (Some(a), Some(b)) => Some(a.min(b)),
                (a, b) => a.or(b),
            };
            let first = |a: Option<f64>, b: Option<f64>| match (a, b) {
                (Some(a), Some(b)) => Some(a.min(b)),
                (a, b) => a.or(b),
            };
            let height = if frac > 0.0 { height } else { None };
            let stops = (opts.landing_vspeed_frac > 0.0)
                .then(|| {
                    first(
                        part_stops(&f.heel_up, i0, rate, opts.landing_vspeed_frac),
                        part_stops(&f.toe_up, i0, rate, opts.landing_vspeed_frac),
                    )
                })
                .flatten();
            let speed = (opts.landing_speed_frac > 0.0)
                .then(|| {
                    let (at, peak) = highest(&f.forward, i0 - 0.5 * rate, i0 + 1.0)?;
                    falls_through(
                        &f.forward,
                        opts.landing_speed_frac * peak,
                        at,
                        (i0 + 0.3 * rate) as usize,
                    )
                })
                .flatten();
            [height, stops, speed]
                .into_iter()
                .flatten()
                .reduce(f64::max)
                .unwrap_or(i0)
        })
        .collect()
}

/// The offs of one foot, one for each of Zeni's offs `j0`: the earlier of (a) the toe's
/// last rise through [`KinematicOptions::lift_height_frac`] of its swing height above its
/// stance level (the lowest in the 0.5 s before `j0`; the swing's highest point in the
/// 0.5 s after it), searched from 0.3 s before `j0` to that highest point (unused when
/// 0), and (b) the foot centre's (or with [`KinematicOptions::lift_speed_of_toe`] the
/// toe's) forward speed rising through [`KinematicOptions::lift_speed_frac`] of its peak
/// in the 0.5 s after `j0` (unused when 0). `j0` itself where neither is seen.
pub fn offs(
    feet: &Feet,
    side: Side,
    prep: &Prepared,
    zeni_offs: &[f64],
    opts: &KinematicOptions,
) -> Vec<f64> {
    let f = foot(feet, side, prep);
    let rate = prep.rate;
    let from = |j0: f64| (j0 - 0.3 * rate).max(0.0) as usize;
    zeni_offs
        .iter()
        .map(|&j0| {
            let height = (opts.lift_height_frac > 0.0)
                .then(|| {
                    let (peak_at, peak) = highest(&f.toe, j0, j0 + 0.5 * rate)?;
                    let stance = lowest(&f.toe, j0 - 0.5 * rate, j0 + 1.0);
                    if !(stance.is_finite() && peak - stance > 5.0) {
                        return None;
                    }
                    let thr = stance + opts.lift_height_frac * (peak - stance);
                    last_rise_through(&f.toe, thr, from(j0), peak_at)
                })
                .flatten();
            let speed = (opts.lift_speed_frac > 0.0)
                .then(|| {
                    let forward = if opts.lift_speed_of_toe {
                        &f.toe_forward
                    } else {
                        &f.forward
                    };
                    let (at, peak) = highest(forward, j0, j0 + 0.5 * rate)?;
                    last_rise_through(forward, opts.lift_speed_frac * peak, from(j0), at)
                })
                .flatten();
            match (height, speed) {
                (Some(a), Some(b)) => a.min(b),
                (a, b) => a.or(b).unwrap_or(j0),
            }
        })
        .collect()
}
