//! Writing: [`C3d`] → bytes.
//!
//! Two paths. A file that was read is *patched*: its original bytes are copied and only what
//! changed is re-encoded (parameter records, header words, data samples); a parameter section
//! that outgrows its blocks moves the data section. A new file, or a conversion to another
//! processor or number format, is written *fresh*: header derived from the parameters and data.

use crate::data::{Encode, Layout};
use crate::error::{Error, Result};
use crate::file::{C3d, NumberFormat, Source};
use crate::header::{Header, BLOCK, KEY_12345};
use crate::parameters::{Parameters, Value};
use crate::processor::Processor;
use std::borrow::Cow;
use std::path::Path;

impl C3d {
    /// The file's bytes: identical to what was read when nothing changed.
    pub fn to_bytes(&self) -> Result<Vec<u8>> {
        self.check_shapes()?;
        match &self.source {
            Some(src) => self.write_patched(src),
            None => self.write_fresh(self.processor(), self.format(), None),
        }
    }

    /// Write to `path` (plainly; the command-line tool adds atomic replacement).
    pub fn write_file(&self, path: impl AsRef<Path>) -> Result<()> {
        std::fs::write(path, self.encoded()?)?;
        Ok(())
    }

    /// The file re-encoded for another processor and/or number format. `scale` overrides
    /// POINT:SCALE when converting to integers (by default the current scale is kept when the
    /// data are exact multiples of it and fit, else the finest scale that fits is chosen).
    pub fn convert(
        &self,
        processor: Processor,
        format: NumberFormat,
        scale: Option<f32>,
    ) -> Result<Vec<u8>> {
        self.converted(processor, format, scale)
            .map(Cow::into_owned)
    }

    /// [`C3d::convert`], borrowing the bytes that were read when the conversion changes
    /// nothing (see [`C3d::encoded`]).
    pub fn converted(
        &self,
        processor: Processor,
        format: NumberFormat,
        scale: Option<f32>,
    ) -> Result<Cow<'_, [u8]>> {
        self.check_shapes()?;
        if processor == self.processor() && format == self.format() && scale.is_none() {
            return self.encoded();
        }
        if let Some(s) = scale.filter(|s| s.is_finite() && *s != 0.0) {
            if format == NumberFormat::Integer {
                check_integer_scale(self.points(), s.abs())?;
            }
        }
        self.write_fresh(processor, format, scale).map(Cow::Owned)
    }

    fn check_shapes(&self) -> Result<()> {
        // Arrays not decoded yet are the file's own, of its shape.
        if !self.points_dirty && !self.analog_dirty {
            return Ok(());
        }
        let p = self.points();
        let n = p.frames() * p.count();
        if p.xyz.len() != n || p.residual.len() != n || p.camera_mask.len() != n {
            return Err(Error::Misuse(format!(
                "point arrays must hold {} frames × {} points = {n} samples",
                p.frames(),
                p.count()
            )));
        }
        let a = self.analog();
        let m = a.samples() * a.channels();
        if a.raw.len() != m {
            return Err(Error::Misuse(format!(
                "analog array must hold {} samples × {} channels = {m} values",
                a.samples(),
                a.channels()
            )));
        }
        if a.channels() > 0 && p.frames() * a.samples_per_frame() != a.samples() {
            return Err(Error::Misuse(
                "analog and point data must cover the same frames".into(),
            ));
        }
        Ok(())
    }

    fn write_patched(&self, src: &Source) -> Result<Vec<u8>> {
        let p = src.processor;
        let l = src.layout;
        if (self.points_dirty
            && (self.points().frames() != l.frames || self.points().count() != l.points))
            || (self.analog_dirty
                && (self.analog().channels() != l.analog_channels
                    || self.analog().samples_per_frame() != l.analog_samples_per_frame))
        {
            // A different shape cannot be patched in: write the file afresh.
            return self.write_fresh(p, self.format(), None);
        }
        let mut out = src.bytes.to_vec();
        let mut header = self.header.clone();
        let mut data_offset = src.data_offset;
        if !self.parameters.unchanged(p) {
            let mut params = self.parameters.clone();
            let mut sec = params.encode(p)?;
            let limit = next_structure(src, &self.header);
            let space = limit - src.param_start;
            let mut clear_to = src.param_end.min(limit);
            if sec.len() > space {
                if data_offset < limit && data_offset > src.param_start {
                    return Err(Error::Unrepresentable(
                        "the parameter section grew but the data section overlaps it".into(),
                    ));
                }
                let extra = (sec.len() - space).div_ceil(BLOCK) * BLOCK;
                out.splice(limit..limit, std::iter::repeat_n(0u8, extra));
                clear_to = limit + extra;
                if data_offset >= limit {
                    data_offset += extra;
                    let ds = data_offset / BLOCK + 1;
                    header.data_start = u16::try_from(ds).map_err(|_| {
                        Error::Unrepresentable(format!("data start block {ds} exceeds 65535"))
                    })?;
                    if params.get("POINT", "DATA_START").is_some() {
                        params.set_i16("POINT", "DATA_START", ds as u16 as i16)?;
                    }
                    sec = params.encode(p)?;
                }
                let lr = header.label_range_block as usize;
                if header.label_range_key == KEY_12345 && lr > 0 && (lr - 1) * BLOCK >= limit {
                    header.label_range_block += (extra / BLOCK) as u16;
                }
            }
            let start = src.param_start;
            out[start..start + sec.len()].copy_from_slice(&sec);
            if clear_to > start + sec.len() {
                out[start + sec.len()..clear_to].fill(0);
            }
        }
        header.encode_into(&mut out[..BLOCK], p, Some(&src.header));
        let need = l.data_bytes();
        // With no data bytes there is nothing to patch (and the data start may lie anywhere).
        if (self.points_dirty || self.analog_dirty) && need > 0 {
            // A damaged file can have its data section overlap the header or the parameters.
            // Edited samples must not be written over those: such a file is written afresh.
            let data = data_offset..data_offset + need;
            let structure = [0..BLOCK, src.param_start..src.param_end];
            let shared: Vec<_> = structure
                .into_iter()
                .map(|r| r.start.max(data.start)..r.end.min(data.end))
                .filter(|r| r.start < r.end)
                .map(|r| (r.clone(), out[r].to_vec()))
                .collect();
            p.dispatch(Encode {
                out: &mut out[data],
                layout: l,
                points: self.points_dirty.then(|| self.points()),
                analog: self.analog_dirty.then(|| self.analog()),
                force: false,
            })?;
            if shared
                .iter()
                .any(|(r, before)| out[r.clone()] != before[..])
            {
                // Integer samples keep their scale, so the samples left alone keep their
                // values exactly (edited ones were kept within its range by the editor).
                let keep = Some(l.point_scale)
                    .filter(|s| !l.float && *s > 0.0 && s.is_finite() && fits(self.points(), *s));
                return self.write_fresh(p, self.format(), keep);
            }
        }
        Ok(out)
    }

    fn write_fresh(
        &self,
        processor: Processor,
        format: NumberFormat,
        scale: Option<f32>,
    ) -> Result<Vec<u8>> {
        let pts = self.points();
        let float = format == NumberFormat::Float;
        let old = self.layout();
        let abs_scale = match scale {
            Some(s) if s.is_finite() && s != 0.0 => s.abs(),
            Some(s) => return Err(Error::Misuse(format!("scale {s} must be finite and not 0"))),
            None if float => match old.point_scale {
                s if s > 0.0 && s.is_finite() => s,
                _ => 1.0,
            },
            None => integer_scale(pts, old.point_scale),
        };
        let mut params = self.parameters.clone();
        let mut analog = self.analog().clone();
        let mut unsigned = old.unsigned_analog;
        if !float && old.float {
            unsigned = analog_to_integers(&mut analog, &mut params, unsigned)?;
        }
        let frames = pts.frames();
        let layout = Layout {
            points: pts.count(),
            analog_channels: analog.channels(),
            analog_samples_per_frame: analog.samples_per_frame().max(1),
            frames,
            float,
            unsigned_analog: unsigned,
            point_scale: abs_scale,
        };
        let signed_scale = if float { -abs_scale } else { abs_scale };
        params.set_f32("POINT", "SCALE", signed_scale)?;
        params.set_i16("POINT", "USED", layout.points as u16 as i16)?;
        if frames <= 65535 {
            params.set_i16("POINT", "FRAMES", frames as u16 as i16)?;
        } else {
            params.set_i16("POINT", "FRAMES", -1)?;
            params.set_f32("POINT", "LONG_FRAMES", frames as f32)?;
            let first = self.first_frame().max(1);
            let last = first + frames - 1;
            let split =
                |v: usize| Value::Int(vec![(v & 0xffff) as u16 as i16, (v >> 16) as u16 as i16]);
            params.set("TRIAL", "ACTUAL_START_FIELD", vec![2], split(first))?;
            params.set("TRIAL", "ACTUAL_END_FIELD", vec![2], split(last))?;
        }
        if params.get("POINT", "RATE").is_none() && self.header.frame_rate > 0.0 {
            params.set_f32("POINT", "RATE", self.header.frame_rate)?;
        }
        if layout.analog_channels > 0 {
            params.set_i16("ANALOG", "USED", layout.analog_channels as u16 as i16)?;
        }
        // DATA_START depends on the section's size, which setting it does not change.
        params.set_i16("POINT", "DATA_START", 0)?;
        let sec_len = params.encode(processor)?.len();
        let data_start = 2 + sec_len / BLOCK;
        params.set_i16("POINT", "DATA_START", data_start as u16 as i16)?;
        let sec = params.encode(processor)?;

        let mut header = Header {
            parameter_block: 2,
            key: 0x50,
            point_count: layout.points as u16,
            analog_per_frame: layout.analog_words() as u16,
            first_frame: self.header.first_frame.max(1),
            last_frame: 0,
            max_gap: self.header.max_gap,
            scale: signed_scale,
            data_start: data_start as u16,
            analog_samples_per_frame: if layout.analog_channels > 0 {
                layout.analog_samples_per_frame as u16
            } else {
                0
            },
            frame_rate: self.point_rate(),
            label_range_key: 0,
            label_range_block: 0,
            ..self.header.clone()
        };
        let last = header.first_frame as usize + frames.saturating_sub(1);
        header.last_frame = last.min(65535) as u16;
        if frames == 0 {
            header.last_frame = header.first_frame.saturating_sub(1);
        }
        if layout.points > 65535 || layout.analog_words() > 65535 {
            return Err(Error::Unrepresentable(
                "more than 65535 points or analog words per frame".into(),
            ));
        }

        let mut out = vec![0u8; BLOCK];
        header.encode_into(&mut out, processor, None);
        out.extend_from_slice(&sec);
        let data_offset = out.len();
        out.resize(data_offset + layout.data_bytes(), 0);
        processor.dispatch(Encode {
            out: &mut out[data_offset..],
            layout,
            points: Some(pts),
            analog: Some(&analog),
            force: true,
        })?;
        out.resize(out.len().div_ceil(BLOCK) * BLOCK, 0);
        Ok(out)
    }
}

/// Where the bytes after the parameter section belong to something else: the data section or
/// the label/range section, whichever comes first after it.
fn next_structure(src: &Source, h: &Header) -> usize {
    let mut limit = usize::MAX;
    if src.data_offset > src.param_start {
        limit = limit.min(src.data_offset);
    }
    let lr = h.label_range_block as usize;
    if h.label_range_key == KEY_12345 && lr > 0 && (lr - 1) * BLOCK > src.param_start {
        limit = limit.min((lr - 1) * BLOCK);
    }
    if limit == usize::MAX {
        limit = src.param_end.div_ceil(BLOCK) * BLOCK;
    }
    limit.min(src.bytes.len()).max(src.param_start)
}

/// Whether every valid coordinate fits in 16 bits at `scale`.
fn fits(pts: &crate::points::Points, scale: f32) -> bool {
    (max_valid_abs(pts) / scale).round() <= 32767.0
}

/// Largest |coordinate| of the valid samples.
fn max_valid_abs(pts: &crate::points::Points) -> f32 {
    pts.xyz
        .iter()
        .zip(&pts.residual)
        .filter(|(_, &r)| r >= 0.0)
        .flat_map(|(xyz, _)| xyz.iter().map(|v| v.abs()))
        .fold(0f32, f32::max)
}

/// A requested integer scale must hold the data: fine enough that the largest coordinate
/// is at least one step (else every coordinate is stored as 0 or ±1 and the trial is lost),
/// coarse enough that it fits in 16 bits.
fn check_integer_scale(pts: &crate::points::Points, scale: f32) -> Result<()> {
    let max = max_valid_abs(pts);
    if max > 0.0 && max.is_finite() && (scale > max || max / scale > 32767.0) {
        return Err(Error::Misuse(format!(
            "scale {scale} does not suit the data: the largest coordinate is {max}, so the scale must be from {} to {max}",
            max / 32767.0
        )));
    }
    Ok(())
}

/// The POINT:SCALE for integer data: the current one when every valid coordinate is an exact
/// multiple of it that fits in int16 (so int → float → int is lossless), else the finest scale
/// at which every valid coordinate fits.
fn integer_scale(pts: &crate::points::Points, current: f32) -> f32 {
    let mut max_abs = 0f32;
    let mut exact = current > 0.0 && current.is_finite();
    for (xyz, &r) in pts.xyz.iter().zip(&pts.residual) {
        if r < 0.0 {
            continue;
        }
        for &v in xyz {
            max_abs = max_abs.max(v.abs());
            if exact {
                let q = (v / current).round();
                exact = q.abs() <= 32767.0 && (q * current).to_bits() == v.to_bits();
            }
        }
    }
    if exact {
        current
    } else if max_abs > 0.0 {
        max_abs / 32000.0
    } else {
        1.0
    }
}

/// Prepare float analog data for integer storage. Channels holding whole numbers in range are
/// kept; others are rescaled (ANALOG:SCALE and OFFSET updated, physical values preserved to
/// 16-bit precision). Returns whether the integers are unsigned.
fn analog_to_integers(
    analog: &mut crate::analog::Analog,
    params: &mut Parameters,
    unsigned: bool,
) -> Result<bool> {
    let ch = analog.channels();
    if ch == 0 {
        return Ok(unsigned);
    }
    let (lo, hi) = if unsigned {
        (0.0, 65535.0)
    } else {
        (-32768.0, 32767.0)
    };
    let fits = |c: usize, a: &crate::analog::Analog| {
        a.raw
            .iter()
            .skip(c)
            .step_by(ch)
            .all(|&v| v.fract() == 0.0 && (lo..=hi).contains(&v))
    };
    if (0..ch).all(|c| fits(c, analog)) {
        return Ok(unsigned);
    }
    let mut scale = params
        .get("ANALOG", "SCALE")
        .map(|p| p.as_f32s())
        .unwrap_or_default();
    scale.resize(ch, 1.0);
    let mut offset = params
        .get("ANALOG", "OFFSET")
        .map(|p| {
            if unsigned {
                p.as_u16s().into_iter().map(|v| v as f32).collect()
            } else {
                p.as_f32s()
            }
        })
        .unwrap_or_default();
    offset.resize(ch, 0.0);
    let mut new_offset: Vec<i16> = Vec::with_capacity(ch);
    for c in 0..ch {
        if fits(c, analog) && !unsigned {
            new_offset.push(offset[c] as i16);
            continue;
        }
        // physical/gen = (raw - off) * sc  →  raw' = (raw - off) * sc / sc', offset 0.
        let max_abs = analog
            .raw
            .iter()
            .skip(c)
            .step_by(ch)
            .map(|&v| ((v - offset[c]) * scale[c]).abs())
            .fold(0f32, f32::max);
        let new_sc = if max_abs > 0.0 {
            max_abs / 32000.0
        } else {
            1.0
        };
        for v in analog.raw.iter_mut().skip(c).step_by(ch) {
            *v = ((*v - offset[c]) * scale[c] / new_sc).round();
        }
        scale[c] = new_sc;
        new_offset.push(0);
    }
    params.set("ANALOG", "SCALE", vec![ch as u8], Value::Float(scale))?;
    params.set("ANALOG", "OFFSET", vec![ch as u8], Value::Int(new_offset))?;
    if unsigned {
        params.set_strings("ANALOG", "FORMAT", &["SIGNED".into()])?;
    }
    Ok(false)
}
