//! Foot strike and foot off from the foot centre's velocity, by O'Connor, Thorpe,
//! O'Malley & Vaughan (2007), "Automatic detection of gait events using kinematic data",
//! Gait & Posture 25(3): 469–474 (the foot velocity algorithm).
//!
//! The foot centre is the midpoint of the heel and toe markers. Its forward velocity peaks
//! in mid-swing; before that peak its vertical velocity peaks as the foot rises after
//! foot off, and after it the vertical velocity falls to its trough as the foot comes down
//! to land. So: mid-swing at each peak of the forward velocity, foot off at the last
//! vertical-velocity peak before it, foot strike at the first vertical-velocity trough
//! after it (within 0.25 s), as the paper and implementations built on it (pyCGM2's
//! `oconnor`, for one) place them. Both instants are kinematic landmarks a
//! little away from the contact itself; the mean lead or lag is the options' offset,
//! chosen on the tuning labs.
//!
//! "Forward" is along the walking direction of each frame ([`crate::kinematic`]), so turns
//! and either direction of travel work; the foot centre is low-pass filtered
//! ([`KinematicOptions::oconnor_lowpass_hz`]) before it is differentiated, as velocity
//! methods need (pyCGM2 takes a marker cut-off for the same reason).

use crate::kinematic_options::{KinematicOptions, Prepared};
use crate::signal::{self, Pass};
use crate::{Feet, Side};

/// Strikes and offs of one foot (fractional frame indices, before the options' offsets).
pub fn events(
    feet: &Feet,
    side: Side,
    prep: &Prepared,
    opts: &KinematicOptions,
) -> (Vec<f64>, Vec<f64>) {
    let (heel, toe) = feet.foot(side);
    let centre: Vec<[f64; 3]> = heel
        .iter()
        .zip(toe)
        .map(|(h, t)| {
            [
                (h[0] + t[0]) / 2.0,
                (h[1] + t[1]) / 2.0,
                (h[2] + t[2]) / 2.0,
            ]
        })
        .collect();
    let rate = prep.rate;
    let cutoff = opts.oconnor_lowpass_hz;
    let low = |x: Vec<f64>| signal::butterworth(&x, rate, cutoff, Pass::Low);
    let height = low(centre.iter().map(|p| prep.vertical.height(*p)).collect());
    let vz = signal::derivative(&height, rate);
    let comps: Vec<Vec<f64>> = (0..3)
        .map(|k| signal::derivative(&low(centre.iter().map(|p| p[k]).collect()), rate))
        .collect();
    let forward: Vec<f64> = (0..centre.len())
        .map(|i| (0..3).map(|k| comps[k][i] * prep.dir[i][k]).sum())
        .collect();
    let range = |x: &[f64]| match (signal::quantile(x, 0.05), signal::quantile(x, 0.95)) {
        (Some(a), Some(b)) => Some(b - a),
        _ => None,
    };
    let (Some(fwd_range), Some(vz_range)) = (range(&forward), range(&vz)) else {
        return (Vec::new(), Vec::new());
    };
    let swings = signal::maxima(&forward, prep.half, prep.reach, 0.3 * fwd_range);
    let depth = 0.1 * vz_range;
    let window = (0.25 * rate).round() as usize;
    let before = (0.5 * rate).round() as usize;
    let n = vz.len();
    // A local extremum of `sign * vz` at `k` at least `depth` from zero.
    let extremum = |k: usize, sign: f64| -> Option<f64> {
        let (y0, y1, y2) = (sign * vz[k - 1], sign * vz[k], sign * vz[k + 1]);
        (y0.is_finite() && y2.is_finite() && y1 > y0 && y1 >= y2 && y1 >= depth)
            .then(|| k as f64 + signal::parabolic(y0, y1, y2))
    };
    let last = n.saturating_sub(1);
    let mut strikes = Vec::new();
    let mut offs = Vec::new();
    for m in swings {
        let m = m.round() as usize;
        // The first trough after mid-swing.
        if let Some(s) = (m.max(1)..(m + window).min(last)).find_map(|k| extremum(k, -1.0)) {
            strikes.push(s);
        }
        // The last peak before it.
        if let Some(o) = (m.saturating_sub(before).max(1)..m.min(last))
            .rev()
            .find_map(|k| extremum(k, 1.0))
        {
            offs.push(o);
        }
    }
    (strikes, offs)
}
