//! A plate's unloaded level: where it is read (FORCE_PLATFORM:ZERO's frames, else the
//! quietest low stretch) and an ORIGIN stored with the wrong sign, found from the loads.

use super::bounds::off_plate;
use super::model::{BaselineSource, ForceOptions, PlateWarning};
use kinetics::PlateSpec;
use std::ops::Range;

/// FORCE_PLATFORM:ZERO's samples, when asked for and within the data; absent or [0, 0],
/// each plate's quiet stretch is used, as it is when ZERO's frames carry a load.
pub(super) fn zero_stretch(
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
pub(super) fn reversed_origin(
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
pub(super) fn unloaded_stretch(
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
    // A run's plate (a treadmill belt's above all) is loaded in every quarter second and
    // unloaded only in the flights between steps: looked for there before the plate is
    // said to carry a load throughout.
    let quiet = match kinetics::baseline::quiet_stretch(&raw.push, &raw.force, rate) {
        Some(q) if !kinetics::baseline::unloaded(q.level) => {
            kinetics::baseline::quiet_flight(&raw.push, &raw.force, rate)
                .filter(|f| kinetics::baseline::unloaded(f.level))
                .or(Some(q))
        }
        other => other,
    };
    match quiet {
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
