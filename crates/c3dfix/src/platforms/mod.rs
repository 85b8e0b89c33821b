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
mod level;
mod model;
mod plate;
mod table;
mod units;

pub(crate) use bounds::off_plate;
pub use bounds::EDGE_MM;
pub use model::{
    Baseline, BaselineSource, Contact, ForceOptions, ForcePlatforms, PlateWarning, Platform, Units,
    DEFAULT_THRESHOLD_N,
};
pub use table::ForcesReport;

use level::zero_stretch;

use crate::error::{Error, Result, Setting};
use c3d::C3d;

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
