//! The options of the plates' computation, one clap struct that `forces` and `export`
//! flatten, so that a default or a flag's name changes in one place.

use c3dfix::ForceOptions;

#[derive(clap::Args, Debug, Clone)]
pub struct PlateArgs {
    /// |Fz| in N below which the COP and free moment are undefined, and which bounds the
    /// contact intervals.
    #[arg(long, default_value_t = c3dfix::platforms::DEFAULT_THRESHOLD_N)]
    pub threshold: f64,
    /// Subtract each channel's mean over FORCE_PLATFORM:ZERO's frames first.
    #[arg(long)]
    pub zero_baseline: bool,
    /// Zero-phase low-pass filter of the plates' channels: butterworth:ORDER:CUTOFF_HZ or
    /// cheby2:ORDER:CUTOFF_HZ:ATTEN_DB (as for markers).
    #[arg(long)]
    pub lowpass: Option<String>,
}

impl PlateArgs {
    /// The library's options for these flags.
    pub fn options(&self) -> ForceOptions {
        ForceOptions {
            threshold: self.threshold,
            zero_baseline: self.zero_baseline,
            lowpass: self.lowpass.clone(),
        }
    }
}
