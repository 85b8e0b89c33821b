//! Writing: [`C3d`] → bytes.
//!
//! Two paths. A file that was read is *patched*: its original bytes are copied and only what
//! changed is re-encoded (parameter records, header words, data samples); a parameter section
//! that outgrows its blocks moves the data section. A new file, or a conversion to another
//! processor or number format, is written *fresh*: header derived from the parameters and data.

use crate::analog::Analog;
use crate::data::{Encode, Layout};
use crate::error::{Error, Result};
use crate::file::{C3d, NumberFormat, Source};
use crate::header::{Header, BLOCK, KEY_12345};
use crate::parameters::{Parameters, Value};
use crate::points::Points;
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
                check_integer_scale(self.point_stats(s.abs()).max_abs, s.abs())?;
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
                first_frame: 0,
            })?;
            if shared
                .iter()
                .any(|(r, before)| out[r.clone()] != before[..])
            {
                // Integer samples keep their scale, so the samples left alone keep their
                // values exactly (edited ones were kept within its range by the editor).
                let keep = Some(l.point_scale)
                    .filter(|s| !l.float && *s > 0.0 && s.is_finite() && fits(self, *s));
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
        let float = format == NumberFormat::Float;
        let old = self.layout();
        let abs_scale = match scale {
            Some(s) if s.is_finite() && s != 0.0 => s.abs(),
            Some(s) => return Err(Error::Misuse(format!("scale {s} must be finite and not 0"))),
            None if float => match old.point_scale {
                s if s > 0.0 && s.is_finite() => s,
                _ => 1.0,
            },
            None => integer_scale(self.point_stats(old.point_scale), old.point_scale),
        };
        let mut params = self.parameters.clone();
        let mut analog = self.analog().clone();
        let mut unsigned = old.unsigned_analog;
        if !float && old.float {
            unsigned = analog_to_integers(&mut analog, &mut params, unsigned)?;
        }
        let frames = self.frames();
        let layout = Layout {
            points: self.point_count(),
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
            // As stored, 0 included (some writers number from 0): a conversion moves no
            // frame number, or every event, report and export of the file would move by one.
            first_frame: self.header.first_frame,
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
        let data = &mut out[data_offset..];
        // Without points there is nothing to decode; the analog data still go in whole.
        let decoded = self
            .decoded_points()
            .or_else(|| (self.point_count() == 0).then(|| self.points()));
        match decoded {
            Some(pts) => processor.dispatch(Encode {
                out: data,
                layout,
                points: Some(pts),
                analog: Some(&analog),
                force: true,
                first_frame: 0,
            })?,
            None => self.encode_by_chunks(processor, layout, &analog, data)?,
        }
        out.resize(out.len().div_ceil(BLOCK) * BLOCK, 0);
        Ok(out)
    }

    /// Encode points that were never decoded, chunk by chunk from the stored bytes, into
    /// `data` (the new data section): a conversion of a long trial holds one chunk of
    /// decoded samples, not a decoded copy of the trial.
    fn encode_by_chunks(
        &self,
        processor: Processor,
        layout: Layout,
        analog: &Analog,
        data: &mut [u8],
    ) -> Result<()> {
        let per = self.point_chunk_frames();
        let fb = layout.frame_bytes();
        let aw = layout.analog_words();
        let states: Vec<&mut [u8]> = if fb == 0 {
            Vec::new()
        } else {
            data.chunks_mut(per * fb).collect()
        };
        let done = self.map_point_chunks(states, |out, v| {
            let mut pts = Points::new(v.frames, v.count);
            for f in 0..v.frames {
                for i in 0..v.count {
                    let k = pts.index(f, i);
                    (pts.xyz[k], pts.residual[k], pts.camera_mask[k]) = v.sample(f, i);
                }
            }
            let spf = analog.samples_per_frame().max(1);
            let first = v.first_frame;
            let raw = analog
                .raw
                .get(first * aw..(first + v.frames) * aw)
                .unwrap_or(&[])
                .to_vec();
            let part = Analog {
                channels: analog.channels(),
                samples_per_frame: spf,
                frames: v.frames,
                raw,
            };
            processor.dispatch(Encode {
                out,
                layout: Layout {
                    frames: v.frames,
                    ..layout
                },
                points: Some(&pts),
                analog: Some(&part),
                force: true,
                first_frame: first,
            })
        });
        done.into_iter().collect()
    }

    /// Largest |coordinate| of the valid samples, and whether every valid coordinate is an
    /// exact multiple of `scale` that fits in 16 bits, in one pass that decodes nothing
    /// into memory.
    fn point_stats(&self, scale: f32) -> PointStats {
        let exact_ok = scale > 0.0 && scale.is_finite();
        self.map_point_chunks(vec![(); self.point_chunks()], |(), v| {
            let mut st = PointStats {
                max_abs: 0.0,
                exact: exact_ok,
            };
            for f in 0..v.frames {
                for i in 0..v.count {
                    let (xyz, r, _) = v.sample(f, i);
                    if r < 0.0 {
                        continue;
                    }
                    for x in xyz {
                        st.max_abs = st.max_abs.max(x.abs());
                        if st.exact {
                            let q = (x / scale).round();
                            st.exact = q.abs() <= 32767.0 && (q * scale).to_bits() == x.to_bits();
                        }
                    }
                }
            }
            st
        })
        .into_iter()
        .fold(
            PointStats {
                max_abs: 0.0,
                exact: exact_ok,
            },
            |a, b| PointStats {
                max_abs: a.max_abs.max(b.max_abs),
                exact: a.exact && b.exact,
            },
        )
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
fn fits(c: &C3d, scale: f32) -> bool {
    (c.point_stats(scale).max_abs / scale).round() <= 32767.0
}

/// What the valid samples say about integer storage (see `C3d::point_stats`).
#[derive(Debug, Clone, Copy)]
struct PointStats {
    max_abs: f32,
    exact: bool,
}

/// A requested integer scale must hold the data: fine enough that the largest coordinate
/// is at least one step (else every coordinate is stored as 0 or ±1 and the trial is lost),
/// coarse enough that it fits in 16 bits. `max` is the largest valid |coordinate|.
fn check_integer_scale(max: f32, scale: f32) -> Result<()> {
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
/// at which every valid coordinate fits. `stats` are taken with `current`.
fn integer_scale(stats: PointStats, current: f32) -> f32 {
    if stats.exact {
        current
    } else if stats.max_abs > 0.0 {
        stats.max_abs / 32000.0
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
