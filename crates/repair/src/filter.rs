//! Which low-pass filter a repair runs ([`FilterSpec`], checked once) and the filter itself,
//! designed as scipy.signal designs it and applied zero-phase as scipy.signal.filtfilt
//! applies it: the design and the filtering live in the `signal` crate, shared with gait's
//! zero-lag filter; this module is the repair's door to them, its errors in
//! [`RepairError`]'s words.

use serde::Serialize;

use crate::error::{RepairError, Result};

pub use signal::filter::{lfilter_zi, padlen, Iir, MAX_ATTEN_DB, MAX_ORDER};

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
                signal::filter::check_attenuation(atten_db)?;
                (order, cutoff_hz)
            }
        };
        signal::filter::check_order(order)?;
        if !(cutoff > 0.0 && cutoff.is_finite()) {
            return Err(RepairError::CutoffNotPositive(cutoff));
        }
        Ok(())
    }

    /// The digital filter for sample rate `fs`.
    pub fn design(&self, fs: f64) -> Result<Iir> {
        let iir = match *self {
            FilterSpec::Butterworth { order, cutoff_hz } => Iir::butterworth(order, cutoff_hz, fs),
            FilterSpec::Cheby2 {
                order,
                cutoff_hz,
                atten_db,
            } => Iir::cheby2(order, cutoff_hz, atten_db, fs),
        };
        Ok(iir?)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn invalid_specs_are_typed_errors() {
        let butter = |order, cutoff_hz| FilterSpec::Butterworth { order, cutoff_hz };
        assert_eq!(
            butter(0, 6.0).design(100.0),
            Err(RepairError::FilterOrder {
                order: 0,
                max: MAX_ORDER
            })
        );
        assert!(matches!(
            butter(4, 50.0).design(100.0),
            Err(RepairError::Cutoff { .. })
        ));
        assert!(matches!(
            butter(4, 6.0).design(0.0),
            Err(RepairError::SampleRate(_))
        ));
        assert_eq!(
            FilterSpec::Cheby2 {
                order: 4,
                cutoff_hz: 6.0,
                atten_db: 0.0
            }
            .design(100.0),
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
            butter(2, -1.0).validate(),
            Err(RepairError::CutoffNotPositive(-1.0))
        );
    }
}
