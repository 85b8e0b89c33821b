//! Foot strike and foot off as physical states of the foot's markers, in millimetres and
//! millimetres per second: the strike where the heel or the toe, whichever first, has come
//! down to within a few millimetres of the level it then holds through stance **and** has
//! stopped descending (its vertical speed under a few tens of mm/s); the off where the toe
//! has left its stance level by a few millimetres **and** moves forward.
//!
//! Why: a position extreme (Zeni's) falls where the marker's placement and the walker's
//! style put it, and the landing refinement ([`crate::kinematic::refine_strike`]) takes the
//! first local minimum of the height, which sits after the impact has settled. A marker
//! that stands still at its stance level is on the floor wherever it is glued, so the
//! instant it gets there should carry less of the lab's placement than an extreme does.
//! Whether it does is measured (docs/events.md, "A physically defined strike").

use crate::kinematic_options::{KinematicOptions, Prepared};
use crate::signal::{self, lowest, Pass};
use crate::{Feet, Side};

/// One part's height (mm) and its low-passed vertical velocity (mm/s) per frame.
struct Part {
    height: Vec<f64>,
    up: Vec<f64>,
}

fn part(marker: &[[f64; 3]], prep: &Prepared, lowpass_hz: f64) -> Part {
    let height: Vec<f64> = marker.iter().map(|p| prep.vertical.height(*p)).collect();
    let up = signal::derivative(
        &signal::butterworth(&height, prep.rate, lowpass_hz, Pass::Low),
        prep.rate,
    );
    Part { height, up }
}

/// Index of the largest finite value of `x` over `[a, b)` (clamped).
fn highest_at(x: &[f64], a: f64, b: f64) -> Option<usize> {
    let n = x.len();
    let (a, b) = ((a.max(0.0) as usize).min(n), (b.max(0.0) as usize).min(n));
    (a..b)
        .filter(|&k| x[k].is_finite())
        .max_by(|&i, &j| x[i].total_cmp(&x[j]))
}

/// Where `x` crosses `thr` between samples `k − 1` and `k` (0 at `k − 1`, 1 at `k`); 1 when
/// it does not cross there (the condition already held, or the samples are unknown).
fn crossing(a: f64, b: f64, thr: f64) -> f64 {
    let t = (a - thr) / (a - b);
    if t.is_finite() && (0.0..=1.0).contains(&t) {
        t
    } else {
        1.0
    }
}

/// The first instant after the part's highest point in terminal swing (the 0.2 s before
/// Zeni's strike `i0`) where it stands within `opts.touchdown_mm` of its stance level (its
/// lowest height in the 0.5 s after `i0`) and its vertical speed is under
/// `opts.touchdown_speed_mm_s`, searched to 0.3 s after `i0`. Starting at the highest
/// point skips a toe's minimum clearance in mid-swing, where it also moves level.
fn part_touches(p: &Part, i0: f64, rate: f64, opts: &KinematicOptions) -> Option<f64> {
    let (h, up) = (&p.height, &p.up);
    let n = h.len();
    let level = lowest(h, i0, i0 + 0.5 * rate);
    let from = highest_at(h, i0 - 0.2 * rate, i0 + 1.0)?;
    // A part that does not come down from above its level (lost over the swing, or
    // standing) shows no landing; 5 mm is under any swing's clearance.
    if !(level.is_finite() && h[from] - level > 5.0) {
        return None;
    }
    let (hmax, vmax) = (level + opts.touchdown_mm, opts.touchdown_speed_mm_s);
    let on =
        |k: usize| h[k].is_finite() && up[k].is_finite() && h[k] <= hmax && up[k].abs() <= vmax;
    let to = ((i0 + 0.3 * rate) as usize).min(n);
    let k = (from.max(1)..to).find(|&k| on(k))?;
    // Interpolated: the later of the two conditions' crossings between k − 1 and k.
    let t_height = crossing(h[k - 1], h[k], hmax);
    let t_speed = crossing(up[k - 1].abs(), up[k].abs(), vmax);
    let t = match (h[k - 1] <= hmax, up[k - 1].abs() <= vmax) {
        (true, _) => t_speed,
        (_, true) => t_height,
        _ => t_height.max(t_speed),
    };
    Some((k - 1) as f64 + t)
}

/// The strikes of one foot (fractional frame indices, before the options' offset), one for
/// each of Zeni's strikes: the earlier of the heel's and the toe's touchdown
/// ([`KinematicOptions::touchdown_mm`], [`KinematicOptions::touchdown_speed_mm_s`]); Zeni's
/// own where neither part shows one. None where an ankle marker stands in for the heel: its
/// height says nothing of the landing, and the landing refinement already gives Zeni's plus
/// [`KinematicOptions::ankle_strike_offset_s`] there, so a second copy of it would only
/// weigh the ankle's estimate twice in the mean.
pub fn strikes(
    feet: &Feet,
    side: Side,
    prep: &Prepared,
    zeni_strikes: &[f64],
    opts: &KinematicOptions,
) -> Vec<f64> {
    let rate = prep.rate;
    if feet.heel_is_ankle(side) {
        return Vec::new();
    }
    let (heel, toe) = feet.foot(side);
    let (heel, toe) = (
        part(heel, prep, opts.touchdown_lowpass_hz),
        part(toe, prep, opts.touchdown_lowpass_hz),
    );
    zeni_strikes
        .iter()
        .map(|&i0| {
            match (
                part_touches(&heel, i0, rate, opts),
                part_touches(&toe, i0, rate, opts),
            ) {
                (Some(a), Some(b)) => a.min(b),
                (a, b) => a.or(b).unwrap_or(i0),
            }
        })
        .collect()
}

/// The offs of one foot, one for each of Zeni's offs `j0`: the instant after the toe's last
/// frame on the floor, where a frame is on the floor while the toe stands within
/// [`KinematicOptions::liftoff_mm`] of its stance level (its lowest height in the 0.5 s
/// before `j0`) or moves forward slower than [`KinematicOptions::liftoff_speed_mm_s`];
/// searched back from 0.2 s after `j0` (the toe then swings) to 0.3 s before it. Zeni's own
/// where the toe is not in swing at the search's end or never on the floor within it.
pub fn offs(
    feet: &Feet,
    side: Side,
    prep: &Prepared,
    zeni_offs: &[f64],
    opts: &KinematicOptions,
) -> Vec<f64> {
    let rate = prep.rate;
    let (_, toe_marker) = feet.foot(side);
    let toe = part(toe_marker, prep, opts.touchdown_lowpass_hz);
    let n = toe.height.len();
    // The toe's speed along the walking direction, low-passed as its height is.
    let along: Vec<f64> = (0..n)
        .map(|i| {
            let d = prep.dir[i];
            (0..3).map(|k| toe_marker[i][k] * d[k]).sum::<f64>()
        })
        .collect();
    let forward = signal::derivative(
        &signal::butterworth(&along, rate, opts.touchdown_lowpass_hz, Pass::Low),
        rate,
    );
    let h = &toe.height;
    zeni_offs
        .iter()
        .map(|&j0| {
            let level = lowest(h, j0 - 0.5 * rate, j0 + 1.0);
            if !level.is_finite() {
                return j0;
            }
            let (hmin, vmin) = (level + opts.liftoff_mm, opts.liftoff_speed_mm_s);
            let known = |k: usize| h[k].is_finite() && forward[k].is_finite();
            let grounded = |k: usize| h[k] <= hmin || forward[k] <= vmin;
            let hi = ((j0 + 0.2 * rate) as usize).min(n.saturating_sub(1));
            let lo = (j0 - 0.3 * rate).max(0.0) as usize;
            if hi <= lo || !known(hi) || grounded(hi) {
                return j0;
            }
            let Some(k) = (lo..hi).rev().find(|&k| !known(k) || grounded(k)) else {
                return j0;
            };
            if !known(k) {
                return j0;
            }
            // Interpolated: the later of the two conditions' crossings between k and k + 1.
            let t_height = crossing(h[k], h[k + 1], hmin);
            let t_speed = crossing(forward[k], forward[k + 1], vmin);
            let t = match (h[k] > hmin, forward[k] > vmin) {
                (true, _) => t_speed,
                (_, true) => t_height,
                _ => t_height.max(t_speed),
            };
            k as f64 + t
        })
        .collect()
}
