//! The repair options shared by `repair` and `batch`, as command-line arguments: they become
//! the library's [`c3dfix::RepairOptions`], which checks them.

use crate::ranges;
use c3dfix::{FillMethod, FilterSpec, RepairOptions, SpikeMode, SpikeSpec};

/// Repair options common to `repair` and `batch`. Names and specs are read by the library's
/// `FromStr` (a misspelt one is a usage error naming the flag), and every default is the
/// library's [`RepairOptions::default`] (a test checks that no flag given is the default).
#[derive(clap::Args, Clone)]
pub struct RepairArgs {
    /// Fill method (gloersen is Gløersen & Federolf's published PCA).
    #[arg(long, default_value_t = RepairOptions::default().fill, help = fill_help())]
    pub fill: FillMethod,
    /// Longest gap (frames, 1 or more) to fill; longer ones are left and reported.
    #[arg(long, default_value_t = RepairOptions::default().max_gap, value_parser = ranges::max_gap)]
    pub max_gap: usize,
    /// Leave gaps whose expected fill error is above this many mm (reported as `uncertain`
    /// with the estimate); `off` fills every gap a method can fill. The default, 20 mm, on
    /// artificial gaps in the labs nothing was chosen on (c3d-more, c3d-labs), each judged
    /// by the model fitted to the others, leaves 2.7 % of the gaps, among them 83 % of the
    /// fills that would have been off by more than 50 mm and 0.05 % of those within 5 mm.
    /// There the truth is within 2x of the estimate for 77.1 % of gaps and above twice it
    /// for 4.6 % (walking 81.0 % / 3.2 %; running, jumps and lifting spread wider). Gaps at
    /// a trial's start or end (only donors can fill them) are filled 2-5x worse and less
    /// surely (docs/fill-evaluation.md, "Gaps at a trial's start or end").
    #[arg(long, default_value_t = ExpectedError(RepairOptions::default().max_expected_error_mm), value_parser = expected_error_arg)]
    pub max_expected_error: ExpectedError,
    /// Remove spikes first: `hampel[:K[:NSIGMA]]` (window of K samples each side, 1 to 1000,
    /// default 5; NSIGMA scaled MADs, a finite number above 0, default 3). Off by default.
    #[arg(long, value_name = "SPEC")]
    pub spikes: Option<SpikeSpec>,
    /// What to do with a spike: `gap` (refill it with the fill method) or `median` (replace
    /// the outlying coordinates with the window median, as MATLAB's hampel does).
    #[arg(long, default_value_t = RepairOptions::default().spike_mode)]
    pub spike_mode: SpikeMode,
    /// Deviations from the window median below this many millimetres are never spikes
    /// (keeps measurement noise on still coordinates from being flagged); 0 or more.
    #[arg(long, default_value_t = RepairOptions::default().spike_min_mm, value_parser = ranges::non_negative)]
    pub spike_min_mm: f64,
    /// Judge raw coordinates (the classic Hampel identifier, as MATLAB's hampel) instead of
    /// residuals from a local robust prediction, which also finds spikes along fast motion.
    #[arg(long)]
    pub spike_classic: bool,
    /// Low-pass filter, zero-phase: `butterworth:ORDER:CUTOFF_HZ` or
    /// `cheby2:ORDER:CUTOFF_HZ:ATTEN_DB` (ORDER 1 to 10; CUTOFF_HZ above 0 and below half the
    /// frame rate; ATTEN_DB above 0, at most 200). Off by default.
    #[arg(long, value_name = "SPEC")]
    pub lowpass: Option<FilterSpec>,
    /// Repair only these markers (comma-separated labels); all markers still serve as donors.
    #[arg(long, value_delimiter = ',')]
    pub markers: Option<Vec<String>>,
    /// Also treat samples whose coordinates are all exactly 0 as missing.
    #[arg(long)]
    pub zero_invalid: bool,
    /// Label swaps and jumps, the first stage (docs/swaps.md): `fix` exchanges settled swaps
    /// back (coordinates, residuals and camera masks as recorded) and makes settled jumps
    /// gaps for the fill; `report` (the default: on untouched trials `fix` would change 2.8
    /// finds per 10 000 frames, not all shown to be label errors) lists every find and
    /// changes nothing; `off` skips it.
    #[arg(long, default_value_t = RepairOptions::default().swaps, value_parser = crate::ranges::choice::<c3dfix::SwapsMode>)]
    pub swaps: c3dfix::SwapsMode,
    /// Labels (a glob: `*` any text, `?` one character, case-insensitive) that also mark a
    /// point as unlabelled, beside the common placeholders (`*51`, `Unlabeled 3`,
    /// `uname*2`, an empty label). Unlabelled points are not repaired nor donors nor
    /// searched for swaps; they are counted apart and left as recorded.
    #[arg(long, value_name = "PATTERN")]
    pub unlabelled: Option<repair::Glob>,
    /// Unlabelled samples that are a labelled marker's, the stage after the swaps and before
    /// the fills (docs/reclaim.md): `on` moves the settled ones into their markers (recorded
    /// values, residuals and camera masks; the unlabelled point is marked missing there);
    /// `report` (the default) lists them and changes nothing; `off` skips it.
    #[arg(long, default_value_t = RepairOptions::default().reclaim, value_parser = crate::ranges::choice::<c3dfix::ReclaimMode>)]
    pub reclaim: c3dfix::ReclaimMode,
}

/// `--fill`'s help, listing the names from the library's one table.
fn fill_help() -> String {
    format!(
        "Fill method: {} (gloersen is Gløersen & Federolf's published PCA)",
        FillMethod::names_listed()
    )
}

impl RepairArgs {
    /// The library's options (checked once by the library, before any file is touched).
    pub fn options(&self) -> RepairOptions {
        RepairOptions {
            fill: self.fill,
            max_gap: self.max_gap,
            max_expected_error_mm: self.max_expected_error.0,
            spikes: self.spikes,
            spike_mode: self.spike_mode,
            spike_min_mm: self.spike_min_mm,
            spike_classic: self.spike_classic,
            lowpass: self.lowpass,
            markers: self.markers.clone(),
            zero_invalid: self.zero_invalid,
            swaps: self.swaps,
            unlabelled: self.unlabelled.clone(),
            reclaim: self.reclaim,
        }
    }
}

/// `--max-expected-error`: millimetres, or `None` for `off`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ExpectedError(pub Option<f64>);

impl std::fmt::Display for ExpectedError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self.0 {
            Some(mm) => write!(f, "{mm}"),
            None => f.write_str("off"),
        }
    }
}

/// `--max-expected-error MM|off`, checked while the command line is parsed.
fn expected_error_arg(s: &str) -> std::result::Result<ExpectedError, String> {
    c3dfix::max_expected_error(s)
        .map(ExpectedError)
        .map_err(|e| e.to_string())
}

#[cfg(test)]
mod tests {
    use super::*;
    use clap::Parser;

    #[derive(clap::Parser)]
    struct Cli {
        #[command(flatten)]
        repair: RepairArgs,
    }

    #[test]
    fn no_flag_given_is_the_librarys_default() {
        let cli = Cli::try_parse_from(["c3dfix"]).unwrap();
        assert_eq!(cli.repair.options(), RepairOptions::default());
    }

    #[test]
    fn flags_are_read_by_the_librarys_names() {
        let cli = Cli::try_parse_from([
            "c3dfix",
            "--fill",
            "Gloersen",
            "--spikes",
            "hampel:7",
            "--spike-mode",
            "median",
            "--lowpass",
            "butter:4:6",
            "--max-expected-error",
            "off",
        ])
        .unwrap();
        let o = cli.repair.options();
        assert_eq!(o.fill, FillMethod::Gloersen);
        assert_eq!(o.spikes.map(|s| s.to_string()).as_deref(), Some("hampel:7"));
        assert_eq!(o.spike_mode, SpikeMode::Median);
        assert_eq!(
            o.lowpass.map(|f| f.to_string()).as_deref(),
            Some("butterworth:4:6")
        );
        assert_eq!(o.max_expected_error_mm, None);
        let e = Cli::try_parse_from(["c3dfix", "--fill", "magic"])
            .err()
            .map(|e| e.to_string())
            .unwrap_or_default();
        assert!(e.contains("--fill") && e.contains("gloersen"), "{e}");
    }
}
