//! Butterworth analog prototype, as scipy.signal.buttap.

use nalgebra::Complex;

type C64 = Complex<f64>;

/// Zeros, poles and gain of the normalized analog Butterworth low-pass of order `n`.
pub(super) fn prototype(n: usize) -> (Vec<C64>, Vec<C64>, f64) {
    let nf = n as f64;
    let p = (0..n)
        .map(|i| {
            let m = -(nf) + 1.0 + 2.0 * i as f64;
            -(C64::new(0.0, std::f64::consts::PI * m / (2.0 * nf))).exp()
        })
        .collect();
    (Vec::new(), p, 1.0)
}
