//! Force platforms of a trial: FORCE_PLATFORM (read by the `c3d` crate) joined with the
//! analog channels in physical units and the plate maths of the `kinetics` crate.
//!
//! Analog values are `(raw − OFFSET) × SCALE × GEN_SCALE` per channel
//! ([`c3d::Calibration`]; OFFSET read as unsigned when ANALOG:FORMAT is "UNSIGNED", as the
//! manual says). Units: forces in N; positions in POINT:UNITS; moments in N × POINT:UNITS
//! (see `units` for why ANALOG:UNITS labels are not applied).
//!
//! A plate that cannot be computed (an unsupported type, a CHANNEL beyond the analog data,
//! CORNERS of the wrong size or enclosing no area, a type 4 without CAL_MATRIX) is left out
//! with a warning naming the plate and the parameter; the others are computed.

mod channels;
mod units;

use crate::error::{Error, Result};
use c3d::C3d;
use kinetics::PlateSpec;
use serde::Serialize;

/// What to compute, as a person asks for it.
#[derive(Debug, Clone, PartialEq)]
pub struct ForceOptions {
    /// |Fz| below which the COP and free moment are undefined (N).
    pub threshold: f64,
    /// Subtract each channel's mean over FORCE_PLATFORM:ZERO's frames first.
    pub zero_baseline: bool,
    /// A zero-phase low-pass filter of the channels, as for markers:
    /// `butterworth:ORDER:CUTOFF_HZ` or `cheby2:ORDER:CUTOFF_HZ:ATTEN_DB`.
    pub lowpass: Option<String>,
}

/// The COP threshold of ezc3d, BTK and Visual3D's examples: 10 N.
pub const DEFAULT_THRESHOLD_N: f64 = 10.0;

impl Default for ForceOptions {
    fn default() -> Self {
        ForceOptions {
            threshold: DEFAULT_THRESHOLD_N,
            zero_baseline: false,
            lowpass: None,
        }
    }
}

/// The units of a plate's outputs.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Units {
    pub force: String,
    pub moment: String,
    pub position: String,
}

/// A stretch where the plate carried at least the threshold: gait's foot-strike to
/// foot-off.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Contact {
    /// First and last analog sample (0-based), inclusive.
    pub first_sample: usize,
    pub last_sample: usize,
    /// The point frames they fall in, numbered as the file numbers them (from its first
    /// frame).
    pub first_frame: usize,
    pub last_frame: usize,
    /// Largest |Fz| in the stretch (N).
    pub peak: f64,
}

/// One plate's outputs at the analog rate, all in the lab frame (see [`kinetics::compute`]).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Platform {
    /// 1-based, as FORCE_PLATFORM numbers plates.
    pub index: usize,
    #[serde(rename = "type")]
    pub kind: i32,
    /// Samples per second (ANALOG:RATE).
    pub rate: f64,
    /// 1-based analog channels.
    pub channels: Vec<usize>,
    pub corners: [[f64; 3]; 4],
    /// The centre of the working surface (mean of the corners).
    pub centre: [f64; 3],
    /// FORCE_PLATFORM:ORIGIN as used (after the sign rule).
    pub origin: [f64; 3],
    /// ORIGIN's z had the unexpected sign and was turned round (see the warnings).
    pub origin_corrected: bool,
    /// FORCE_PLATFORM:ZERO's frames, when their mean was subtracted.
    pub zero_applied: Option<[usize; 2]>,
    /// The low-pass filter applied to the channels, if any.
    pub filtered: Option<String>,
    pub force: Vec<[f64; 3]>,
    /// About the centre of the working surface.
    pub moment: Vec<[f64; 3]>,
    /// NaN (null in JSON) where |Fz| is below the threshold.
    pub cop: Vec<[f64; 3]>,
    pub free_moment: Vec<[f64; 3]>,
    /// The force along the plate's own z axis, which the threshold judges.
    #[serde(skip)]
    pub normal: Vec<f64>,
    /// Largest |Fz| over the trial (N).
    pub peak_force: f64,
    pub contacts: Vec<Contact>,
    pub units: Units,
}

/// A plate left out or a parameter not used, naming the plate and the parameter.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PlateWarning {
    /// 1-based plate; 0 for the whole group.
    pub plate: usize,
    pub parameter: String,
    pub message: String,
}

impl std::fmt::Display for PlateWarning {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        if self.plate == 0 {
            write!(f, "{}: {}", self.parameter, self.message)
        } else {
            write!(
                f,
                "plate {}: {} {}",
                self.plate, self.parameter, self.message
            )
        }
    }
}

/// The plates of a trial.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ForcePlatforms {
    pub platforms: Vec<Platform>,
    pub warnings: Vec<PlateWarning>,
    /// Analog samples per point frame.
    #[serde(skip)]
    pub samples_per_frame: usize,
    /// The file's first frame number.
    #[serde(skip)]
    pub first_frame: usize,
    /// The threshold used (N).
    #[serde(skip)]
    pub threshold: f64,
}

impl ForcePlatforms {
    /// Analog samples of the trial's plates (every plate has the trial's analog samples; 0
    /// without plates).
    pub fn samples(&self) -> usize {
        self.platforms
            .iter()
            .map(|p| p.force.len())
            .max()
            .unwrap_or(0)
    }
}

/// A parameter value as stored (single precision), for messages: `37.84`, not
/// `37.84000015258789`; no negative zero.
fn short(v: f64) -> String {
    format!("{}", v as f32 + 0.0)
}

fn triple(v: [f64; 3]) -> String {
    format!("[{}, {}, {}]", short(v[0]), short(v[1]), short(v[2]))
}

/// Compute every plate of `c`. Fails only for options that make no sense (a malformed or
/// impossible filter); each plate's own trouble is a warning.
pub fn force_platforms(c: &C3d, opts: &ForceOptions) -> Result<ForcePlatforms> {
    if !(opts.threshold >= 0.0 && opts.threshold.is_finite()) {
        return Err(Error::options(format!(
            "--threshold {}: expected 0 N or more",
            opts.threshold
        )));
    }
    let rate = c.analog_rate() as f64;
    let filter = match &opts.lowpass {
        Some(spec) => {
            let s = crate::filter_spec(spec)?;
            let iir = s
                .validate()
                .and_then(|_| s.design(rate))
                .map_err(|e| Error::options(format!("--lowpass {spec}: {e}")))?;
            Some((spec.clone(), iir))
        }
        None => None,
    };
    let fp = c.platform_params();
    let mut out = ForcePlatforms {
        platforms: Vec::new(),
        warnings: fp
            .problems
            .iter()
            .map(|p| PlateWarning {
                plate: p.plate,
                parameter: p.parameter.clone(),
                message: p.message.clone(),
            })
            .collect(),
        samples_per_frame: c.analog().samples_per_frame().max(1),
        first_frame: c.first_frame(),
        threshold: opts.threshold,
    };
    if fp.plates.is_empty() {
        return Ok(out);
    }
    let point_units = {
        let u = c.point_units();
        if u.trim().is_empty() {
            "mm".to_string()
        } else {
            u.trim().to_string()
        }
    };
    let point_mm = c3d::mm_per_unit(&point_units);
    let analog_units = c.analog_units();
    let cal = c.analog_calibration();
    // How many channels ANALOG:SCALE and OFFSET really describe (the calibration pads the
    // rest with 1 and 0, which is no calibration for a force channel).
    let described = |name: &str| c.param("ANALOG", name).map_or(0, |p| p.value.len());
    let (scaled, offset_known) = (described("SCALE"), described("OFFSET"));
    let analog = c.analog();
    let samples = analog.samples();
    let spf = out.samples_per_frame;
    let warn = |out: &mut ForcePlatforms, plate: usize, parameter: &str, message: String| {
        out.warnings.push(PlateWarning {
            plate,
            parameter: format!("FORCE_PLATFORM:{parameter}"),
            message,
        })
    };

    // The baseline's samples, when asked for and possible.
    let zero = match (opts.zero_baseline, fp.zero) {
        (false, _) => None,
        (true, None) => {
            warn(
                &mut out,
                0,
                "ZERO",
                "names no frames ([0, 0] or absent): no baseline subtracted".into(),
            );
            None
        }
        (true, Some([a, b])) => {
            let (s0, s1) = ((a - 1) * spf, (b * spf).min(samples));
            if s0 >= s1 {
                warn(
                    &mut out,
                    0,
                    "ZERO",
                    format!("frames {a}..{b} lie beyond the trial's analog data: no baseline subtracted"),
                );
                None
            } else {
                Some(([a, b], s0..s1))
            }
        }
    };

    for p in &fp.plates {
        let kind = match kinetics::PlateKind::from_type(p.kind) {
            Ok(k) => k,
            Err(e) => {
                warn(&mut out, p.index, "TYPE", format!("{}: plate left out", e));
                continue;
            }
        };
        let (Some(corners), Some(origin)) = (p.corners, p.origin) else {
            // Already reported by the parameter reading.
            continue;
        };
        if p.channels.is_empty() {
            continue;
        }
        if p.channels.len() < kind.channels() {
            warn(
                &mut out,
                p.index,
                "CHANNEL",
                format!(
                    "lists {} channels; type {} needs {}: plate left out",
                    p.channels.len(),
                    p.kind,
                    kind.channels()
                ),
            );
            continue;
        }
        let used = &p.channels[..kind.channels()];
        if let Some(&k) = used.iter().find(|&&k| k > scaled || k > offset_known) {
            let (name, n) = if k > scaled {
                ("SCALE", scaled)
            } else {
                ("OFFSET", offset_known)
            };
            out.warnings.push(PlateWarning {
                plate: p.index,
                parameter: format!("ANALOG:{name}"),
                message: format!(
                    "has {n} entries, none for the plate's channel {k}: plate left out"
                ),
            });
            continue;
        }
        let mut ch = channels::physical(analog, &cal, used);
        let mut zero_applied = None;
        if let Some((frames, range)) = &zero {
            channels::subtract_baseline(&mut ch, range);
            zero_applied = Some(*frames);
        }
        let bad = channels::non_finite(&ch);
        if bad > 0 {
            warn(
                &mut out,
                p.index,
                "CHANNEL",
                format!("analog data hold {bad} samples that are not finite: those samples give no force"),
            );
        }
        for i in channels::constant(&ch) {
            warn(
                &mut out,
                p.index,
                "CHANNEL",
                format!(
                    "channel {} holds one value throughout: it recorded nothing, so what depends on it (moments, COP) is not measured",
                    used[i]
                ),
            );
        }
        let mut filtered = None;
        if let Some((spec, iir)) = &filter {
            if bad > 0 {
                warn(
                    &mut out,
                    p.index,
                    "CHANNEL",
                    format!("not filtered ({spec}): its analog data are not all finite"),
                );
            } else if channels::filter(&mut ch, iir) {
                filtered = Some(spec.clone());
            } else {
                warn(
                    &mut out,
                    p.index,
                    "CHANNEL",
                    format!("not filtered ({spec}): {samples} samples are too few for its padding"),
                );
            }
        }
        for (k, label) in units::mislabelled(kind, used, &analog_units, point_mm) {
            warn(
                &mut out,
                p.index,
                "CHANNEL",
                format!(
                    "channel {k} is labelled {label:?} (ANALOG:UNITS), but the manual has every length in POINT:UNITS: read in {point_units}"
                ),
            );
        }
        let spec = PlateSpec {
            kind: p.kind,
            corners,
            origin,
            cal_matrix: p.cal_matrix.as_deref(),
            cop_poly: p.cop_poly,
            mm_per_unit: point_mm,
        };
        let refs: Vec<&[f64]> = ch.iter().map(|v| v.as_slice()).collect();
        let r = match kinetics::compute(&spec, &refs, opts.threshold) {
            Ok(r) => r,
            Err(e) => {
                let parameter = match e {
                    kinetics::Error::ZeroArea
                    | kinetics::Error::NotAPlate
                    | kinetics::Error::CornersNotFinite => "CORNERS",
                    kinetics::Error::NoCalMatrix | kinetics::Error::CalMatrixSize(_) => {
                        "CAL_MATRIX"
                    }
                    kinetics::Error::OriginNotFinite => "ORIGIN",
                    kinetics::Error::UnsupportedType(_) => "TYPE",
                    _ => "CHANNEL",
                };
                let msg = e.to_string();
                let msg = msg
                    .strip_prefix(&format!("FORCE_PLATFORM:{parameter} "))
                    .unwrap_or(&msg)
                    .to_string();
                warn(
                    &mut out,
                    p.index,
                    parameter,
                    format!("{msg}: plate left out"),
                );
                continue;
            }
        };
        if r.origin.corrected {
            warn(
                &mut out,
                p.index,
                "ORIGIN",
                format!(
                    "z is {} but must be negative (the plate's origin lies below its surface, z down): read as {}",
                    short(origin[2]),
                    triple(r.origin.used)
                ),
            );
        }
        if kind == kinetics::PlateKind::Type3
            && (r.origin.used[0] == 0.0 || r.origin.used[1] == 0.0)
        {
            warn(
                &mut out,
                p.index,
                "ORIGIN",
                format!(
                    "gives the sensors' distances a = {}, b = {}: with a zero the moments about that axis vanish and the COP cannot leave the plate's centre line",
                    short(r.origin.used[0]),
                    short(r.origin.used[1])
                ),
            );
        }
        let peak_force = r
            .normal
            .iter()
            .filter(|v| v.is_finite())
            .fold(0.0f64, |m, v| m.max(v.abs()));
        let contacts = kinetics::contacts(&r.normal, opts.threshold, rate)
            .into_iter()
            .map(|[a, b]| Contact {
                first_sample: a,
                last_sample: b,
                first_frame: out.first_frame + a / spf,
                last_frame: out.first_frame + b / spf,
                peak: r.normal[a..=b].iter().fold(0.0f64, |m, v| m.max(v.abs())),
            })
            .collect();
        out.platforms.push(Platform {
            index: p.index,
            kind: p.kind,
            rate,
            channels: used.to_vec(),
            corners,
            centre: r.frame.centre,
            origin: r.origin.used,
            origin_corrected: r.origin.corrected,
            zero_applied,
            filtered,
            force: r.force,
            moment: r.moment,
            cop: r.cop,
            free_moment: r.free_moment,
            normal: r.normal,
            peak_force,
            contacts,
            units: Units {
                force: "N".into(),
                moment: format!("N{point_units}"),
                position: point_units.clone(),
            },
        });
    }
    Ok(out)
}
