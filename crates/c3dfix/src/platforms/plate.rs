//! One plate of a trial computed from its channels: the checks that leave it out, its
//! channels in physical units with the unloaded level removed and the filter applied, the
//! plate maths, and every warning in the order it arises (the order the reports print).

use super::level::{reversed_origin, unloaded_stretch};
use super::model::{short, triple, Baseline, Contact, ForceOptions, PlateWarning, Platform, Units};
use super::{channels, units};
use c3d::{C3d, PlateParams};
use kinetics::PlateSpec;
use std::ops::Range;

/// What every plate of one trial shares.
pub(super) struct Trial<'a> {
    pub c: &'a C3d,
    pub opts: &'a ForceOptions,
    /// The analog rate (Hz).
    pub rate: f64,
    /// The low-pass filter asked for, as written and as designed.
    pub filter: Option<(String, repair::filter::Iir)>,
    pub point_units: String,
    pub point_mm: f64,
    pub analog_units: Vec<String>,
    pub cal: c3d::Calibration,
    /// How many channels ANALOG:SCALE and OFFSET describe.
    pub scaled: usize,
    pub offset_known: usize,
    /// Analog samples, and per point frame.
    pub samples: usize,
    pub spf: usize,
    /// FORCE_PLATFORM:ZERO's frames and samples, when they apply.
    pub zero: Option<([usize; 2], Range<usize>)>,
}

/// A warning about `plate`'s FORCE_PLATFORM `parameter`.
fn warn(warnings: &mut Vec<PlateWarning>, plate: usize, parameter: &str, message: String) {
    warnings.push(PlateWarning {
        plate,
        parameter: format!("FORCE_PLATFORM:{parameter}"),
        message,
    })
}

impl Trial<'_> {
    /// Plate `p` computed, or `None` when it is left out (said in `warnings`).
    pub fn plate(&self, p: &PlateParams, warnings: &mut Vec<PlateWarning>) -> Option<Platform> {
        let (kind, used) = self.usable(p, warnings)?;
        let (Some(corners), Some(origin)) = (p.corners, p.origin) else {
            return None;
        };
        let mut ch = channels::physical(self.c.analog(), &self.cal, used);
        let spec = PlateSpec {
            kind: p.kind,
            corners,
            origin,
            cal_matrix: p.cal_matrix.as_deref(),
            cop_poly: p.cop_poly,
            mm_per_unit: self.point_mm,
        };
        let baseline = self.baseline(p.index, &spec, &mut ch, warnings);
        let filtered = self.prepared(p.index, kind, used, &mut ch, warnings);
        let refs: Vec<&[f64]> = ch.iter().map(|v| v.as_slice()).collect();
        let threshold = self.opts.threshold;
        let r = match kinetics::compute(&spec, &refs, threshold) {
            Ok(r) => r,
            Err(e) => {
                let what = format!("{e}: plate left out");
                warn(warnings, p.index, e.parameter(), what);
                return None;
            }
        };
        let r = self.origin_checked(p.index, kind, &spec, &refs, r, warnings);
        Some(self.platform(p, used, corners, baseline, filtered, r))
    }

    /// The plate's kind and the channels it reads, unless its type, channel list or the
    /// analog calibration leaves it out.
    fn usable<'p>(
        &self,
        p: &'p PlateParams,
        warnings: &mut Vec<PlateWarning>,
    ) -> Option<(kinetics::PlateKind, &'p [usize])> {
        let kind = match kinetics::PlateKind::from_type(p.kind) {
            Ok(k) => k,
            Err(e) => {
                let parameter = e.parameter();
                let what = format!("FORCE_PLATFORM:{parameter} {e}: plate left out");
                warn(warnings, p.index, parameter, what);
                return None;
            }
        };
        if p.corners.is_none() || p.origin.is_none() {
            // Already reported by the parameter reading.
            return None;
        }
        if p.channels.is_empty() {
            return None;
        }
        if p.channels.len() < kind.channels() {
            warn(
                warnings,
                p.index,
                "CHANNEL",
                format!(
                    "lists {} channels; type {} needs {}: plate left out",
                    p.channels.len(),
                    p.kind,
                    kind.channels()
                ),
            );
            return None;
        }
        let used = &p.channels[..kind.channels()];
        if let Some(&k) = used
            .iter()
            .find(|&&k| k > self.scaled || k > self.offset_known)
        {
            let (name, n) = if k > self.scaled {
                ("SCALE", self.scaled)
            } else {
                ("OFFSET", self.offset_known)
            };
            warnings.push(PlateWarning {
                plate: p.index,
                parameter: format!("ANALOG:{name}"),
                message: format!(
                    "has {n} entries, none for the plate's channel {k}: plate left out"
                ),
            });
            return None;
        }
        Some((kind, used))
    }

    /// The plate's unloaded level removed from its channels, when asked for and found.
    fn baseline(
        &self,
        plate: usize,
        spec: &PlateSpec,
        ch: &mut [Vec<f64>],
        warnings: &mut Vec<PlateWarning>,
    ) -> Option<Baseline> {
        if !self.opts.zero_baseline {
            return None;
        }
        let (found, message) = unloaded_stretch(spec, ch, self.zero.as_ref(), self.rate);
        if let Some(message) = message {
            // Named for ZERO when the file set one; else the rule's own.
            let parameter = if self.zero.is_some() {
                "FORCE_PLATFORM:ZERO"
            } else {
                "baseline"
            };
            warnings.push(PlateWarning {
                plate,
                parameter: parameter.into(),
                message,
            });
        }
        let (source, range, level) = found?;
        channels::subtract_baseline(ch, &range);
        let (c, spf) = (self.c, self.spf);
        Some(Baseline {
            source,
            first_sample: range.start,
            last_sample: range.end - 1,
            first_frame: c.frame_number(range.start / spf),
            last_frame: c.frame_number((range.end - 1) / spf),
            level,
        })
    }

    /// What the channels hold that a reader should know (samples not finite, a channel that
    /// recorded nothing, a length unit that is not POINT:UNITS), and the filter applied when
    /// it can be: its spec when it was.
    fn prepared(
        &self,
        plate: usize,
        kind: kinetics::PlateKind,
        used: &[usize],
        ch: &mut [Vec<f64>],
        warnings: &mut Vec<PlateWarning>,
    ) -> Option<String> {
        let bad = channels::non_finite(ch);
        if bad > 0 {
            warn(
                warnings,
                plate,
                "CHANNEL",
                format!("analog data hold {bad} samples that are not finite: those samples give no force"),
            );
        }
        for i in channels::constant(ch) {
            warn(
                warnings,
                plate,
                "CHANNEL",
                format!(
                    "channel {} holds one value throughout: it recorded nothing, so what depends on it (moments, COP) is not measured",
                    used[i]
                ),
            );
        }
        let mut filtered = None;
        if let Some((spec, iir)) = &self.filter {
            if bad > 0 {
                warn(
                    warnings,
                    plate,
                    "CHANNEL",
                    format!("not filtered ({spec}): its analog data are not all finite"),
                );
            } else if channels::filter(ch, iir) {
                filtered = Some(spec.clone());
            } else {
                let samples = self.samples;
                warn(
                    warnings,
                    plate,
                    "CHANNEL",
                    format!("not filtered ({spec}): {samples} samples are too few for its padding"),
                );
            }
        }
        let point_units = &self.point_units;
        for (k, label) in units::mislabelled(kind, used, &self.analog_units, self.point_mm) {
            warn(
                warnings,
                plate,
                "CHANNEL",
                format!(
                    "channel {k} is labelled {label:?} (ANALOG:UNITS), but the manual has every length in POINT:UNITS: read in {point_units}"
                ),
            );
        }
        filtered
    }

    /// The plate's result, read with its ORIGIN's x and y negated where the ORIGIN as stored
    /// puts the centre of pressure off the plate and the negated one on it; each ORIGIN the
    /// maths had to read otherwise than stored is said.
    fn origin_checked(
        &self,
        plate: usize,
        kind: kinetics::PlateKind,
        spec: &PlateSpec,
        refs: &[&[f64]],
        r: kinetics::PlateOutput,
        warnings: &mut Vec<PlateWarning>,
    ) -> kinetics::PlateOutput {
        let origin = spec.origin;
        let (r, reversed) = match reversed_origin(spec, refs, self.opts.threshold, &r) {
            Some((r2, before, after)) => (r2, Some((before, after))),
            None => (r, None),
        };
        if let Some((before, after)) = reversed {
            warn(
                warnings,
                plate,
                "ORIGIN",
                format!(
                    "x and y are {}, {}, which put the centre of pressure outside the plate in {:.0} % of its loaded samples; with their signs reversed, {:.0} %: read as {} (the transducer's offset written from the other end)",
                    short(origin[0]),
                    short(origin[1]),
                    100.0 * before,
                    100.0 * after,
                    triple(r.origin.used)
                ),
            );
        }
        if r.origin.corrected {
            warn(
                warnings,
                plate,
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
                warnings,
                plate,
                "ORIGIN",
                format!(
                    "gives the sensors' distances a = {}, b = {}: with a zero the moments about that axis vanish and the COP cannot leave the plate's centre line",
                    short(r.origin.used[0]),
                    short(r.origin.used[1])
                ),
            );
        }
        r
    }

    /// The plate as reported: its result, peak push and contacts in the file's frames and
    /// times, and its units.
    fn platform(
        &self,
        p: &PlateParams,
        used: &[usize],
        corners: [[f64; 3]; 4],
        baseline: Option<Baseline>,
        filtered: Option<String>,
        r: kinetics::PlateOutput,
    ) -> Platform {
        let (c, spf) = (self.c, self.spf);
        let peak_force = r
            .push
            .iter()
            .filter(|v| v.is_finite())
            .fold(0.0f64, |m, &v| m.max(v));
        let contacts = kinetics::contacts(&r.push, self.opts.threshold, self.rate)
            .into_iter()
            .map(|[a, b]| Contact {
                first_sample: a,
                last_sample: b,
                first_frame: c.frame_number(a / spf),
                last_frame: c.frame_number(b / spf),
                first_time: c.analog_time(a),
                last_time: c.analog_time(b),
                peak: r.push[a..=b].iter().fold(0.0f64, |m, &v| m.max(v)),
            })
            .collect();
        Platform {
            index: p.index,
            kind: p.kind,
            rate: self.rate,
            channels: used.to_vec(),
            corners,
            centre: r.frame.centre,
            origin: r.origin.used,
            origin_corrected: r.origin.corrected,
            baseline,
            filtered,
            force: r.force,
            moment: r.moment,
            cop: r.cop,
            free_moment: r.free_moment,
            push: r.push,
            peak_force,
            contacts,
            units: Units {
                force: "N".into(),
                moment: format!("N{}", self.point_units),
                position: self.point_units.clone(),
            },
        }
    }
}
