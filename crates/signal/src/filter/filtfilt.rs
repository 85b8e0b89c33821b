//! The one forward-backward filtering ([`zero_phase`]) both designs run through, and
//! scipy.signal.filtfilt with its defaults on top of it: odd extension of padlen samples at
//! each end, lfilter_zi initial conditions scaled by the first sample, forward then backward
//! pass.

use crate::error::FilterError;

/// Zero-phase filtering of `x` in place: `x` extended at each end by `pad` samples of its
/// odd reflection (`2 x[0] - x[k]`, as scipy's `odd_ext`), `pass` run over the extension,
/// the result reversed and `pass` run again, then reversed back and its middle kept.
/// `pass` filters a slice in place, starting from its own first sample's steady state.
/// `pad` must be below `x.len()`.
pub(super) fn zero_phase(x: &mut [f64], pad: usize, mut pass: impl FnMut(&mut [f64])) {
    let n = x.len();
    let mut ext = Vec::with_capacity(n + 2 * pad);
    ext.extend((1..=pad).rev().map(|i| 2.0 * x[0] - x[i]));
    ext.extend_from_slice(x);
    ext.extend((1..=pad).map(|i| 2.0 * x[n - 1] - x[n - 1 - i]));
    pass(&mut ext);
    ext.reverse();
    pass(&mut ext);
    ext.reverse();
    x.copy_from_slice(&ext[pad..pad + n]);
}

/// filtfilt's default padding: `3 * max(len(a), len(b))`.
pub fn padlen(b: &[f64], a: &[f64]) -> usize {
    3 * a.len().max(b.len())
}

/// Steady-state initial conditions for a unit step, as scipy.signal.lfilter_zi (explicit
/// solution of `zi = A zi + B` for the companion matrix; same values as its linear solve).
pub fn lfilter_zi(b: &[f64], a: &[f64]) -> Vec<f64> {
    let (b, a) = normalized(b, a);
    let n = a.len();
    if n < 2 {
        return Vec::new();
    }
    let asum_all: f64 = a.iter().sum();
    let bsum: f64 = b[1..].iter().sum::<f64>() - b[0] * a[1..].iter().sum::<f64>();
    let mut zi = vec![0.0; n - 1];
    zi[0] = bsum / asum_all;
    let mut asum = 1.0;
    let mut csum = 0.0;
    for k in 1..n - 1 {
        asum += a[k];
        csum += b[k] - a[k] * b[0];
        zi[k] = asum * zi[0] - csum;
    }
    zi
}

/// `b` and `a` padded to equal length and divided by `a[0]`.
fn normalized(b: &[f64], a: &[f64]) -> (Vec<f64>, Vec<f64>) {
    let n = a.len().max(b.len());
    let a0 = a.first().copied().unwrap_or(1.0);
    let mut bb: Vec<f64> = b.iter().map(|v| v / a0).collect();
    let mut aa: Vec<f64> = a.iter().map(|v| v / a0).collect();
    bb.resize(n, 0.0);
    aa.resize(n, 0.0);
    (bb, aa)
}

/// Direct form II transposed, in place, starting from state `z` (consumed).
fn lfilter_in_place(b: &[f64], a: &[f64], x: &mut [f64], mut z: Vec<f64>) {
    let m = z.len();
    for v in x.iter_mut() {
        let xn = *v;
        let yn = b[0] * xn + z.first().copied().unwrap_or(0.0);
        for i in 0..m {
            let next = if i + 1 < m { z[i + 1] } else { 0.0 };
            z[i] = b[i + 1] * xn + next - a[i + 1] * yn;
        }
        *v = yn;
    }
}

/// Forward-backward filtering of `x` in place, as scipy.signal.filtfilt(b, a, x).
pub(super) fn filtfilt(b: &[f64], a: &[f64], x: &mut [f64]) -> Result<(), FilterError> {
    let pad = padlen(b, a);
    let n = x.len();
    if n <= pad {
        return Err(FilterError::TooShort {
            len: n,
            padlen: pad,
        });
    }
    let (bn, an) = normalized(b, a);
    let zi = lfilter_zi(b, a);
    zero_phase(x, pad, |s| {
        let s0 = s[0];
        lfilter_in_place(&bn, &an, s, zi.iter().map(|z| z * s0).collect());
    });
    Ok(())
}
