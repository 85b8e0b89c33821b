//! The words of a trial's plates: what a person asks for ([`ForceOptions`]), and what each
//! plate gives back ([`Platform`], its [`Contact`]s, [`Baseline`] and [`Units`], the
//! [`PlateWarning`]s); `force_platforms` (in the module above) and each plate's computation
//! (`plate.rs`) both speak them, so they live apart from either.

use serde::Serialize;

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
    /// ([`c3d::C3d::frame_number`]).
    pub first_frame: usize,
    pub last_frame: usize,
    /// The times of the first and last sample in seconds, on the file's time base
    /// ([`c3d::C3d::analog_time`], the EVENT group's base).
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
    /// The time of the first analog sample on the file's time base ([`c3d::C3d::analog_time`]).
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
    /// (`n` − 1) / POINT:RATE, the EVENT group's base), as [`c3d::C3d::analog_time`] gives it.
    pub fn time(&self, i: usize) -> f64 {
        match self.platforms.first() {
            Some(p) if p.rate > 0.0 && p.rate.is_finite() => self.start_time + i as f64 / p.rate,
            _ => self.start_time,
        }
    }
}

/// A parameter value as stored (single precision), for messages: `37.84`, not
/// `37.84000015258789`; no negative zero.
pub(super) fn short(v: f64) -> String {
    format!("{}", v as f32 + 0.0)
}

pub(super) fn triple(v: [f64; 3]) -> String {
    format!("[{}, {}, {}]", short(v[0]), short(v[1]), short(v[2]))
}
