//! A plate's analog channels in physical units, with the baseline and the filter applied,
//! and what is wrong with them.
//!
//! Both the baseline and the filter are linear, so acting on the channels is the same as
//! acting on forces and moments, and it happens before the COP (which is not linear).

use c3d::{Analog, Calibration};
use repair::Iir;
use std::ops::Range;

/// Channels `used` (1-based) of `analog`, `(raw − OFFSET) × SCALE × GEN_SCALE` in double
/// precision, one vector per channel.
pub(super) fn physical(analog: &Analog, cal: &Calibration, used: &[usize]) -> Vec<Vec<f64>> {
    let nch = analog.channels();
    let gen = cal.gen_scale as f64;
    used.iter()
        .map(|&k| {
            let c = k - 1;
            let (offset, scale) = (cal.offset[c] as f64, cal.scale[c] as f64);
            (0..analog.samples())
                .map(|s| (analog.raw[s * nch + c] as f64 - offset) * scale * gen)
                .collect()
        })
        .collect()
}

/// Subtract each channel's mean over `range` (FORCE_PLATFORM:ZERO's samples).
pub(super) fn subtract_baseline(ch: &mut [Vec<f64>], range: &Range<usize>) {
    for v in ch {
        let base = &v[range.clone()];
        let mean = base.iter().sum::<f64>() / base.len() as f64;
        v.iter_mut().for_each(|x| *x -= mean);
    }
}

/// Samples where some channel is not finite.
pub(super) fn non_finite(ch: &[Vec<f64>]) -> usize {
    let n = ch.first().map_or(0, Vec::len);
    (0..n)
        .filter(|&s| ch.iter().any(|v| !v[s].is_finite()))
        .count()
}

/// Positions (in `ch`) of channels that hold one value all through a trial in which some
/// channel of the plate moves: they recorded nothing (btkdata_parameterOverflow's moment
/// channels), and what depends on them is an artefact.
pub(super) fn constant(ch: &[Vec<f64>]) -> Vec<usize> {
    let flat = |v: &Vec<f64>| {
        let first = v.iter().copied().find(|x| x.is_finite());
        v.len() > 1 && first.is_some_and(|f| v.iter().all(|&x| x == f))
    };
    if ch.iter().all(flat) && ch.iter().flatten().all(|&x| x == 0.0) {
        return Vec::new(); // an unused plate: all zero
    }
    (0..ch.len()).filter(|&i| flat(&ch[i])).collect()
}

/// Filter every channel forward and backward; `false` (nothing changed) when they are too
/// short for the filter's padding.
pub(super) fn filter(ch: &mut [Vec<f64>], iir: &Iir) -> bool {
    let n = ch.first().map_or(0, Vec::len);
    if n <= iir.padlen() {
        return false;
    }
    ch.iter_mut().all(|v| iir.filtfilt(v).is_ok())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn baseline_and_checks() {
        let mut ch = vec![vec![1.0, 3.0, 10.0], vec![2.0, 2.0, 2.0]];
        subtract_baseline(&mut ch, &(0..2));
        assert_eq!(ch[0], vec![-1.0, 1.0, 8.0]);
        assert_eq!(ch[1], vec![0.0, 0.0, 0.0]);
        assert_eq!(constant(&ch), vec![1]);
        assert!(constant(&[vec![0.0; 4], vec![0.0; 4]]).is_empty());
        ch[0][2] = f64::NAN;
        assert_eq!(non_finite(&ch), 1);
    }
}
