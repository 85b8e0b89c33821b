//! Chebyshev type II analog prototype, as scipy.signal.cheb2ap.

use nalgebra::Complex;
use std::f64::consts::PI;

type C64 = Complex<f64>;

/// Zeros, poles and gain of the analog Chebyshev II low-pass of order `n` whose stopband
/// starts at 1 rad/s with `rs` dB of attenuation.
pub(super) fn prototype(n: usize, rs: f64) -> (Vec<C64>, Vec<C64>, f64) {
    let nf = n as f64;
    let de = 1.0 / (10f64.powf(0.1 * rs) - 1.0).sqrt();
    let mu = (1.0 / de).asinh() / nf;
    // Odd orders skip m = 0, whose zero would sit at infinity.
    let ms: Vec<f64> = if n % 2 == 1 {
        let lo = (0..)
            .map(|i| -(nf) + 1.0 + 2.0 * i as f64)
            .take_while(|&m| m < 0.0);
        let hi = (0..).map(|i| 2.0 + 2.0 * i as f64).take_while(|&m| m < nf);
        lo.chain(hi).collect()
    } else {
        (0..n).map(|i| -(nf) + 1.0 + 2.0 * i as f64).collect()
    };
    let z: Vec<C64> = ms
        .iter()
        .map(|&m| -(C64::new(0.0, 1.0) / (m * PI / (2.0 * nf)).sin()).conj())
        .collect();
    let p: Vec<C64> = (0..n)
        .map(|i| {
            let m = -(nf) + 1.0 + 2.0 * i as f64;
            let q = -(C64::new(0.0, PI * m / (2.0 * nf))).exp();
            let q = C64::new(mu.sinh() * q.re, mu.cosh() * q.im);
            C64::new(1.0, 0.0) / q
        })
        .collect();
    let num: C64 = p.iter().map(|&r| -r).product();
    let den: C64 = z.iter().map(|&r| -r).product();
    let k = (num / den).re;
    (z, p, k)
}
