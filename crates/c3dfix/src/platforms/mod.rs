//! Force platforms of a trial: FORCE_PLATFORM (read by the `c3d` crate) joined with the
//! analog channels in physical units and the plate maths of the `kinetics` crate.
//!
//! Analog values are `(raw − OFFSET) × SCALE × GEN_SCALE` per channel
//! ([`c3d::Calibration`]; OFFSET read as unsigned when ANALOG:FORMAT is "UNSIGNED", as the
//! manual says). Units: forces in N; positions in POINT:UNITS; moments in N × POINT:UNITS
//! (see `units` for why ANALOG:UNITS labels are not applied).
//!
//! A plate's load is its push (−Fz of its own frame, [`kinetics::plate::PlateOutput::push`]),
//! never |Fz|: the threshold, the COP's validity, the free moment and the contacts judge it.
//! Its unloaded level is removed by default ([`Baseline`]): FORCE_PLATFORM:ZERO's frames
//! where they name an unloaded stretch, else the plate's quietest low stretch
//! ([`kinetics::baseline`]).
//!
//! A plate that cannot be computed (an unsupported type, a CHANNEL beyond the analog data,
//! CORNERS of the wrong size or enclosing no area, a type 4 without CAL_MATRIX) is left out
//! with a warning naming the plate and the parameter; the others are computed.

mod bounds;
mod channels;
mod plate;
mod table;
mod units;

pub(crate) use bounds::off_plate;
pub use bounds::EDGE_MM;
pub use table::ForcesReport;

use crate::error::{Error, Result, Setting};
use c3d::C3d;
use kinetics::PlateSpec;
use serde::Serialize;
use std::ops::Range;

/// What to compute, as a person asks for it.
#[derive(Debug, Clone, PartialEq)]
pub struct ForceOptions {
    /// The push (N) below which the COP and free moment are undefined and which bounds the
    /// contacts.
    pub threshold: f64,
    /// Remove each plate's unloaded level first: each channel's mean over
    /// FORCE_PLATFORM:ZERO's frames where they hold the unloaded plate, else over the plate's
    /// quietest low stretch ([`kinetics::baseline`]). On by default: an offset left in is a
    /// load in every exported row, or contacts made of noise.
    pub zero_baseline: bool,
    /// A zero-phase low-pass filter of the channels, as for markers:
    /// `butterworth:ORDER:CUTOFF_HZ` or `cheby2:ORDER:CUTOFF_HZ:ATTEN_DB`.
    pub lowpass: Option<repair::FilterSpec>,
}

/// The COP threshold of ezc3d, BTK and Visual3D's examples: 10 N.
pub const DEFAULT_THRESHOLD_N: f64 = 10.0;

impl Default for ForceOptions {
    fn default() -> Self {
        ForceOptions {
            threshold: DEFAULT_THRESHOLD_N,
            zero_baseline: true,
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

/// A stretch where a foot pushed the plate with at least the threshold: gait's foot-strike
/// to foot-off.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Contact {
    /// First and last analog sample (0-based), inclusive.
    pub first_sample: usize,
    pub last_sample: usize,
    /// The point frames they fall in, numbered as the file numbers them
    /// ([`C3d::frame_number`]).
    pub first_frame: usize,
    pub last_frame: usize,
    /// The times of the first and last sample in seconds, on the file's time base
    /// ([`C3d::analog_time`], the EVENT group's base).
    pub first_time: f64,
    pub last_time: f64,
    /// Largest push in the stretch (N).
    pub peak: f64,
}

/// Where a plate's unloaded level was read.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum BaselineSource {
    /// FORCE_PLATFORM:ZERO's frames.
    #[serde(rename = "FORCE_PLATFORM:ZERO")]
    Zero,
    /// The plate's quietest low stretch ([`kinetics::baseline::quiet_stretch`]).
    #[serde(rename = "quiet")]
    Quiet,
}

impl BaselineSource {
    pub fn name(self) -> &'static str {
        match self {
            BaselineSource::Zero => "FORCE_PLATFORM:ZERO",
            BaselineSource::Quiet => "quiet",
        }
    }
}

/// The unloaded level subtracted from a plate's channels: each channel's mean over these
/// samples.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Baseline {
    pub source: BaselineSource,
    /// First and last analog sample (0-based), inclusive.
    pub first_sample: usize,
    pub last_sample: usize,
    /// The point frames they fall in, numbered as the file numbers them.
    pub first_frame: usize,
    pub last_frame: usize,
    /// The push the plate read there (N), now removed: negative for a pull.
    pub level: f64,
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
    /// The unloaded level subtracted, if any.
    pub baseline: Option<Baseline>,
    /// The low-pass filter applied to the channels, if any.
    pub filtered: Option<String>,
    pub force: Vec<[f64; 3]>,
    /// About the centre of the working surface.
    pub moment: Vec<[f64; 3]>,
    /// NaN (null in JSON) where the push is below the threshold.
    pub cop: Vec<[f64; 3]>,
    pub free_moment: Vec<[f64; 3]>,
    /// The push: −Fz of the plate's own frame (N), which the threshold judges
    /// ([`kinetics::plate::PlateOutput::push`]).
    pub push: Vec<f64>,
    /// Largest push over the trial (N).
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
    /// The time of the first analog sample on the file's time base ([`C3d::analog_time`]).
    #[serde(skip)]
    pub start_time: f64,
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

    /// The time of analog sample `i` in seconds on the file's time base (frame `n` at
    /// (`n` − 1) / POINT:RATE, the EVENT group's base), as [`C3d::analog_time`] gives it.
    pub fn time(&self, i: usize) -> f64 {
        match self.platforms.first() {
            Some(p) if p.rate > 0.0 && p.rate.is_finite() => self.start_time + i as f64 / p.rate,
            _ => self.start_time,
        }
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
        return Err(Error::OutOfRange {
            setting: Setting::Threshold,
            value: opts.threshold.to_string(),
            limits: "expected 0 N or more".into(),
        });
    }
    let rate = c.analog_rate() as f64;
    let filter = match &opts.lowpass {
        Some(spec) => {
            let iir = spec
                .validate()
                .and_then(|_| spec.design(rate))
                .map_err(|e| Error::options(format!("low-pass filter {spec}: {e}")))?;
            Some((spec.to_string(), iir))
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
        start_time: c.analog_time(0),
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
    // How many channels ANALOG:SCALE and OFFSET really describe (the calibration pads the
    // rest with 1 and 0, which is no calibration for a force channel).
    let described = |name: &str| c.param("ANALOG", name).map_or(0, |p| p.value.len());
    let spf = out.samples_per_frame;
    let samples = c.analog().samples();
    let zero = zero_stretch(opts, fp.zero, spf, samples, &mut out.warnings);
    let trial = plate::Trial {
        c,
        opts,
        rate,
        filter,
        point_mm: c3d::mm_per_unit(&point_units),
        point_units,
        analog_units: c.analog_units(),
        cal: c.analog_calibration(),
        scaled: described("SCALE"),
        offset_known: described("OFFSET"),
        samples,
        spf,
        zero,
    };
    for p in &fp.plates {
        if let Some(platform) = trial.plate(p, &mut out.warnings) {
            out.platforms.push(platform);
        }
    }
    Ok(out)
}

/// FORCE_PLATFORM:ZERO's samples, when asked for and within the data; absent or [0, 0],
/// each plate's quiet stretch is used, as it is when ZERO's frames carry a load.
fn zero_stretch(
    opts: &ForceOptions,
    zero: Option<[usize; 2]>,
    spf: usize,
    samples: usize,
    warnings: &mut Vec<PlateWarning>,
) -> Option<([usize; 2], Range<usize>)> {
    match (opts.zero_baseline, zero) {
        (true, Some([a, b])) => {
            let (s0, s1) = ((a - 1) * spf, (b * spf).min(samples));
            if s0 >= s1 {
                warnings.push(PlateWarning {
                    plate: 0,
                    parameter: "FORCE_PLATFORM:ZERO".into(),
                    message: format!("frames {a}..{b} lie beyond the trial's analog data: each plate's quiet stretch is used instead"),
                });
                None
            } else {
                Some(([a, b], s0..s1))
            }
        }
        _ => None,
    }
}

/// Loaded samples (push at least the threshold, a finite COP) needed before the COP's place
/// on the plate is judged for [`reversed_origin`]: a tenth of a second at 1 kHz.
const MIN_LOADED_SAMPLES: usize = 100;

/// The plate computed with FORCE_PLATFORM:ORIGIN's x and y negated, when the ORIGIN as
/// stored puts the centre of pressure outside the plate's corners in most loaded samples
/// and the negated one puts it inside in at least nine in ten: the physics decides (a foot
/// stands on the plate), and some writers store the transducer's offset from the other end
/// (`c3d-labs`' rtosim treadmill: 100 % outside as stored). With the fractions outside,
/// before and after. Type 3 plates' ORIGIN holds the sensors' distances, not an offset: left
/// alone.
fn reversed_origin(
    spec: &PlateSpec,
    refs: &[&[f64]],
    threshold: f64,
    r: &kinetics::PlateOutput,
) -> Option<(kinetics::PlateOutput, f64, f64)> {
    if spec.kind == 3 || !(spec.origin[0] != 0.0 || spec.origin[1] != 0.0) {
        return None;
    }
    let off = |o: &kinetics::PlateOutput| -> Option<f64> {
        let loaded: Vec<&[f64; 3]> = o
            .push
            .iter()
            .zip(&o.cop)
            .filter(|(p, c)| **p >= threshold && c.iter().all(|v| v.is_finite()))
            .map(|(_, c)| c)
            .collect();
        (loaded.len() >= MIN_LOADED_SAMPLES).then(|| {
            let n = loaded
                .iter()
                .filter(|c| off_plate(&spec.corners, c, spec.mm_per_unit))
                .count();
            n as f64 / loaded.len() as f64
        })
    };
    let before = off(r)?;
    if before <= 0.5 {
        return None;
    }
    let flipped = PlateSpec {
        origin: [-spec.origin[0], -spec.origin[1], spec.origin[2]],
        ..*spec
    };
    let r2 = kinetics::compute(&flipped, refs, threshold).ok()?;
    let after = off(&r2)?;
    (after <= 0.1).then_some((r2, before, after))
}

/// The stretch whose channel means are the plate's unloaded level: ZERO's samples where the
/// plate reads no load there, else the quiet stretch of [`kinetics::baseline`]; with what to
/// tell the user when the rule had to depart from ZERO or found nothing.
#[allow(clippy::type_complexity)]
fn unloaded_stretch(
    spec: &PlateSpec,
    ch: &[Vec<f64>],
    zero: Option<&([usize; 2], Range<usize>)>,
    rate: f64,
) -> (Option<(BaselineSource, Range<usize>, f64)>, Option<String>) {
    let refs: Vec<&[f64]> = ch.iter().map(|v| v.as_slice()).collect();
    // The raw plate, only for its push and force; errors are the caller's to report.
    let Ok(raw) = kinetics::compute(spec, &refs, f64::INFINITY) else {
        return (None, None);
    };
    let mut note = None;
    if let Some(([a, b], range)) = zero {
        let level = kinetics::baseline::level(&raw.push, range);
        let long = range.len() as f64 >= kinetics::baseline::MIN_ZERO_S * rate;
        if !long {
            note = Some(format!(
                "frames {a}..{b} span less than {} s: too short to average the plate's noise",
                kinetics::baseline::MIN_ZERO_S
            ));
        } else if kinetics::baseline::unloaded(level) {
            return (Some((BaselineSource::Zero, range.clone(), level)), None);
        } else {
            note = Some(if level.is_finite() {
                format!(
                "frames {a}..{b} carry a push of {level:.0} N, a load (an unloaded plate reads at most {} N): not taken as its zero",
                kinetics::baseline::MAX_UNLOADED_N
            )
            } else {
                format!("frames {a}..{b} hold samples that are not finite: not taken as its zero")
            });
        }
    }
    match kinetics::baseline::quiet_stretch(&raw.push, &raw.force, rate) {
        Some(q) if !kinetics::baseline::steady_pull(q.level, q.spread) => {
            let m = format!(
                "its quietest low stretch reads a pull of {:.1} N that moves by {:.1} N, pulls coming and going rather than an offset: nothing subtracted (a pull is never a load)",
                -q.level, q.spread
            );
            (None, Some(note.map_or(m.clone(), |n| format!("{n}; {m}"))))
        }
        Some(q) if kinetics::baseline::unloaded(q.level) => {
            let found = (BaselineSource::Quiet, q.range, q.level);
            let note = note.map(|n| format!("{n}; its quietest low stretch is used"));
            (Some(found), note)
        }
        Some(q) => {
            let m = format!(
                "the plate carries at least {:.0} N throughout (a subject standing on it?): no unloaded stretch, nothing subtracted",
                q.level
            );
            (None, Some(note.map_or(m.clone(), |n| format!("{n}; {m}"))))
        }
        None => {
            let m = "no stretch of finite samples as long as a baseline window: nothing subtracted"
                .to_string();
            (None, Some(note.map_or(m.clone(), |n| format!("{n}; {m}"))))
        }
    }
}
