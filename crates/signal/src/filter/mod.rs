//! Zero-phase IIR filters: two designs run through one forward-backward implementation
//! (`filtfilt.rs`'s `zero_phase`: the odd extension, the pass forward, the pass backward).
//!
//!
//! - [`Iir`]: low-pass Butterworth and Chebyshev II of any order up to [`MAX_ORDER`],
//!   designed as scipy.signal designs them and applied as scipy.signal.filtfilt applies them
//!   (its padding, its initial conditions, its refusal of short signals), so results can be
//!   checked against scipy's numbers. Repair's low-pass stage and the plates' filter run it.
//! - [`Section`]: one second-order Butterworth section (low- or high-pass) run forward and
//!   backward, the "4th-order zero-lag" filter of Winter and the gait papers, over each
//!   finite run of a signal with gaps. Gait's event methods run it.
//!
//! Why two and not one: they differ in their numbers, and each caller's outputs (the
//! repaired files, the events) were made with its own. The section's coefficients are the
//! closed form of the bilinear transform, not scipy's zeros-poles-gain path (equal in exact
//! arithmetic, not in the last bits); it pads by three periods of the cut-off rather than
//! scipy's `3 * max(len(a), len(b))` samples, so a low cut-off's start-up transient still
//! falls outside the samples kept, and shortens the padding to fit a short run instead of
//! refusing it, since a foot's run between gaps may be short; and it filters in direct form
//! I from the first sample's steady state, where scipy's runs direct form II transposed from
//! `lfilter_zi`. Both share the odd extension and the forward-backward passes.

mod butterworth;
mod chebyshev2;
mod filtfilt;
mod section;

use nalgebra::Complex;
use serde::Serialize;

use crate::error::FilterError;

pub use filtfilt::{lfilter_zi, padlen};
pub use section::{zero_lag, Pass, Section};

type C64 = Complex<f64>;
type Result<T> = std::result::Result<T, FilterError>;

/// Highest filter order. The filters run in transfer-function form (as scipy's `filtfilt`
/// with `b, a`), whose coefficients lose precision as the order grows; beyond this the
/// design is refused rather than run inaccurately.
pub const MAX_ORDER: usize = 10;

/// Highest Chebyshev II stopband attenuation, in dB: 200 dB is a ratio of 1e10, well inside
/// what double precision resolves.
pub const MAX_ATTEN_DB: f64 = 200.0;

/// A digital filter in transfer-function form: `b` numerator, `a` denominator, `a[0] == 1`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Iir {
    pub b: Vec<f64>,
    pub a: Vec<f64>,
}

impl Iir {
    /// Low-pass Butterworth of `order` with -3 dB at `cutoff_hz`, as `scipy.signal.butter`.
    pub fn butterworth(order: usize, cutoff_hz: f64, fs: f64) -> Result<Iir> {
        let wn = normalized_cutoff(order, cutoff_hz, fs)?;
        let (z, p, k) = butterworth::prototype(order);
        Ok(digital_lowpass(z, p, k, wn))
    }

    /// Low-pass Chebyshev type II with stopband edge `cutoff_hz` and `atten_db` of stopband
    /// attenuation, as `scipy.signal.cheby2`.
    pub fn cheby2(order: usize, cutoff_hz: f64, atten_db: f64, fs: f64) -> Result<Iir> {
        check_attenuation(atten_db)?;
        let wn = normalized_cutoff(order, cutoff_hz, fs)?;
        let (z, p, k) = chebyshev2::prototype(order, atten_db);
        Ok(digital_lowpass(z, p, k, wn))
    }

    /// Zero-phase forward-backward filtering in place, as `scipy.signal.filtfilt(b, a, x)`
    /// with its defaults. Signals of `padlen()` samples or fewer are refused.
    pub fn filtfilt(&self, x: &mut [f64]) -> Result<()> {
        filtfilt::filtfilt(&self.b, &self.a, x)
    }

    /// The edge padding filtfilt uses: `3 * max(len(a), len(b))`.
    pub fn padlen(&self) -> usize {
        padlen(&self.b, &self.a)
    }
}

/// A Chebyshev II attenuation within what the design resolves (above 0, at most
/// [`MAX_ATTEN_DB`]).
pub fn check_attenuation(atten_db: f64) -> Result<()> {
    if !(atten_db > 0.0 && atten_db <= MAX_ATTEN_DB) {
        return Err(FilterError::Attenuation {
            atten_db,
            max: MAX_ATTEN_DB,
        });
    }
    Ok(())
}

/// An order the designs accept (1 to [`MAX_ORDER`]).
pub fn check_order(order: usize) -> Result<()> {
    if !(1..=MAX_ORDER).contains(&order) {
        return Err(FilterError::FilterOrder {
            order,
            max: MAX_ORDER,
        });
    }
    Ok(())
}

/// Cutoff as a fraction of Nyquist, validated as scipy's iirfilter does.
fn normalized_cutoff(order: usize, cutoff_hz: f64, fs: f64) -> Result<f64> {
    check_order(order)?;
    if !(fs > 0.0 && fs.is_finite()) {
        return Err(FilterError::SampleRate(fs));
    }
    let wn = 2.0 * cutoff_hz / fs;
    if !(wn > 0.0 && wn < 1.0) {
        return Err(FilterError::Cutoff {
            cutoff_hz,
            nyquist_hz: fs / 2.0,
        });
    }
    Ok(wn)
}

/// Analog prototype (zeros, poles, gain) → lp2lp at the prewarped frequency (fs = 2
/// convention) → bilinear → transfer function, the path scipy's iirfilter takes.
fn digital_lowpass(z: Vec<C64>, p: Vec<C64>, k: f64, wn: f64) -> Iir {
    let fs = 2.0;
    let warped = 2.0 * fs * (std::f64::consts::PI * wn / fs).tan();
    // lp2lp_zpk
    let degree = p.len() - z.len();
    let z: Vec<C64> = z.iter().map(|&r| r * warped).collect();
    let p: Vec<C64> = p.iter().map(|&r| r * warped).collect();
    let k = k * warped.powi(degree as i32);
    // bilinear_zpk
    let fs2 = C64::new(2.0 * fs, 0.0);
    let mut zz: Vec<C64> = z.iter().map(|&r| (fs2 + r) / (fs2 - r)).collect();
    let pz: Vec<C64> = p.iter().map(|&r| (fs2 + r) / (fs2 - r)).collect();
    zz.resize(zz.len() + degree, C64::new(-1.0, 0.0));
    let num: C64 = z.iter().map(|&r| fs2 - r).product();
    let den: C64 = p.iter().map(|&r| fs2 - r).product();
    let kz = k * (num / den).re;
    // zpk2tf
    let b = poly(&zz).into_iter().map(|c| kz * c).collect();
    let a = poly(&pz);
    Iir { b, a }
}

/// Coefficients of the monic polynomial with the given roots, highest power first, built by
/// successive convolution in root order as numpy.poly does; the roots come in conjugate
/// pairs, so the imaginary parts are round-off and dropped.
fn poly(roots: &[C64]) -> Vec<f64> {
    let mut c = vec![C64::new(1.0, 0.0)];
    for &r in roots {
        let mut next = vec![C64::new(0.0, 0.0); c.len() + 1];
        for (i, &ci) in c.iter().enumerate() {
            next[i] += ci;
            next[i + 1] -= ci * r;
        }
        c = next;
    }
    c.into_iter().map(|x| x.re).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn invalid_designs_are_typed_errors() {
        assert_eq!(
            Iir::butterworth(0, 6.0, 100.0),
            Err(FilterError::FilterOrder {
                order: 0,
                max: MAX_ORDER
            })
        );
        assert!(matches!(
            Iir::butterworth(4, 50.0, 100.0),
            Err(FilterError::Cutoff { .. })
        ));
        assert!(matches!(
            Iir::butterworth(4, 0.0, 100.0),
            Err(FilterError::Cutoff { .. })
        ));
        assert!(matches!(
            Iir::butterworth(4, 6.0, 0.0),
            Err(FilterError::SampleRate(_))
        ));
        assert_eq!(
            Iir::cheby2(4, 6.0, 0.0, 100.0),
            Err(FilterError::Attenuation {
                atten_db: 0.0,
                max: MAX_ATTEN_DB
            })
        );
    }

    #[test]
    fn butterworth_second_order_closed_form() {
        // Unit DC gain: sum(b) == sum(a).
        let f = Iir::butterworth(2, 10.0, 100.0).unwrap();
        let sb: f64 = f.b.iter().sum();
        let sa: f64 = f.a.iter().sum();
        assert!((sb - sa).abs() < 1e-14);
        assert_eq!(f.a[0], 1.0);
        assert_eq!(f.b.len(), 3);
    }
}
