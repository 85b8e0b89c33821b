//! Foot strike where the heel's descent is stopped: the peak of its upward acceleration
//! (the height's second derivative) near Zeni's strike. The landing halts a heel (or a
//! malleolus standing in for it) that comes down at a few hundred millimetres a second
//! within a few samples, so its vertical acceleration peaks at the contact, whatever the
//! marker's height above the sole; a position extreme (Zeni) or a minimum of height (the
//! landing refinement) lies where the marker's placement puts it.
//!
//! Measured, not used (docs/events.md): alone it finds too few of the tuning labs' strikes
//! (the heel's largest acceleration is often its rise at heel-off or noise), and joined to
//! the shipped strike mean it worsened the tuning labs' 95th percentile.

use crate::kinematic_options::{KinematicOptions, Prepared};
use crate::signal::{self, Pass};
use crate::{Feet, Side};

/// The strikes of one foot (fractional frame indices, before the options' offset): for each
/// of Zeni's strikes `i0`, the largest upward acceleration of the heel's low-passed height
/// ([`KinematicOptions::impact_lowpass_hz`]) from 0.05 s before `i0` to
/// [`KinematicOptions::impact_after_s`] after it;
/// none where a sample there is missing or no local maximum lies inside.
pub fn strikes(
    feet: &Feet,
    side: Side,
    prep: &Prepared,
    zeni_strikes: &[f64],
    opts: &KinematicOptions,
) -> Vec<f64> {
    let rate = prep.rate;
    let (heel, _) = feet.foot(side);
    let height: Vec<f64> = heel.iter().map(|p| prep.vertical.height(*p)).collect();
    let low = signal::butterworth(&height, rate, opts.impact_lowpass_hz, Pass::Low);
    let acc = signal::derivative(&signal::derivative(&low, rate), rate);
    let n = acc.len();
    zeni_strikes
        .iter()
        .filter_map(|&i0| {
            let a = (i0 - 0.05 * rate).floor().max(1.0) as usize;
            let b = ((i0 + opts.impact_after_s * rate).ceil() as usize).min(n.saturating_sub(1));
            if a >= b || acc[a - 1..=b].iter().any(|v| !v.is_finite()) {
                return None;
            }
            let k = (a..b).max_by(|&x, &y| acc[x].total_cmp(&acc[y]))?;
            (k > a && acc[k] >= acc[k - 1] && acc[k] >= acc[k + 1])
                .then(|| k as f64 + signal::parabolic(acc[k - 1], acc[k], acc[k + 1]))
        })
        .collect()
}
