//! Repair options as typed values (a [`FillMethod`], a [`SpikeSpec`], a [`FilterSpec`],
//! thresholds in mm) with one [`Default`], checked once and turned into the repair
//! library's configuration. The command line and the Python package read the names with
//! the same `FromStr` and both build a [`RepairOptions`], so they accept and refuse the
//! same things.

use crate::error::{Error, Result, Setting};
use repair::{
    FillMethod, FillOptions, FilterSpec, Glob, RepairConfig, SpikeMode, SpikeSpec, Unlabelled,
};

/// Longest gap that may be asked for, in frames (a C3D file holds at most 2³² frames).
pub const MAX_GAP_FRAMES: usize = u32::MAX as usize;

/// The default of `--max-expected-error`. On the 8 923 artificial gaps of the 9 labs no
/// constant was chosen on, each lab's estimates from the model fitted to the other labs
/// (`cargo run --release -p evals --bin fill_eval`, its "a limit of" lines), it leaves
/// 0.4 % of the gaps unfilled: 5 of the 7 fills worse than 50 mm, 21 of the 55 worse than
/// 20 mm, and none of the 8 135 within 5 mm. A limit of 15 mm leaves 0.9 % (6 of 7, 34 of
/// 55, 1 of 8 135), 30 mm leaves 0.1 % (3 of 7, 7 of 55, none).
pub const DEFAULT_MAX_EXPECTED_ERROR_MM: f64 = 20.0;

/// What `repair` does with marker label swaps and label jumps (issue 34), its first stage.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum SwapsMode {
    /// Undo the settled finds (a swap exchanged back, a jump made a gap for the fill);
    /// report the others.
    Fix,
    /// Find and report, change nothing. The default: see [`DEFAULT_SWAPS`].
    #[default]
    Report,
    /// Do not look.
    Off,
}

/// The default of `--swaps`: `report` (docs/swaps.md, "Choosing the default"). On the
/// untouched trials of the labs no constant was chosen on, `fix` would act on 2.8 finds per
/// 10 000 frames (3 in 10 662), not all of them shown to be label errors, and each would
/// change recorded samples; against 72–100 % of injected swaps and 81–87 % of injected jumps
/// it would undo at 99 % precision. A default repair changes no sample a person would keep
/// unasked, so the stage lists what it sees and `fix` is asked for.
pub const DEFAULT_SWAPS: SwapsMode = SwapsMode::Report;

impl std::str::FromStr for SwapsMode {
    type Err = Error;
    fn from_str(s: &str) -> Result<SwapsMode> {
        match s.trim().to_ascii_lowercase().as_str() {
            "fix" => Ok(SwapsMode::Fix),
            "report" => Ok(SwapsMode::Report),
            "off" => Ok(SwapsMode::Off),
            _ => Err(Error::OutOfRange {
                setting: Setting::Swaps,
                value: format!("{s:?}"),
                limits: "expected fix, report or off".into(),
            }),
        }
    }
}

impl std::fmt::Display for SwapsMode {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            SwapsMode::Fix => "fix",
            SwapsMode::Report => "report",
            SwapsMode::Off => "off",
        })
    }
}

/// What `repair` does with the unlabelled samples that are a labelled marker's (issue 47),
/// the stage after the swaps and before the fills.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum ReclaimMode {
    /// Move the settled pieces into their markers (recorded samples, flags and all); report
    /// the others.
    On,
    /// Find and report, change nothing. The default: see [`DEFAULT_RECLAIM`].
    #[default]
    Report,
    /// Do not look.
    Off,
}

/// The default of `--reclaim`: `report` (docs/reclaim.md, "Choosing the default").
pub const DEFAULT_RECLAIM: ReclaimMode = ReclaimMode::Report;

impl std::str::FromStr for ReclaimMode {
    type Err = Error;
    fn from_str(s: &str) -> Result<ReclaimMode> {
        match s.trim().to_ascii_lowercase().as_str() {
            "on" => Ok(ReclaimMode::On),
            "report" => Ok(ReclaimMode::Report),
            "off" => Ok(ReclaimMode::Off),
            _ => Err(Error::OutOfRange {
                setting: Setting::Reclaim,
                value: format!("{s:?}"),
                limits: "expected on, report or off".into(),
            }),
        }
    }
}

impl std::fmt::Display for ReclaimMode {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            ReclaimMode::On => "on",
            ReclaimMode::Report => "report",
            ReclaimMode::Off => "off",
        })
    }
}

/// Everything `repair` can be asked to do, typed: names and specs are read (`FromStr`) at
/// each front end's door, so a misspelt method or filter is refused there, and written back
/// (`Display`) in reports and the C3DFIX record as one spelling.
#[derive(Debug, Clone, PartialEq)]
pub struct RepairOptions {
    /// How gaps are filled (names: [`FillMethod::NAMED`]).
    pub fill: FillMethod,
    /// Longest gap (frames) to fill; longer ones are left and reported.
    pub max_gap: usize,
    /// Leave gaps whose expected fill error is above this many mm, reported as `uncertain`
    /// with the estimate; `None` fills every gap a method can fill.
    pub max_expected_error_mm: Option<f64>,
    /// `hampel[:K[:NSIGMA]]`, or `None` for no spike removal.
    pub spikes: Option<SpikeSpec>,
    /// `gap` (refill spikes with the fill method) or `median` (MATLAB's hampel).
    pub spike_mode: SpikeMode,
    /// Deviations below this many millimetres are never spikes.
    pub spike_min_mm: f64,
    /// Judge raw coordinates (the classic identifier) rather than residuals from a local
    /// robust prediction.
    pub spike_classic: bool,
    /// `butterworth:ORDER:CUTOFF_HZ` or `cheby2:ORDER:CUTOFF_HZ:ATTEN_DB`, or `None`.
    pub lowpass: Option<FilterSpec>,
    /// Repair only these markers (labels); every marker still serves as a donor.
    pub markers: Option<Vec<String>>,
    /// Also treat samples at exactly (0, 0, 0) as missing.
    pub zero_invalid: bool,
    /// Label swaps and jumps, the first stage: fixed, reported or not looked for.
    pub swaps: SwapsMode,
    /// Labels that also mark a point as unlabelled, beside the common placeholders
    /// ([`repair::unlabelled::is_common_placeholder`]): such points are no markers of the
    /// repair (not filled, no donors, no swaps), counted apart and left as recorded.
    pub unlabelled: Option<Glob>,
    /// Unlabelled samples that are a marker's: moved back, reported or not looked for.
    pub reclaim: ReclaimMode,
}

impl Default for RepairOptions {
    /// The defaults of every front end (the command line's flags and the Python functions'
    /// keywords are checked against these by tests): `auto` fill up to 200 frames, gaps
    /// expected worse than 20 mm left, no spikes, no filter.
    fn default() -> Self {
        RepairOptions {
            fill: FillMethod::Auto,
            max_gap: 200,
            max_expected_error_mm: Some(DEFAULT_MAX_EXPECTED_ERROR_MM),
            spikes: None,
            spike_mode: SpikeMode::Gap,
            spike_min_mm: 5.0,
            spike_classic: false,
            lowpass: None,
            markers: None,
            zero_invalid: false,
            swaps: DEFAULT_SWAPS,
            unlabelled: None,
            reclaim: DEFAULT_RECLAIM,
        }
    }
}

impl RepairOptions {
    /// Which points are unlabelled under these options.
    pub fn unlabelled_rule(&self) -> Unlabelled {
        self.unlabelled
            .clone()
            .map_or_else(Unlabelled::common, Unlabelled::with_pattern)
    }

    /// Check every option, once, and build the repair library's configuration in
    /// millimetres ([`RepairConfig::in_units`] turns it to a file's units). Nothing here
    /// depends on a file, so a run checks before it touches one.
    pub fn config(&self) -> Result<RepairConfig> {
        if !(1..=MAX_GAP_FRAMES).contains(&self.max_gap) {
            return Err(Error::options(format!(
                "max gap {} must be from 1 to {MAX_GAP_FRAMES} frames",
                self.max_gap
            )));
        }
        if !(self.spike_min_mm.is_finite() && self.spike_min_mm >= 0.0) {
            return Err(Error::options(format!(
                "spike minimum {} mm must be a finite number ≥ 0",
                self.spike_min_mm
            )));
        }
        if let Some(e) = self.max_expected_error_mm {
            if !(e > 0.0 && e.is_finite()) {
                return Err(Error::options(format!(
                    "max expected error {e} mm must be a finite number above 0 (or off)"
                )));
            }
        }
        let fill = FillOptions {
            method: self.fill,
            max_gap: Some(self.max_gap),
            max_expected_error: self.max_expected_error_mm,
            ..FillOptions::default()
        };
        let spikes = self
            .spikes
            .map(|s| s.options(self.spike_mode, self.spike_min_mm, !self.spike_classic));
        RepairConfig::new(spikes, fill, self.lowpass).map_err(|e| Error::options(e.to_string()))
    }
}

/// Parse `MM` or `off` (`None`).
pub fn max_expected_error(s: &str) -> Result<Option<f64>> {
    if s.trim().eq_ignore_ascii_case("off") {
        return Ok(None);
    }
    let v: f64 = s.trim().parse().map_err(|_| {
        Error::options(format!(
            "max expected error {s:?}: expected a positive number of mm or off"
        ))
    })?;
    if !(v > 0.0 && v.is_finite()) {
        return Err(Error::options(format!(
            "max expected error {s:?}: expected a positive number of mm or off"
        )));
    }
    Ok(Some(v))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn option_values_are_checked_once_in_the_configuration() {
        let o = RepairOptions {
            spikes: Some("hampel:7:2.5".parse().unwrap()),
            spike_mode: SpikeMode::Median,
            spike_min_mm: 4.0,
            max_expected_error_mm: Some(10.0),
            ..RepairOptions::default()
        };
        let c = o.config().unwrap();
        let s = c.spikes().unwrap();
        assert_eq!(
            (s.half_window, s.nsigma, s.mode, s.min_deviation, s.detrend),
            (7, 2.5, SpikeMode::Median, 4.0, true)
        );
        // In metres: the millimetre values divided by 1000, nothing else changed.
        let m = c.clone().in_units(1000.0);
        assert_eq!(m.spikes().unwrap().min_deviation, 4.0 / 1000.0);
        assert_eq!(m.fill().max_expected_error, Some(10.0 / 1000.0));
        assert_eq!(m.fill().mm_per_unit, 1000.0);
        assert_eq!(m.fill().method, c.fill().method);
        for (bad, why) in [
            ("hampel:1000000000", "from 1 to 1000"),
            ("hampel:18446744073709551615", "from 1 to 1000"),
            ("hampel:3:nan", "nsigma"),
        ] {
            let o = RepairOptions {
                spikes: Some(bad.parse().unwrap()),
                ..RepairOptions::default()
            };
            let e = o.config().unwrap_err().to_string();
            assert!(e.contains(why), "{bad}: {e}");
        }
        let cutoff = RepairOptions {
            lowpass: Some("butterworth:4:-1".parse().unwrap()),
            ..RepairOptions::default()
        };
        assert!(cutoff.config().unwrap_err().to_string().contains("cutoff"));
        assert_eq!(max_expected_error("off").unwrap(), None);
        assert_eq!(max_expected_error(" 12.5").unwrap(), Some(12.5));
        assert!(max_expected_error("0").is_err());
        assert!(max_expected_error("much").is_err());
    }

    #[test]
    fn swaps_modes_read_back() {
        assert_eq!(" Fix".parse::<SwapsMode>().unwrap(), SwapsMode::Fix);
        assert_eq!("off".parse::<SwapsMode>().unwrap().to_string(), "off");
        let e = "undo".parse::<SwapsMode>().unwrap_err();
        assert!(
            matches!(
                e,
                Error::OutOfRange {
                    setting: Setting::Swaps,
                    ..
                }
            ),
            "{e}"
        );
    }

    #[test]
    fn defaults_are_every_front_ends() {
        let d = RepairOptions::default();
        assert_eq!(
            (d.fill.to_string(), d.spike_mode.to_string(), d.max_gap),
            ("auto".to_string(), "gap".to_string(), 200)
        );
        let c = d.config().unwrap();
        assert_eq!(c.fill().method, FillMethod::Auto);
        assert!(c.spikes().is_none() && c.filter().is_none());
        let bad = RepairOptions {
            max_gap: 0,
            ..RepairOptions::default()
        };
        assert!(bad.config().is_err());
    }
}
