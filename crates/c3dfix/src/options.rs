//! Repair options as people give them (method names, `hampel:K:NSIGMA`,
//! `butterworth:ORDER:CUTOFF_HZ`, thresholds in mm), checked and turned into the repair
//! library's configuration for one file's units. The command line and the Python package
//! both build an [`RepairOptions`], so they accept and refuse the same things.

use crate::error::{Error, Result};
use crate::markers::mm_per_unit;
use repair::{FillMethod, FillOptions, FilterSpec, RepairConfig, SpikeMode, SpikeOptions};

/// Largest half window of the Hampel identifier (the repair library's bound).
pub const MAX_SPIKE_HALF_WINDOW: usize = repair::spikes::MAX_HALF_WINDOW;
/// Longest gap that may be asked for, in frames (a C3D file holds at most 2³² frames).
pub const MAX_GAP_FRAMES: usize = u32::MAX as usize;

/// The default of `--max-expected-error`. On the 8 923 artificial gaps of the 9 labs no
/// constant was chosen on, each lab's estimates from the model fitted to the other labs
/// (`cargo run --release -p repair --example fill_eval`, its "a limit of" lines), it leaves
/// 0.4 % of the gaps unfilled: 5 of the 7 fills worse than 50 mm, 21 of the 55 worse than
/// 20 mm, and none of the 8 135 within 5 mm. A limit of 15 mm leaves 0.9 % (6 of 7, 34 of
/// 55, 1 of 8 135), 30 mm leaves 0.1 % (3 of 7, 7 of 55, none).
pub const DEFAULT_MAX_EXPECTED_ERROR_MM: f64 = 20.0;

/// Parse `MM` or `off` (`None`).
pub fn max_expected_error(s: &str) -> Result<Option<f64>> {
    if s.trim().eq_ignore_ascii_case("off") {
        return Ok(None);
    }
    let v: f64 = number("--max-expected-error", s)?;
    if !(v > 0.0 && v.is_finite()) {
        return Err(Error::options(format!(
            "--max-expected-error {s:?}: expected a positive number of mm or off"
        )));
    }
    Ok(Some(v))
}

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
            _ => Err(Error::options(format!(
                "--swaps {s:?}: expected fix, report or off"
            ))),
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

/// Everything `repair` can be asked to do, as given by a person.
#[derive(Debug, Clone, PartialEq)]
pub struct RepairOptions {
    /// Fill method name: auto, linear, lagrange2, lagrange5, spline, rigid, pattern, pca, kalman, none.
    pub fill: String,
    /// Longest gap (frames) to fill; longer ones are left and reported.
    pub max_gap: usize,
    /// Leave gaps whose expected fill error is above this many mm, reported as `uncertain`
    /// with the estimate; `None` fills every gap a method can fill.
    pub max_expected_error_mm: Option<f64>,
    /// `hampel[:K[:NSIGMA]]`, or `None` for no spike removal.
    pub spikes: Option<String>,
    /// `gap` (refill spikes with the fill method) or `median` (MATLAB's hampel).
    pub spike_mode: String,
    /// Deviations below this many millimetres are never spikes.
    pub spike_min_mm: f64,
    /// Judge raw coordinates (the classic identifier) rather than residuals from a local
    /// robust prediction.
    pub spike_classic: bool,
    /// `butterworth:ORDER:CUTOFF_HZ` or `cheby2:ORDER:CUTOFF_HZ:ATTEN_DB`, or `None`.
    pub lowpass: Option<String>,
    /// Repair only these markers (labels); every marker still serves as a donor.
    pub markers: Option<Vec<String>>,
    /// Also treat samples at exactly (0, 0, 0) as missing.
    pub zero_invalid: bool,
    /// Label swaps and jumps, the first stage: fixed, reported or not looked for.
    pub swaps: SwapsMode,
}

impl Default for RepairOptions {
    /// The command line's defaults: `auto` fill up to 200 frames, no spikes, no filter.
    fn default() -> Self {
        RepairOptions {
            fill: "auto".into(),
            max_gap: 200,
            max_expected_error_mm: Some(DEFAULT_MAX_EXPECTED_ERROR_MM),
            spikes: None,
            spike_mode: "gap".into(),
            spike_min_mm: 5.0,
            spike_classic: false,
            lowpass: None,
            markers: None,
            zero_invalid: false,
            swaps: DEFAULT_SWAPS,
        }
    }
}

impl RepairOptions {
    /// The checked configuration for a file whose coordinates are in `units`.
    pub fn config(&self, units: &str) -> Result<RepairConfig> {
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
            method: fill_method(&self.fill)?,
            max_gap: Some(self.max_gap),
            max_expected_error: self.max_expected_error_mm.map(|mm| mm / mm_per_unit(units)),
            mm_per_unit: mm_per_unit(units),
            ..FillOptions::default()
        };
        let spikes = self
            .spikes
            .as_deref()
            .map(|s| {
                spike_options(
                    s,
                    &self.spike_mode,
                    self.spike_min_mm / mm_per_unit(units),
                    self.spike_classic,
                )
            })
            .transpose()?;
        let filter = self.lowpass.as_deref().map(filter_spec).transpose()?;
        RepairConfig::new(spikes, fill, filter).map_err(|e| Error::options(e.to_string()))
    }
}

/// A fill method by name (case-insensitive).
pub fn fill_method(name: &str) -> Result<FillMethod> {
    FillMethod::from_name(&name.to_ascii_lowercase()).ok_or_else(|| {
        Error::options(format!(
            "unknown fill method {name:?} (expected auto, linear, lagrange2, lagrange5, spline, rigid, pattern, pca, kalman, gloersen or none)"
        ))
    })
}

/// The name a method has in reports.
pub fn method_name(m: FillMethod) -> String {
    serde_json::to_value(m)
        .ok()
        .and_then(|v| v.as_str().map(str::to_string))
        .unwrap_or_else(|| format!("{m:?}").to_ascii_lowercase())
}

fn number<T: std::str::FromStr>(what: &str, s: &str) -> Result<T> {
    s.trim()
        .parse()
        .map_err(|_| Error::options(format!("{what}: {s:?} is not a valid number")))
}

/// Parse `hampel[:K[:NSIGMA]]` with the spike mode, the minimum deviation (in the file's
/// units) and the classic/detrended choice.
pub fn spike_options(spec: &str, mode: &str, min_dev: f64, classic: bool) -> Result<SpikeOptions> {
    let mut parts = spec.split(':');
    let kind = parts.next().unwrap_or_default();
    if !kind.eq_ignore_ascii_case("hampel") {
        return Err(Error::options(format!(
            "--spikes {spec:?}: the detector must be hampel (hampel[:K[:NSIGMA]])"
        )));
    }
    let mut o = SpikeOptions::default();
    if let Some(k) = parts.next() {
        o.half_window = number("--spikes K", k)?;
        if !(1..=MAX_SPIKE_HALF_WINDOW).contains(&o.half_window) {
            return Err(Error::options(format!(
                "--spikes K = {}: the half window must be from 1 to {MAX_SPIKE_HALF_WINDOW} samples",
                o.half_window
            )));
        }
    }
    if let Some(n) = parts.next() {
        // Its range is the repair library's to check (SpikeOptions::validate).
        o.nsigma = number("--spikes NSIGMA", n)?;
    }
    if parts.next().is_some() {
        return Err(Error::options(format!(
            "--spikes {spec:?}: expected hampel[:K[:NSIGMA]]"
        )));
    }
    o.mode = match mode.to_ascii_lowercase().as_str() {
        "gap" => SpikeMode::Gap,
        "median" => SpikeMode::Median,
        _ => {
            return Err(Error::options(format!(
                "--spike-mode {mode:?}: expected gap or median"
            )))
        }
    };
    o.min_deviation = min_dev;
    o.detrend = !classic;
    Ok(o)
}

/// Parse `butterworth:ORDER:CUTOFF_HZ` or `cheby2:ORDER:CUTOFF_HZ:ATTEN_DB`.
pub fn filter_spec(spec: &str) -> Result<FilterSpec> {
    let p: Vec<&str> = spec.split(':').collect();
    match p.as_slice() {
        [k, o, c] if k.eq_ignore_ascii_case("butterworth") || k.eq_ignore_ascii_case("butter") => {
            Ok(FilterSpec::Butterworth {
                order: number("--lowpass ORDER", o)?,
                cutoff_hz: number("--lowpass CUTOFF_HZ", c)?,
            })
        }
        [k, o, c, a] if k.eq_ignore_ascii_case("cheby2") => Ok(FilterSpec::Cheby2 {
            order: number("--lowpass ORDER", o)?,
            cutoff_hz: number("--lowpass CUTOFF_HZ", c)?,
            atten_db: number("--lowpass ATTEN_DB", a)?,
        }),
        _ => Err(Error::options(format!(
            "--lowpass {spec:?}: expected butterworth:ORDER:CUTOFF_HZ or cheby2:ORDER:CUTOFF_HZ:ATTEN_DB"
        ))),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn option_strings_parse() {
        let s = spike_options("hampel:7:2.5", "median", 4.0, false).unwrap();
        assert_eq!(
            (s.half_window, s.nsigma, s.mode, s.min_deviation),
            (7, 2.5, SpikeMode::Median, 4.0)
        );
        assert_eq!(
            spike_options("hampel", "gap", 0.0, true)
                .unwrap()
                .half_window,
            SpikeOptions::default().half_window
        );
        assert!(spike_options("median:3", "gap", 0.0, false).is_err());
        assert!(spike_options("hampel:x", "gap", 0.0, false)
            .unwrap_err()
            .to_string()
            .contains("not a valid number"));
        assert!(spike_options("hampel:18446744073709551615", "gap", 0.0, false).is_err());
        assert!(spike_options("hampel:1000000000", "gap", 0.0, false).is_err());
        let nan = RepairOptions {
            spikes: Some("hampel:3:nan".into()),
            ..RepairOptions::default()
        };
        assert!(nan.config("mm").is_err());
        assert_eq!(
            filter_spec("butterworth:4:6").unwrap(),
            FilterSpec::Butterworth {
                order: 4,
                cutoff_hz: 6.0
            }
        );
        assert_eq!(
            filter_spec("cheby2:4:10:40").unwrap(),
            FilterSpec::Cheby2 {
                order: 4,
                cutoff_hz: 10.0,
                atten_db: 40.0
            }
        );
        assert!(filter_spec("bessel:4:6").is_err());
        assert_eq!(method_name(FillMethod::Lagrange5), "lagrange5");
        assert_eq!(max_expected_error("off").unwrap(), None);
        assert_eq!(max_expected_error(" 12.5").unwrap(), Some(12.5));
        assert!(max_expected_error("0").is_err());
        assert!(max_expected_error("much").is_err());
        assert_eq!(" Fix".parse::<SwapsMode>().unwrap(), SwapsMode::Fix);
        assert_eq!("off".parse::<SwapsMode>().unwrap().to_string(), "off");
        assert!("undo".parse::<SwapsMode>().is_err());
    }

    #[test]
    fn defaults_are_the_command_lines() {
        let c = RepairOptions::default().config("mm").unwrap();
        assert_eq!(c.fill().method, FillMethod::Auto);
        assert!(c.spikes().is_none() && c.filter().is_none());
        let bad = RepairOptions {
            max_gap: 0,
            ..RepairOptions::default()
        };
        assert!(bad.config("mm").is_err());
    }
}
