//! Typed errors: configuration and shape problems. Data-driven problems (a gap too long, a
//! segment too short) are not errors; they are reported in [`crate::RepairReport`].

use thiserror::Error;

/// Everything that makes a repair or a filter design refuse to run.
///
/// More kinds may come in later versions, so matches need a `_` arm.
#[non_exhaustive]
#[derive(Debug, Error, Clone, PartialEq)]
pub enum RepairError {
    /// The filter design's own limit travels with the error, so this vocabulary needs nothing
    /// from the filters that use it.
    #[error("filter order {order} must be from 1 to {max}")]
    FilterOrder { order: usize, max: usize },
    #[error("cutoff {cutoff_hz} Hz must be above 0 and below Nyquist ({nyquist_hz} Hz)")]
    Cutoff { cutoff_hz: f64, nyquist_hz: f64 },
    #[error("cutoff {0} Hz must be above 0")]
    CutoffNotPositive(f64),
    #[error("stopband attenuation {atten_db} dB must be above 0 and at most {max}")]
    Attenuation { atten_db: f64, max: f64 },
    #[error("sample rate {0} Hz must be finite and above 0")]
    SampleRate(f64),
    #[error("signal of {len} samples is too short for filtfilt (needs more than {padlen})")]
    TooShort { len: usize, padlen: usize },
    #[error("marker {marker}: {what} has {got} frames, expected {expected}")]
    Shape {
        marker: usize,
        what: &'static str,
        got: usize,
        expected: usize,
    },
    #[error("invalid option: {0}")]
    Option(String),
}

/// Crate-wide result.
pub type Result<T> = std::result::Result<T, RepairError>;

/// The filters' errors in the repair's words: each kind one of [`RepairError`]'s, with the
/// same data, so a repair reports a filter's refusal as it always has.
impl From<signal::FilterError> for RepairError {
    fn from(e: signal::FilterError) -> Self {
        use signal::FilterError as F;
        match e {
            F::FilterOrder { order, max } => RepairError::FilterOrder { order, max },
            F::Cutoff {
                cutoff_hz,
                nyquist_hz,
            } => RepairError::Cutoff {
                cutoff_hz,
                nyquist_hz,
            },
            F::Attenuation { atten_db, max } => RepairError::Attenuation { atten_db, max },
            F::SampleRate(fs) => RepairError::SampleRate(fs),
            F::TooShort { len, padlen } => RepairError::TooShort { len, padlen },
            _ => RepairError::Option(e.to_string()),
        }
    }
}
