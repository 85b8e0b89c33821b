//! Low-pass IIR filters designed as scipy.signal designs them, applied zero-phase as
//! scipy.signal.filtfilt applies them, so results can be checked against scipy's numbers.

mod butterworth;
mod chebyshev2;
mod filtfilt;

use nalgebra::Complex;
use serde::Serialize;

use crate::error::{RepairError, Result};

pub use filtfilt::{lfilter_zi, padlen};

type C64 = Complex<f64>;

/// Highest filter order. The filters run in transfer-function form (as scipy's `filtfilt`
/// with `b, a`), whose coefficients lose precision as the order grows; beyond this the
/// design is refused rather than run inaccurately.
pub const MAX_ORDER: usize = 10;

/// Highest Chebyshev II stopband attenuation, in dB: 200 dB is a ratio of 1e10, well inside
/// what double precision resolves.
pub const MAX_ATTEN_DB: f64 = 200.0;

/// Which low-pass filter to run over each continuous valid segment. The sample rate comes
/// from the trial, so one spec serves trials recorded at different rates.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum FilterSpec {
    /// Butterworth (scipy.signal.butter); `cutoff_hz` is the -3 dB frequency.
    Butterworth { order: usize, cutoff_hz: f64 },
    /// Chebyshev type II (scipy.signal.cheby2); `cutoff_hz` is the stopband edge, where the
    /// attenuation first reaches `atten_db`.
    Cheby2 {
        order: usize,
        cutoff_hz: f64,
        atten_db: f64,
    },
}

impl FilterSpec {
    /// Checks what can be checked without the sample rate.
    pub fn validate(&self) -> Result<()> {
        let (order, cutoff) = match *self {
            FilterSpec::Butterworth { order, cutoff_hz } => (order, cutoff_hz),
            FilterSpec::Cheby2 {
                order,
                cutoff_hz,
                atten_db,
            } => {
                if !(atten_db > 0.0 && atten_db <= MAX_ATTEN_DB) {
                    return Err(RepairError::Attenuation {
                        atten_db,
                        max: MAX_ATTEN_DB,
                    });
                }
                (order, cutoff_hz)
            }
        };
        if !(1..=MAX_ORDER).contains(&order) {
            return Err(RepairError::FilterOrder {
                order,
                max: MAX_ORDER,
            });
        }
        if !(cutoff > 0.0 && cutoff.is_finite()) {
            return Err(RepairError::CutoffNotPositive(cutoff));
        }
        Ok(())
    }

    /// The digital filter for sample rate `fs`.
    pub fn design(&self, fs: f64) -> Result<Iir> {
        match *self {
            FilterSpec::Butterworth { order, cutoff_hz } => Iir::butterworth(order, cutoff_hz, fs),
            FilterSpec::Cheby2 {
                order,
                cutoff_hz,
                atten_db,
            } => Iir::cheby2(order, cutoff_hz, atten_db, fs),
        }
    }
}

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
        if !(atten_db > 0.0 && atten_db <= MAX_ATTEN_DB) {
            return Err(RepairError::Attenuation {
                atten_db,
                max: MAX_ATTEN_DB,
            });
        }
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

/// Cutoff as a fraction of Nyquist, validated as scipy's iirfilter does.
fn normalized_cutoff(order: usize, cutoff_hz: f64, fs: f64) -> Result<f64> {
    if !(1..=MAX_ORDER).contains(&order) {
        return Err(RepairError::FilterOrder {
            order,
            max: MAX_ORDER,
        });
    }
    if !(fs > 0.0 && fs.is_finite()) {
        return Err(RepairError::SampleRate(fs));
    }
    let wn = 2.0 * cutoff_hz / fs;
    if !(wn > 0.0 && wn < 1.0) {
        return Err(RepairError::Cutoff {
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
            Err(RepairError::FilterOrder {
                order: 0,
                max: MAX_ORDER
            })
        );
        assert!(matches!(
            Iir::butterworth(4, 50.0, 100.0),
            Err(RepairError::Cutoff { .. })
        ));
        assert!(matches!(
            Iir::butterworth(4, 0.0, 100.0),
            Err(RepairError::Cutoff { .. })
        ));
        assert!(matches!(
            Iir::butterworth(4, 6.0, 0.0),
            Err(RepairError::SampleRate(_))
        ));
        assert_eq!(
            Iir::cheby2(4, 6.0, 0.0, 100.0),
            Err(RepairError::Attenuation {
                atten_db: 0.0,
                max: MAX_ATTEN_DB
            })
        );
        assert!(FilterSpec::Cheby2 {
            order: 2,
            cutoff_hz: 6.0,
            atten_db: -3.0
        }
        .validate()
        .is_err());
        assert_eq!(
            FilterSpec::Butterworth {
                order: 2,
                cutoff_hz: -1.0
            }
            .validate(),
            Err(RepairError::CutoffNotPositive(-1.0))
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
