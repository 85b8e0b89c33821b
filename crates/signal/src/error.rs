//! Typed errors of the filters: a design that cannot be made, a signal too short to filter.

use thiserror::Error;

/// Why a filter design or a zero-phase filtering refuses to run. Each limit travels with the
/// error, so a caller can phrase it in its own words.
///
/// More kinds may come in later versions, so matches need a `_` arm.
#[non_exhaustive]
#[derive(Debug, Error, Clone, PartialEq)]
pub enum FilterError {
    #[error("filter order {order} must be from 1 to {max}")]
    FilterOrder { order: usize, max: usize },
    #[error("cutoff {cutoff_hz} Hz must be above 0 and below Nyquist ({nyquist_hz} Hz)")]
    Cutoff { cutoff_hz: f64, nyquist_hz: f64 },
    #[error("stopband attenuation {atten_db} dB must be above 0 and at most {max}")]
    Attenuation { atten_db: f64, max: f64 },
    #[error("sample rate {0} Hz must be finite and above 0")]
    SampleRate(f64),
    #[error("signal of {len} samples is too short for filtfilt (needs more than {padlen})")]
    TooShort { len: usize, padlen: usize },
}
