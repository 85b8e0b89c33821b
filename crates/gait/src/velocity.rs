//! Foot strike and foot off where the foot's markers stop and start moving, after Bonci et
//! al. (2022), "An algorithm for accurate marker-based gait event detection in healthy and
//! pathological populations during complex motor tasks", Front. Bioeng. Biotechnol. 10:
//! 868928 (its Zeni pre-detection refined by 3-D speed thresholds), which builds on
//! Ghoussayni et al. (2004)'s sagittal velocity threshold and Bruening & Ridge (2014)'s
//! thresholds scaled to the walking speed.
//!
//! At Zeni's strike the heel is at its forward extreme relative to the pelvis, so it
//! moves over the floor at about the walking speed; it lands and stops within the next
//! few tenths of a second. The strike is the first instant after Zeni's where the heel's
//! 3-D speed falls below [`KinematicOptions::velocity_heel_ratio`] × the walking speed or
//! the toe's below [`KinematicOptions::velocity_toe_ratio`] × (whichever part lands first:
//! toe-first landings count). Likewise at Zeni's off the toe moves at about the walking
//! speed, having just left the floor: the off is the last instant before it where the
//! toe's speed rose through [`KinematicOptions::velocity_toe_ratio`] × the walking speed.
//! A stationary foot is a physical state the marker's placement on the foot does not
//! shift, unlike an extreme relative to the pelvis; the ratios are chosen on the tuning
//! labs (docs/events.md).
//!
//! The walking speed is the trial's median pelvis speed over its walking frames; the
//! markers are low-passed ([`KinematicOptions::oconnor_lowpass_hz`], as for O'Connor's
//! velocities) before they are differentiated.

use crate::kinematic_options::{KinematicOptions, Prepared};
use crate::signal::{self, Pass};
use crate::{Feet, Side};

/// 3-D speed (mm/s) of `marker`, low-passed at `cutoff_hz` first (NaN where unknown).
fn speed(marker: &[[f64; 3]], rate: f64, cutoff_hz: f64) -> Vec<f64> {
    let comps: Vec<Vec<f64>> = (0..3)
        .map(|k| {
            let x: Vec<f64> = marker.iter().map(|p| p[k]).collect();
            signal::derivative(&signal::butterworth(&x, rate, cutoff_hz, Pass::Low), rate)
        })
        .collect();
    (0..marker.len())
        .map(|i| (0..3).map(|k| comps[k][i].powi(2)).sum::<f64>().sqrt())
        .collect()
}

/// The trial's walking speed (mm/s): the median speed of the pelvis over the frames with a
/// walking direction.
pub fn walking_speed(prep: &Prepared) -> Option<f64> {
    let s = speed(&prep.pelvis, prep.rate, 6.0);
    let v: Vec<f64> = s
        .iter()
        .zip(&prep.dir)
        .filter(|(v, d)| v.is_finite() && d[0].is_finite())
        .map(|(v, _)| *v)
        .collect();
    signal::quantile(&v, 0.5).filter(|v| *v > 0.0)
}

/// Where `x` crosses `thr` between samples `k` and `k + 1` (fractional index), linear.
fn crossing(x: &[f64], k: usize, thr: f64) -> f64 {
    let (a, b) = (x[k], x[k + 1]);
    let t = if (b - a).abs() > 0.0 {
        ((thr - a) / (b - a)).clamp(0.0, 1.0)
    } else {
        0.5
    };
    k as f64 + t
}

/// Strikes and offs of one foot (fractional frame indices, before the options' offsets),
/// refined from Zeni's (`zeni_strikes`, `zeni_offs`). An event whose search finds no
/// crossing with known speeds on both sides is left out.
pub fn events(
    feet: &Feet,
    side: Side,
    prep: &Prepared,
    zeni_strikes: &[f64],
    zeni_offs: &[f64],
    opts: &KinematicOptions,
) -> (Vec<f64>, Vec<f64>) {
    let Some(v) = walking_speed(prep) else {
        return (Vec::new(), Vec::new());
    };
    let rate = prep.rate;
    let (heel, toe) = feet.foot(side);
    let cutoff = opts.oconnor_lowpass_hz;
    let (hs, ts) = (speed(heel, rate, cutoff), speed(toe, rate, cutoff));
    let (heel_thr, toe_thr) = (opts.velocity_heel_ratio * v, opts.velocity_toe_ratio * v);
    let n = hs.len();
    let reach = (0.3 * rate).round() as usize;
    // The first fall through the threshold after `i0`, within reach.
    let fall = |x: &[f64], thr: f64, i0: f64| -> Option<f64> {
        let a = i0.floor().max(0.0) as usize;
        (a..(a + reach).min(n.saturating_sub(1)))
            .find(|&k| x[k].is_finite() && x[k + 1].is_finite() && x[k] >= thr && x[k + 1] < thr)
            .map(|k| crossing(x, k, thr))
    };
    let strikes = zeni_strikes
        .iter()
        .filter_map(
            |&i0| match (fall(&hs, heel_thr, i0), fall(&ts, toe_thr, i0)) {
                (Some(h), Some(t)) => Some(h.min(t)),
                (h, t) => h.or(t),
            },
        )
        .collect();
    // The last rise through the threshold before `j0`, within reach.
    let offs = zeni_offs
        .iter()
        .filter_map(|&j0| {
            let b = (j0.ceil().max(0.0) as usize).min(n.saturating_sub(1));
            (b.saturating_sub(reach)..b)
                .rev()
                .find(|&k| {
                    ts[k].is_finite()
                        && ts[k + 1].is_finite()
                        && ts[k] < toe_thr
                        && ts[k + 1] >= toe_thr
                })
                .map(|k| crossing(&ts, k, toe_thr))
        })
        .collect();
    (strikes, offs)
}
