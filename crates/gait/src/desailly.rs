//! Foot strike and foot off from high-pass filtered forward positions, by Desailly,
//! Daniel, Sardain & Lacouture (2009), "Foot contact event detection using kinematic data
//! in cerebral palsy children and normal adults gait", Gait & Posture 29(1): 76–80 (the
//! high pass algorithm, HPA).
//!
//! The forward positions of the heel and the toe (metatarsal) markers are high-pass
//! filtered: the progression and the slow part of the swing go, and what is left swings
//! about zero with sharp turns where the foot meets and leaves the floor. The strike is at
//! each maximum of the filtered heel, the off at each minimum of the filtered toe. Here the
//! cut-off follows the trial's own stride frequency (found from its Zeni strikes), so slow
//! pathological walking and fast walking are filtered alike; the multiple,
//! [`KinematicOptions::desailly_cutoff_ratio`], is chosen on the tuning labs. The paper
//! reports 1 ± 23 ms (strike) and 2 ± 25 ms (off) against plates in children with cerebral
//! palsy, where position-extreme methods drift.
//!
//! "Forward" is the displacement along the walking direction of each frame summed over the
//! trial ([`crate::kinematic`]), so curved paths keep their progression in one signal;
//! each run of valid samples is summed and filtered on its own.

use crate::kinematic_options::{KinematicOptions, Prepared};
use crate::signal::{self, Pass};
use crate::{Feet, Side};

/// Forward position of `marker` (mm): its displacement along the walking direction summed
/// from the start of each run of frames where both are known (NaN elsewhere).
fn forward_position(marker: &[[f64; 3]], dir: &[[f64; 3]]) -> Vec<f64> {
    let ok = |i: usize| marker[i].iter().chain(&dir[i]).all(|v| v.is_finite());
    let mut out = vec![f64::NAN; marker.len()];
    for i in 0..marker.len() {
        if !ok(i) {
            continue;
        }
        out[i] = if i > 0 && out[i - 1].is_finite() {
            out[i - 1]
                + (0..3)
                    .map(|k| (marker[i][k] - marker[i - 1][k]) * dir[i][k])
                    .sum::<f64>()
        } else {
            0.0
        };
    }
    out
}

/// Strikes and offs of one foot (fractional frame indices, before the options' offsets);
/// `stride_hz` is the trial's stride frequency.
pub fn events(
    feet: &Feet,
    side: Side,
    prep: &Prepared,
    stride_hz: f64,
    opts: &KinematicOptions,
) -> (Vec<f64>, Vec<f64>) {
    let (heel, toe) = feet.foot(side);
    let cutoff = opts.desailly_cutoff_ratio * stride_hz;
    let filtered = |m: &[[f64; 3]]| {
        signal::butterworth(
            &forward_position(m, &prep.dir),
            prep.rate,
            cutoff,
            Pass::High,
        )
    };
    let heel = filtered(heel);
    let toe: Vec<f64> = filtered(toe).into_iter().map(|v| -v).collect();
    let peaks = |x: &[f64]| match (signal::quantile(x, 0.05), signal::quantile(x, 0.95)) {
        (Some(a), Some(b)) => signal::maxima(x, prep.half, prep.reach, 0.25 * (b - a)),
        _ => Vec::new(),
    };
    (peaks(&heel), peaks(&toe))
}
