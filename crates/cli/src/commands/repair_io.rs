//! Between C3D files and the repair library: which points are markers, trajectories as a
//! [`repair::Trial`], repaired samples written back with the C3D manual's flags, and the
//! parsing of the repair options shared by `repair`, `batch` and `evaluate`.

use anyhow::{bail, Context, Result};
use repair::{change, FillMethod, FillOptions, FilterSpec, RepairConfig, SpikeMode, SpikeOptions};
use std::path::{Path, PathBuf};

/// Repair options common to `repair` and `batch`.
#[derive(clap::Args, Clone)]
pub struct RepairArgs {
    /// Fill method: auto, linear, lagrange2, lagrange5, spline, rigid, pattern, pca, none.
    #[arg(long, default_value = "auto")]
    pub fill: String,
    /// Longest gap (frames) to fill; longer ones are left and reported.
    #[arg(long, default_value_t = 200)]
    pub max_gap: usize,
    /// Leave gaps whose expected fill error is above this many mm (reported as
    /// `uncertain` with the estimate); `off` fills every gap a method can fill. The default
    /// 20 mm, on the artificial gaps of the real trials, left 92 % of the fills worse than
    /// 50 mm and 70 % of those worse than 20 mm, and 0.3 % of the gaps that would have been
    /// filled within 5 mm (README, "Fill accuracy").
    #[arg(long, default_value = "20")]
    pub max_expected_error: String,
    /// Remove spikes first: `hampel[:K[:NSIGMA]]` (window of K samples each side, default 5;
    /// NSIGMA scaled MADs, default 3). Off by default.
    #[arg(long)]
    pub spikes: Option<String>,
    /// What to do with a spike: `gap` (refill it with the fill method) or `median` (replace
    /// the outlying coordinates with the window median, as MATLAB's hampel does).
    #[arg(long, default_value = "gap")]
    pub spike_mode: String,
    /// Deviations from the window median below this many millimetres are never spikes
    /// (keeps measurement noise on still coordinates from being flagged).
    #[arg(long, default_value_t = 5.0)]
    pub spike_min_mm: f64,
    /// Judge raw coordinates (the classic Hampel identifier, as MATLAB's hampel) instead of
    /// residuals from a local robust prediction, which also finds spikes along fast motion.
    #[arg(long)]
    pub spike_classic: bool,
    /// Low-pass filter, zero-phase: `butterworth:ORDER:CUTOFF_HZ` or
    /// `cheby2:ORDER:CUTOFF_HZ:ATTEN_DB`. Off by default.
    #[arg(long)]
    pub lowpass: Option<String>,
    /// Repair only these markers (comma-separated labels); all markers still serve as donors.
    #[arg(long, value_delimiter = ',')]
    pub markers: Option<Vec<String>>,
    /// Also treat samples whose coordinates are all exactly 0 as missing.
    #[arg(long)]
    pub zero_invalid: bool,
}

/// Millimetres per POINT:UNITS unit (so thresholds given in mm apply to any file).
pub fn mm_per_unit(units: &str) -> f64 {
    match units.trim().to_ascii_lowercase().as_str() {
        "m" | "mete" | "meter" | "meters" | "metre" | "metres" => 1000.0,
        "cm" => 10.0,
        "dm" => 100.0,
        "in" | "inch" | "inches" => 25.4,
        _ => 1.0,
    }
}

/// Parse a fill method name.
pub fn fill_method(name: &str) -> Result<FillMethod> {
    FillMethod::from_name(&name.to_ascii_lowercase()).with_context(|| {
        format!(
            "unknown fill method {name:?} (expected auto, linear, lagrange2, lagrange5, spline, rigid, pattern, pca or none)"
        )
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
        .map_err(|_| anyhow::anyhow!("{what}: {s:?} is not a valid number"))
}

/// Parse `--max-expected-error MM|off` (millimetres; `None` for off).
pub fn max_expected_error(s: &str) -> Result<Option<f64>> {
    if s.trim().eq_ignore_ascii_case("off") {
        return Ok(None);
    }
    let v: f64 = number("--max-expected-error", s)?;
    if !(v > 0.0 && v.is_finite()) {
        bail!("--max-expected-error {s:?}: expected a positive number of mm or off");
    }
    Ok(Some(v))
}

/// Parse `--spikes hampel[:K[:NSIGMA]]`.
pub fn spike_options(spec: &str, mode: &str, min_dev: f64, classic: bool) -> Result<SpikeOptions> {
    let mut parts = spec.split(':');
    let kind = parts.next().unwrap_or_default();
    if !kind.eq_ignore_ascii_case("hampel") {
        bail!("--spikes {spec:?}: the detector must be hampel (hampel[:K[:NSIGMA]])");
    }
    let mut o = SpikeOptions::default();
    if let Some(k) = parts.next() {
        o.half_window = number("--spikes K", k)?;
    }
    if let Some(n) = parts.next() {
        o.nsigma = number("--spikes NSIGMA", n)?;
    }
    if parts.next().is_some() {
        bail!("--spikes {spec:?}: expected hampel[:K[:NSIGMA]]");
    }
    o.mode = match mode.to_ascii_lowercase().as_str() {
        "gap" => SpikeMode::Gap,
        "median" => SpikeMode::Median,
        _ => bail!("--spike-mode {mode:?}: expected gap or median"),
    };
    o.min_deviation = min_dev;
    o.detrend = !classic;
    Ok(o)
}

/// Parse `--lowpass butterworth:ORDER:CUTOFF` or `cheby2:ORDER:CUTOFF:ATTEN`.
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
        _ => bail!(
            "--lowpass {spec:?}: expected butterworth:ORDER:CUTOFF_HZ or cheby2:ORDER:CUTOFF_HZ:ATTEN_DB"
        ),
    }
}

impl RepairArgs {
    /// The validated configuration for a file whose coordinates are in `units`.
    pub fn config(&self, units: &str) -> Result<RepairConfig> {
        let fill = FillOptions {
            method: fill_method(&self.fill)?,
            max_gap: Some(self.max_gap),
            max_expected_error: max_expected_error(&self.max_expected_error)?
                .map(|mm| mm / mm_per_unit(units)),
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
        RepairConfig::new(spikes, fill, filter).map_err(|e| anyhow::anyhow!("{e}"))
    }
}

/// Labels of points that are model outputs, not markers (Plug-in Gait stores angles, forces,
/// moments and powers as points and lists them in these POINT parameters).
pub fn model_outputs(c: &c3d::C3d) -> Vec<String> {
    [
        "ANGLES",
        "FORCES",
        "MOMENTS",
        "POWERS",
        "SCALARS",
        "REACTIONS",
    ]
    .iter()
    .flat_map(|p| c.parameters.get_strings("POINT", p).unwrap_or_default())
    .filter(|s| !s.is_empty())
    .collect()
}

/// The markers of a file: indices of points that are not model outputs.
pub fn marker_indices(c: &c3d::C3d) -> Vec<usize> {
    let outputs = model_outputs(c);
    c.point_labels()
        .iter()
        .enumerate()
        .filter(|(_, l)| !outputs.contains(l))
        .map(|(i, _)| i)
        .collect()
}

/// The given points as a trial. Validity is the C3D crate's one rule ([`c3d::is_missing`]);
/// `zero_invalid` also treats samples at exactly (0, 0, 0) as missing, for writers that store
/// missing points that way with a valid fourth word.
pub fn trial(c: &c3d::C3d, points: &[usize], zero_invalid: bool) -> Result<repair::Trial> {
    let p = c.points();
    let mut xyz = Vec::with_capacity(points.len());
    let mut valid = Vec::with_capacity(points.len());
    for &i in points {
        let t: Vec<[f64; 3]> = p
            .trajectory(i)
            .into_iter()
            .map(|v| [v[0] as f64, v[1] as f64, v[2] as f64])
            .collect();
        let v: Vec<bool> = (0..p.frames())
            .map(|f| p.is_valid(f, i) && !(zero_invalid && t[f] == [0.0; 3]))
            .collect();
        valid.push(v);
        xyz.push(t);
    }
    repair::Trial::new(c.point_rate() as f64, xyz, valid).map_err(|e| anyhow::anyhow!("{e}"))
}

/// Resolve `--markers` labels to point indices, listing the available labels on a miss.
pub fn select(c: &c3d::C3d, names: &Option<Vec<String>>) -> Result<Option<Vec<usize>>> {
    let Some(names) = names else { return Ok(None) };
    let mut out = Vec::new();
    for n in names.iter().map(|n| n.trim()).filter(|n| !n.is_empty()) {
        match c.point_index(n) {
            Some(i) => out.push(i),
            None => bail!(
                "no marker {n:?}; the file has: {}",
                c.point_labels().join(", ")
            ),
        }
    }
    Ok(Some(out))
}

/// Write the repair of `points` (trial rows) back into the file: filled, despiked and filtered
/// samples get the new coordinates with residual 0 and camera mask 0 (the C3D manual's mark
/// for processed points); samples invalidated and not refilled become gaps; the others keep
/// their bits. Only markers in `only` (point indices) are written when given.
pub fn write_back(
    c: &mut c3d::C3d,
    trial: &repair::Trial,
    points: &[usize],
    changes: &[Vec<u8>],
    only: Option<&[usize]>,
) -> WriteBack {
    let mut w = WriteBack::default();
    let frames = c.points().frames();
    // Integer files hold ±32767 × POINT:SCALE at most; a filter's overshoot or a fill near
    // that edge is clamped to it (and counted) rather than making the file unwritable.
    let limit = match c.format() {
        c3d::NumberFormat::Integer => Some(c.layout().point_scale as f64 * 32767.0),
        c3d::NumberFormat::Float => None,
    };
    let pts = c.points_mut();
    for (row, &i) in points.iter().enumerate() {
        if only.is_some_and(|o| !o.contains(&i)) {
            continue;
        }
        for (f, &ch) in changes[row].iter().enumerate().take(frames) {
            if ch == 0 {
                continue;
            }
            let k = pts.index(f, i);
            if ch & (change::FILLED | change::DESPIKED | change::FILTERED) != 0
                && trial.valid[row][f]
            {
                let mut v = trial.xyz[row][f];
                if let Some(l) = limit {
                    if v.iter().any(|x| x.abs() > l) {
                        w.clamped += 1;
                        v = v.map(|x| x.clamp(-l, l));
                    }
                }
                pts.xyz[k] = [v[0] as f32, v[1] as f32, v[2] as f32];
                pts.residual[k] = 0.0;
                pts.camera_mask[k] = 0;
                w.changed += 1;
            } else if ch & change::INVALIDATED != 0 {
                pts.xyz[k] = [0.0; 3];
                pts.residual[k] = -1.0;
                pts.camera_mask[k] = 0;
                w.changed += 1;
            }
        }
    }
    w
}

/// What [`write_back`] did.
#[derive(Debug, Default, Clone, Copy)]
pub struct WriteBack {
    /// Samples given new values or flags.
    pub changed: usize,
    /// Of those, samples clamped to the integer range of the file's POINT:SCALE.
    pub clamped: usize,
}

/// Where to write: `-o OUT`, or the input itself with `--in-place`.
pub fn output_path(input: &Path, output: &Option<PathBuf>, in_place: bool) -> Result<PathBuf> {
    match (output, in_place) {
        (Some(_), true) => bail!("give either -o OUT or --in-place, not both"),
        (Some(o), false) => Ok(o.clone()),
        (None, true) => Ok(input.to_path_buf()),
        (None, false) => bail!("give -o OUT or --in-place"),
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
        assert_eq!(mm_per_unit("m"), 1000.0);
        assert_eq!(max_expected_error("off").unwrap(), None);
        assert_eq!(max_expected_error(" 12.5").unwrap(), Some(12.5));
        assert!(max_expected_error("0").is_err());
        assert!(max_expected_error("much").is_err());
    }
}
