//! The unloaded level of a plate: the stretch of a trial where nothing stands on it, whose
//! channel means are the plate's offsets.
//!
//! Most plates do not read zero when nothing stands on them: the corpora hold unloaded
//! levels from a pull of 2 900 N to a push of 46 N. Left in, a pull of 15 N puts that offset
//! into every exported row and a push of 11 N makes the noise cross a 10 N threshold over and
//! over. A FORCE_PLATFORM:ZERO range names the stretch when the lab set one; otherwise it is
//! found here, on the plate's own data.
//!
//! The rule rests on one fact: a load adds to the push (a foot only pushes), so the unloaded
//! level is the lowest level the plate holds steadily. Windows of [`WINDOW_S`] are judged by
//! their mean push and by how much the total force moves in them (the root of the summed
//! variances of its three components, which no rotation changes); among the windows moving
//! no more than noise does — at most [`FLAT_FACTOR`] times the stillest window's spread plus
//! [`FLAT_FLOOR_N`] — the lowest is the stretch. Ringing after a foot leaves, a heel strike
//! or a drift all move more than that.
//!
//! A plate loaded from the first sample to the last (a subject standing through a static
//! trial) has no unloaded stretch, and its lowest steady level is the subject's weight (or
//! the part of it on that plate). On `c3d-samples`, where the constants were chosen, the
//! largest unloaded push is 46 N (`sample_25`) and the smallest standing load 578 N; a level
//! above [`MAX_UNLOADED_N`], 30 % over the largest offset, is taken as a load and nothing is
//! subtracted (the caller says so). Checked on `c3d-extra` and `c3d-more` (see
//! `docs/plates.md`), where the smallest standing load is 65 N (one plate of six under a
//! subject standing across them, `btkdata_Res16bits`): kept, as it should be.

use std::ops::Range;

/// The length of the windows judged, in seconds: long enough to average a plate's noise
/// (25 samples at 100 Hz), short enough to fit between two footfalls of a walk.
pub const WINDOW_S: f64 = 0.25;

/// A window is steady when its spread is at most this many times the stillest window's …
pub const FLAT_FACTOR: f64 = 2.0;

/// … plus this (N), so that a plate whose stillest window is exactly flat (a writer that
/// stores zeros when unloaded) still has steady windows with a few quanta of noise.
pub const FLAT_FLOOR_N: f64 = 0.5;

/// The shortest FORCE_PLATFORM:ZERO range taken, in seconds: a mean over fewer than five
/// periods of 50 Hz mains hum keeps part of the hum in the level. Shorter ranges (Vicon's
/// one-frame [1, 1]; `Gait with EMG.c3d`'s first frame reads 0 where the plate rests at a
/// push of 23 N) give way to the quiet stretch.
pub const MIN_ZERO_S: f64 = 0.1;

/// The highest push (N) an unloaded plate is taken to read (see the module's doc).
pub const MAX_UNLOADED_N: f64 = 60.0;

/// The stretch of the plate's samples that reads its unloaded level, and that level (the
/// mean push over it, N).
#[derive(Debug, Clone, PartialEq)]
pub struct Quiet {
    pub range: Range<usize>,
    pub level: f64,
    /// How much the total force moves in the stretch (N, the root of the summed variances
    /// of its components).
    pub spread: f64,
}

/// The smallest pull (N) whose subtraction could lift a plate's zero readings to a contact:
/// half the lowest contact threshold the library uses (10 N). Smaller levels are kept as
/// they always were, whatever their noise.
pub const MIN_LIFTING_PULL_N: f64 = 5.0;

/// Whether a stretch read as a pull of `level` (negative push) with `spread` can be the
/// plate's offset: a steady offset moves less than its own size. A "level" that is no more
/// than the mean of pulls coming and going (a plate reading 0 on most samples and a pull
/// of 95 N on the others, as `c3d-labs`' sprint plate 2 does) is no offset, and subtracting
/// it would turn every sample at 0 into a push that nothing made: a pull is never a load.
/// Pulls under [`MIN_LIFTING_PULL_N`] make no contact and are taken as before.
pub fn steady_pull(level: f64, spread: f64) -> bool {
    level > -MIN_LIFTING_PULL_N || spread < -level
}

/// The mean of `push` over `range` (the level a baseline stretch removes); NaN when the
/// range holds a non-finite sample or nothing.
pub fn level(push: &[f64], range: &Range<usize>) -> f64 {
    let Some(v) = push.get(range.clone()) else {
        return f64::NAN;
    };
    if v.is_empty() {
        return f64::NAN;
    }
    v.iter().sum::<f64>() / v.len() as f64
}

/// Whether a stretch at this push level can be the unloaded plate.
pub fn unloaded(level: f64) -> bool {
    level.is_finite() && level <= MAX_UNLOADED_N
}

/// The quietest low stretch of a plate: `push` (N) and `force` (the force vectors, any
/// frame) sampled at `rate` Hz. `None` when the trial is shorter than one window or holds
/// no window of finite samples. The level may be above [`MAX_UNLOADED_N`]: the caller
/// decides (see [`unloaded`]).
pub fn quiet_stretch(push: &[f64], force: &[[f64; 3]], rate: f64) -> Option<Quiet> {
    quiet_in_windows(push, force, rate, WINDOW_S)
}

/// The length of the windows judged when no [`WINDOW_S`] window is unloaded, in seconds:
/// under the shortest flight of a run (running flights last about 0.08–0.15 s; a plate
/// under a treadmill's belt is loaded in every quarter second of a run, and unloaded only
/// in its flights).
pub const FLIGHT_WINDOW_S: f64 = 0.05;

/// [`quiet_stretch`] for a plate whose every [`WINDOW_S`] window carries a load: the
/// quietest low stretch among windows of [`FLIGHT_WINDOW_S`], which fit in the flights
/// between a run's steps. A plate loaded throughout (a subject standing) has none unloaded
/// here either, and the caller says so.
pub fn quiet_flight(push: &[f64], force: &[[f64; 3]], rate: f64) -> Option<Quiet> {
    quiet_in_windows(push, force, rate, FLIGHT_WINDOW_S)
}

/// The quietest low stretch among windows of `window_s` seconds (at least 5 samples).
fn quiet_in_windows(push: &[f64], force: &[[f64; 3]], rate: f64, window_s: f64) -> Option<Quiet> {
    let n = push.len().min(force.len());
    let w = if rate.is_finite() && rate > 0.0 {
        ((window_s * rate).round() as usize).max(5)
    } else {
        5
    };
    if n < w {
        return None;
    }
    let step = (w / 2).max(1);
    // (start, mean push, spread) of every window of finite samples.
    let mut windows: Vec<(usize, f64, f64)> = Vec::new();
    let mut s = 0;
    loop {
        let p = &push[s..s + w];
        let f = &force[s..s + w];
        if p.iter().chain(f.iter().flatten()).all(|v| v.is_finite()) {
            let mean = p.iter().sum::<f64>() / w as f64;
            let mut var = 0.0;
            for k in 0..3 {
                let m = f.iter().map(|v| v[k]).sum::<f64>() / w as f64;
                var += f.iter().map(|v| (v[k] - m).powi(2)).sum::<f64>() / w as f64;
            }
            windows.push((s, mean, var.sqrt()));
        }
        if s + w >= n {
            break;
        }
        // The last window ends at the last sample.
        s = (s + step).min(n - w);
    }
    let stillest = windows.iter().map(|w| w.2).fold(f64::INFINITY, f64::min);
    let steady = FLAT_FACTOR * stillest + FLAT_FLOOR_N;
    let (start, mean, spread) = windows
        .into_iter()
        .filter(|w| w.2 <= steady)
        .min_by(|a, b| a.1.total_cmp(&b.1))?;
    Some(Quiet {
        range: start..start + w,
        level: mean,
        spread,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A plate at a pull of 15 N with a 600 N stance in the middle and a 40 N sway-free
    /// ringing after it: the stretch is the offset's, wherever the load is.
    #[test]
    fn the_lowest_steady_stretch_is_the_offset() {
        let rate = 100.0;
        let mut push: Vec<f64> = (0..300)
            .map(|i| -15.0 + 0.3 * ((i * 7919) % 13) as f64 / 13.0)
            .collect();
        push[100..160].iter_mut().for_each(|v| *v += 600.0);
        // Ringing below the offset right after the foot leaves: moves, so not steady.
        for (k, v) in push[160..190].iter_mut().enumerate() {
            *v += 40.0 * (k as f64).sin();
        }
        let force: Vec<[f64; 3]> = push.iter().map(|&p| [0.0, 0.0, -p]).collect();
        let q = quiet_stretch(&push, &force, rate).expect("a stretch");
        assert!(q.range.end <= 100 || q.range.start >= 190, "{q:?}");
        assert!((q.level + 14.85).abs() < 0.2, "{q:?}");
        assert!(unloaded(q.level));
        assert!((level(&push, &q.range) - q.level).abs() < 1e-12);
    }

    #[test]
    fn a_standing_subject_is_no_offset() {
        let push = vec![590.0; 500];
        let force: Vec<[f64; 3]> = push.iter().map(|&p| [0.0, 0.0, -p]).collect();
        let q = quiet_stretch(&push, &force, 100.0).expect("a stretch");
        assert!(!unloaded(q.level));
    }

    #[test]
    fn too_short_or_not_finite() {
        assert!(quiet_stretch(&[0.0; 4], &[[0.0; 3]; 4], 100.0).is_none());
        let push = vec![f64::NAN; 100];
        let force = vec![[0.0; 3]; 100];
        assert!(quiet_stretch(&push, &force, 100.0).is_none());
        assert!(level(&[1.0], &(0..2)).is_nan());
        assert!(!unloaded(f64::NAN));
    }
}
