//! The force-plate flags (`--threshold`, `--no-zero-baseline`, `--lowpass`) of the commands
//! that compute plates, as the library's [`c3dfix::ForceOptions`]. The plates themselves, the
//! lab's vertical and `--axes` are the library's ([`c3dfix::force_platforms`],
//! [`c3dfix::axes`]).

use c3dfix::ForceOptions;

/// The force-plate options, one struct for every command that computes plates (`forces`,
/// `plot --forces`; flattened into each command's arguments), mapping onto
/// [`c3dfix::ForceOptions`].
#[derive(clap::Args, Debug, Clone, Default, PartialEq)]
pub struct PlateArgs {
    /// The push in N (how hard a foot presses the plate down; a pull is never a load) below
    /// which the COP and free moment are undefined, and which bounds the contact intervals
    /// [default: 10].
    #[arg(long, value_name = "N")]
    pub threshold: Option<f64>,
    /// Keep each plate's raw values: do not remove its unloaded level (by default each
    /// channel's mean over FORCE_PLATFORM:ZERO's frames, or over the plate's quietest low
    /// stretch, is subtracted).
    #[arg(long)]
    pub no_zero_baseline: bool,
    /// Remove each plate's unloaded level: the default, accepted for old command lines.
    #[arg(long, hide = true, conflicts_with = "no_zero_baseline")]
    pub zero_baseline: bool,
    /// Zero-phase low-pass filter of the plates' channels: butterworth:ORDER:CUTOFF_HZ or
    /// cheby2:ORDER:CUTOFF_HZ:ATTEN_DB (as for markers).
    #[arg(long, value_name = "SPEC")]
    pub lowpass: Option<c3dfix::FilterSpec>,
}

impl PlateArgs {
    pub fn options(&self) -> ForceOptions {
        ForceOptions {
            threshold: self
                .threshold
                .unwrap_or(c3dfix::platforms::DEFAULT_THRESHOLD_N),
            zero_baseline: !self.no_zero_baseline,
            lowpass: self.lowpass,
        }
    }

    /// Whether any option was given (for commands where they apply to one mode only).
    pub fn given(&self) -> bool {
        *self != PlateArgs::default()
    }
}
