//! The data section: frames of point samples followed by analog samples, decoded and encoded
//! through one codec chosen per file.

use crate::analog::Analog;
use crate::error::{Error, Result};
use crate::points::{
    decode_float_word, decode_word, encode_fourth, float_word, is_missing, model_sample, Points,
};
use crate::processor::{Codec, CodecFn, Dec, Intel, Processor, Sgi};
use serde::Serialize;

/// How the data section is laid out.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Layout {
    /// Points per frame.
    pub points: usize,
    /// Analog channels.
    pub analog_channels: usize,
    /// Analog samples per channel per 3D frame.
    pub analog_samples_per_frame: usize,
    pub frames: usize,
    /// Floating-point (true) or scaled int16 (false) samples.
    pub float: bool,
    /// Analog integers are unsigned (ANALOG:FORMAT = UNSIGNED).
    pub unsigned_analog: bool,
    /// |POINT:SCALE|: integer coordinates are multiplied by it; residuals always are.
    pub point_scale: f32,
}

impl Layout {
    pub fn word_bytes(&self) -> usize {
        if self.float {
            4
        } else {
            2
        }
    }

    // Counts come from the file: products saturate, so an absurd layout compares as larger
    // than any file instead of wrapping around.

    pub fn analog_words(&self) -> usize {
        self.analog_channels
            .saturating_mul(self.analog_samples_per_frame)
    }

    /// Bytes of one 3D frame with its analog samples.
    pub fn frame_bytes(&self) -> usize {
        (4 * self.points)
            .saturating_add(self.analog_words())
            .saturating_mul(self.word_bytes())
    }

    /// Bytes of the whole data section.
    pub fn data_bytes(&self) -> usize {
        self.frames.saturating_mul(self.frame_bytes())
    }
}

/// Data sections above this many bytes are decoded into arrays in parallel chunks of frames.
const PARALLEL_BYTES: usize = 1 << 20;

/// Data sections above this many bytes are scanned in parallel (the reader's notes,
/// [`C3d::map_point_chunks`](crate::C3d::map_point_chunks)). A scan is lighter than
/// decoding, and the commands that only scan are short processes for which starting the
/// thread pool is part of the bill: below this, one thread scans a typical 2 MB trial in
/// less time than starting the others takes (about 0.3 ms against 0.3–0.5 ms).
pub(crate) const PARALLEL_SCAN_BYTES: usize = 4 << 20;

/// Data bytes per chunk when the data section is decoded in pieces: small enough that each
/// thread's chunk stays in cache, large enough that scheduling costs nothing.
const CHUNK_BYTES: usize = 256 << 10;

/// Frames per chunk for a layout (at least one).
pub(crate) fn chunk_frames(l: &Layout) -> usize {
    CHUNK_BYTES.checked_div(l.frame_bytes()).unwrap_or(1).max(1)
}

/// What decoding found besides the samples.
#[derive(Debug, Default, Clone, Copy)]
pub(crate) struct DecodeNotes {
    /// Float fourth words that are not 16-bit words (see [`float_word`]).
    pub odd_fourth_words: usize,
    /// The first of them, as a sample index (frame × points + point).
    pub first_odd: Option<usize>,
}

impl DecodeNotes {
    pub(crate) fn merge(self, other: DecodeNotes) -> DecodeNotes {
        DecodeNotes {
            odd_fourth_words: self.odd_fourth_words + other.odd_fourth_words,
            first_odd: match (self.first_odd, other.first_odd) {
                (Some(a), Some(b)) => Some(a.min(b)),
                (a, b) => a.or(b),
            },
        }
    }
}

/// Decode the point samples of all frames from `bytes` (exactly `layout.data_bytes()` long).
pub(crate) struct DecodePoints<'a> {
    pub bytes: &'a [u8],
    pub layout: Layout,
}

impl CodecFn<Points> for DecodePoints<'_> {
    fn call<C: Codec>(self) -> Points {
        use rayon::prelude::*;
        let l = self.layout;
        let fb = l.frame_bytes();
        let n = l.frames * l.points;
        // Zero-filled allocations come straight from the OS (calloc): their pages are touched
        // first by the decoding threads, not by a fill.
        let mut xyz: Vec<[f32; 3]> = crate::memory::zeroed(n);
        let mut residual: Vec<f32> = crate::memory::zeroed(n);
        let mut camera_mask: Vec<u8> = crate::memory::zeroed(n);
        if fb > 0 && n > 0 {
            let chunk = if l.data_bytes() > PARALLEL_BYTES {
                chunk_frames(&l)
            } else {
                l.frames.max(1)
            };
            let per = chunk * l.points;
            xyz.par_chunks_mut(per)
                .zip(residual.par_chunks_mut(per))
                .zip(camera_mask.par_chunks_mut(per))
                .zip(self.bytes[..l.frames * fb].par_chunks(chunk * fb))
                .for_each(|(((x, r), m), b)| {
                    decode_points::<C>(l, b, x, r, m);
                });
        }
        Points {
            frames: l.frames,
            count: l.points,
            xyz,
            residual,
            camera_mask,
        }
    }
}

/// Decode the analog samples of all frames from `bytes` (exactly `layout.data_bytes()` long).
pub(crate) struct DecodeAnalog<'a> {
    pub bytes: &'a [u8],
    pub layout: Layout,
}

impl CodecFn<Analog> for DecodeAnalog<'_> {
    fn call<C: Codec>(self) -> Analog {
        let l = self.layout;
        let fb = l.frame_bytes();
        let aw = l.analog_words();
        let mut raw: Vec<f32> = crate::memory::zeroed(l.frames * aw);
        if fb > 0 && aw > 0 {
            let pb = 4 * l.word_bytes() * l.points;
            for (frame, out) in self.bytes[..l.frames * fb]
                .chunks_exact(fb)
                .zip(raw.chunks_exact_mut(aw))
            {
                decode_analog::<C>(l, &frame[pb..], out);
            }
        }
        Analog {
            channels: l.analog_channels,
            samples_per_frame: l.analog_samples_per_frame,
            frames: l.frames,
            raw,
        }
    }
}

/// The point samples of a run of whole frames: a chunk of a trial's point data (see
/// [`C3d::map_point_chunks`](crate::C3d::map_point_chunks)). Samples are decoded as they are
/// asked for, straight from the stored bytes when the trial's arrays have not been decoded,
/// with the same decoding as [`C3d::points`](crate::C3d::points).
#[derive(Debug, Clone, Copy)]
pub struct PointsView<'a> {
    /// Index (0-based) of the chunk's first frame in the trial.
    pub first_frame: usize,
    /// Frames in the chunk.
    pub frames: usize,
    /// Points per frame.
    pub count: usize,
    data: ViewData<'a>,
}

#[derive(Debug, Clone, Copy)]
enum ViewData<'a> {
    /// Slices of decoded arrays.
    Decoded {
        xyz: &'a [[f32; 3]],
        residual: &'a [f32],
        camera_mask: &'a [u8],
    },
    /// Whole frames of the stored data section.
    Stored {
        bytes: &'a [u8],
        layout: Layout,
        processor: Processor,
    },
}

impl<'a> PointsView<'a> {
    /// Frames `first_frame..` of decoded points: samples `range` of the arrays.
    pub(crate) fn decoded(
        first_frame: usize,
        p: &'a Points,
        range: std::ops::Range<usize>,
    ) -> Self {
        PointsView {
            first_frame,
            frames: range.len() / p.count.max(1),
            count: p.count,
            data: ViewData::Decoded {
                xyz: &p.xyz[range.clone()],
                residual: &p.residual[range.clone()],
                camera_mask: &p.camera_mask[range],
            },
        }
    }

    /// Frames `first_frame..` as stored: `bytes` holds whole frames of the data section.
    pub(crate) fn stored(
        first_frame: usize,
        bytes: &'a [u8],
        layout: Layout,
        processor: Processor,
    ) -> Self {
        PointsView {
            first_frame,
            frames: bytes.len() / layout.frame_bytes().max(1),
            count: layout.points,
            data: ViewData::Stored {
                bytes,
                layout,
                processor,
            },
        }
    }

    /// Sample `(frame, point)` of the chunk (`frame` counted from the chunk's first):
    /// coordinates, residual (−1 when missing) and camera mask, as in [`Points`].
    #[inline]
    pub fn sample(&self, frame: usize, point: usize) -> ([f32; 3], f32, u8) {
        match self.data {
            ViewData::Decoded {
                xyz,
                residual,
                camera_mask,
            } => {
                let k = frame * self.count + point;
                (xyz[k], residual[k], camera_mask[k])
            }
            ViewData::Stored {
                bytes,
                layout,
                processor,
            } => {
                let sb = 4 * layout.word_bytes();
                let at = frame * layout.frame_bytes() + point * sb;
                let c = &bytes[at..at + sb];
                match processor {
                    Processor::Intel => decode_sample::<Intel>(c, &layout),
                    Processor::Dec => decode_sample::<Dec>(c, &layout),
                    Processor::Sgi => decode_sample::<Sgi>(c, &layout),
                }
            }
        }
    }

    /// Whether sample `(frame, point)` of the chunk is valid, by
    /// [`is_missing`](crate::is_missing).
    #[inline]
    pub fn is_valid(&self, frame: usize, point: usize) -> bool {
        let (p, r, _) = self.sample(frame, point);
        !is_missing(p, r)
    }
}

/// One stored point sample (`c`: 16 bytes of float data or 8 of integers) as the model holds
/// it: coordinates, residual (−1 when missing by [`is_missing`]) and camera mask. Every
/// reading of samples goes through here, so they all agree on which are missing.
#[inline(always)]
fn decode_sample<C: Codec>(c: &[u8], l: &Layout) -> ([f32; 3], f32, u8) {
    let s = l.point_scale;
    if l.float {
        let v = |k: usize| C::read_f32([c[k], c[k + 1], c[k + 2], c[k + 3]]);
        let p = [v(0), v(4), v(8)];
        let (r, m) = model_sample(p, decode_float_word(v(12), s));
        (p, r, m)
    } else {
        let v = |k: usize| C::read_i16([c[k], c[k + 1]]);
        // Integer coordinates are always finite: the word alone decides.
        let (r, m) = decode_word(v(6), s);
        ([v(0) as f32 * s, v(2) as f32 * s, v(4) as f32 * s], r, m)
    }
}

/// Decode the point samples of whole frames from `bytes` into the output slices of the same
/// frames (analog words are skipped).
fn decode_points<C: Codec>(
    l: Layout,
    bytes: &[u8],
    xyz: &mut [[f32; 3]],
    residual: &mut [f32],
    camera_mask: &mut [u8],
) {
    let fb = l.frame_bytes();
    let sb = 4 * l.word_bytes();
    let pb = sb * l.points;
    for (f, frame) in bytes.chunks_exact(fb).enumerate() {
        let base = f * l.points;
        let out = base..base + l.points;
        let (xo, ro, mo) = (
            &mut xyz[out.clone()],
            &mut residual[out.clone()],
            &mut camera_mask[out],
        );
        for (i, c) in frame[..pb].chunks_exact(sb).enumerate() {
            (xo[i], ro[i], mo[i]) = decode_sample::<C>(c, &l);
        }
    }
}

/// What the reader notes about a file's samples without decoding them into memory.
#[derive(Debug, Default, Clone, Copy)]
pub(crate) struct ScanNotes {
    pub notes: DecodeNotes,
    /// Some sample is valid.
    pub any_valid: bool,
    /// Some missing sample stores coordinates other than (0, 0, 0) (looked for only until a
    /// valid sample turns up).
    pub any_stored: bool,
}

/// One pass over the stored samples for [`ScanNotes`]: float fourth words that are not
/// 16-bit words (every sample), and whether any sample is valid (until one is).
pub(crate) struct Scan<'a> {
    pub bytes: &'a [u8],
    pub layout: Layout,
}

impl CodecFn<ScanNotes> for Scan<'_> {
    fn call<C: Codec>(self) -> ScanNotes {
        use rayon::prelude::*;
        let l = self.layout;
        let fb = l.frame_bytes();
        let sb = 4 * l.word_bytes();
        let pb = sb * l.points;
        if fb == 0 || l.points == 0 {
            return ScanNotes::default();
        }
        let chunk = chunk_frames(&l);
        let scan = |(i, b): (usize, &[u8])| {
            let mut n = ScanNotes::default();
            for (f, frame) in b.chunks_exact(fb).enumerate() {
                for (j, c) in frame[..pb].chunks_exact(sb).enumerate() {
                    if l.float {
                        let w = C::read_f32([c[12], c[13], c[14], c[15]]);
                        if float_word(w).is_none() {
                            n.notes.odd_fourth_words += 1;
                            n.notes
                                .first_odd
                                .get_or_insert((i * chunk + f) * l.points + j);
                        }
                    } else if n.any_valid {
                        // Integer files have nothing more to note.
                        return n;
                    }
                    if !n.any_valid {
                        let (p, r, _) = decode_sample::<C>(c, &l);
                        n.any_valid = !is_missing(p, r);
                        n.any_stored |= p != [0.0; 3];
                    }
                }
            }
            n
        };
        let merge = |a: ScanNotes, b: ScanNotes| ScanNotes {
            notes: a.notes.merge(b.notes),
            any_valid: a.any_valid || b.any_valid,
            any_stored: a.any_stored || b.any_stored,
        };
        let data = &self.bytes[..l.frames * fb];
        if data.len() > PARALLEL_SCAN_BYTES {
            data.par_chunks(chunk * fb)
                .enumerate()
                .map(scan)
                .reduce(ScanNotes::default, merge)
        } else {
            data.chunks(chunk * fb)
                .enumerate()
                .map(scan)
                .fold(ScanNotes::default(), merge)
        }
    }
}

/// Decode one frame's analog words (`abytes`, after its points) into `out`.
fn decode_analog<C: Codec>(l: Layout, abytes: &[u8], out: &mut [f32]) {
    if l.float {
        for (o, c) in out.iter_mut().zip(abytes.chunks_exact(4)) {
            *o = C::read_f32([c[0], c[1], c[2], c[3]]);
        }
    } else if l.unsigned_analog {
        for (o, c) in out.iter_mut().zip(abytes.chunks_exact(2)) {
            *o = C::read_i16([c[0], c[1]]) as u16 as f32;
        }
    } else {
        for (o, c) in out.iter_mut().zip(abytes.chunks_exact(2)) {
            *o = C::read_i16([c[0], c[1]]) as f32;
        }
    }
}

/// Encode samples into `out` (exactly `layout.data_bytes()` long). Unless `force`, a sample
/// whose stored bytes already decode to the model's value is left alone, so a rewrite changes
/// only the words of samples that changed.
pub(crate) struct Encode<'a> {
    pub out: &'a mut [u8],
    pub layout: Layout,
    pub points: Option<&'a Points>,
    pub analog: Option<&'a Analog>,
    pub force: bool,
    /// The trial's frame at which `out` starts (when it holds a chunk), for messages.
    pub first_frame: usize,
}

fn same(a: f32, b: f32) -> bool {
    a.to_bits() == b.to_bits()
}

fn int16(v: f32, what: impl Fn() -> String) -> Result<i16> {
    let q = v.round();
    if q.is_nan() || !(-32768.0..=32767.0).contains(&q) {
        return Err(Error::Unrepresentable(format!(
            "{} = {v} does not fit in a 16-bit integer",
            what()
        )));
    }
    Ok(q as i16)
}

/// Encode one point sample (coordinates, residual, camera mask) into its stored bytes `c`
/// (16 bytes for float data, 8 for integers). Unless `force`, a sample whose stored bytes
/// already decode (by the reader's own rule) to the same values keeps its bytes, however its
/// writer spelled it. `at` is (frame, point), for errors.
#[inline]
pub(crate) fn encode_point<C: Codec>(
    c: &mut [u8],
    l: &Layout,
    sample: ([f32; 3], f32, u8),
    force: bool,
    at: (usize, usize),
) -> Result<()> {
    let ([x, y, z], r, m) = sample;
    let s = l.point_scale;
    if l.float {
        let rd = |k: usize| C::read_f32([c[k], c[k + 1], c[k + 2], c[k + 3]]);
        let p0 = [rd(0), rd(4), rd(8)];
        let (r0, m0) = model_sample(p0, decode_float_word(rd(12), s));
        if !force && same(p0[0], x) && same(p0[1], y) && same(p0[2], z) && same(r0, r) && m0 == m {
            return Ok(());
        }
        c[0..4].copy_from_slice(&C::write_f32(x));
        c[4..8].copy_from_slice(&C::write_f32(y));
        c[8..12].copy_from_slice(&C::write_f32(z));
        let fourth = encode_fourth([x, y, z], r, m, s) as f32;
        c[12..16].copy_from_slice(&C::write_f32(fourth));
    } else {
        let rd = |k: usize| C::read_i16([c[k], c[k + 1]]);
        let (r0, m0) = decode_word(rd(6), s);
        if !force
            && same(rd(0) as f32 * s, x)
            && same(rd(2) as f32 * s, y)
            && same(rd(4) as f32 * s, z)
            && same(r0, r)
            && m0 == m
        {
            return Ok(());
        }
        let valid = !crate::points::is_missing([x, y, z], r);
        let (f, i) = at;
        let q = |v: f32, axis: &str| -> Result<i16> {
            // An invalid sample's coordinates carry no meaning (the manual): ones an integer
            // cannot hold are stored as 0.
            if !valid && !(v / s).round().abs().le(&32767.0) {
                return Ok(0);
            }
            int16(v / s, || {
                format!("frame {f}, point {i}, {axis}/POINT:SCALE")
            })
        };
        c[0..2].copy_from_slice(&C::write_i16(q(x, "x")?));
        c[2..4].copy_from_slice(&C::write_i16(q(y, "y")?));
        c[4..6].copy_from_slice(&C::write_i16(q(z, "z")?));
        c[6..8].copy_from_slice(&C::write_i16(encode_fourth([x, y, z], r, m, s)));
    }
    Ok(())
}

/// Patch point samples into the data section `out` (exactly `layout.data_bytes()` long), in
/// place: each `(frame, point, xyz, residual, mask)` gets its bytes re-encoded (see
/// [`encode_point`]).
pub(crate) struct Patch<'a, I> {
    pub out: &'a mut [u8],
    pub layout: Layout,
    pub samples: I,
}

impl<I> CodecFn<Result<usize>> for Patch<'_, I>
where
    I: Iterator<Item = (usize, usize, [f32; 3], f32, u8)>,
{
    fn call<C: Codec>(self) -> Result<usize> {
        let l = self.layout;
        let fb = l.frame_bytes();
        let sb = 4 * l.word_bytes();
        let mut n = 0;
        for (f, i, xyz, r, m) in self.samples {
            if f >= l.frames || i >= l.points {
                return Err(Error::Misuse(format!(
                    "sample (frame {f}, point {i}) outside {} frames × {} points",
                    l.frames, l.points
                )));
            }
            let at = f * fb + i * sb;
            encode_point::<C>(&mut self.out[at..at + sb], &l, (xyz, r, m), false, (f, i))?;
            n += 1;
        }
        Ok(n)
    }
}

impl CodecFn<Result<()>> for Encode<'_> {
    fn call<C: Codec>(self) -> Result<()> {
        let Encode {
            out,
            layout: l,
            points,
            analog,
            force,
            first_frame,
        } = self;
        let fb = l.frame_bytes();
        if fb == 0 {
            return Ok(());
        }
        let aw = l.analog_words();
        let wb = l.word_bytes();
        for (f, frame) in out.chunks_exact_mut(fb).take(l.frames).enumerate() {
            let (pbytes, abytes) = frame.split_at_mut(4 * wb * l.points);
            if let Some(pts) = points {
                let base = f * l.points;
                for (i, c) in pbytes.chunks_exact_mut(4 * wb).enumerate() {
                    let k = base + i;
                    let sample = (pts.xyz[k], pts.residual[k], pts.camera_mask[k]);
                    encode_point::<C>(c, &l, sample, force, (first_frame + f, i))?;
                }
            }
            if let Some(ana) = analog {
                let src = &ana.raw[f * aw..(f + 1) * aw];
                for (j, (c, &v)) in abytes.chunks_exact_mut(wb).zip(src).enumerate() {
                    if l.float {
                        if !force && same(C::read_f32([c[0], c[1], c[2], c[3]]), v) {
                            continue;
                        }
                        c.copy_from_slice(&C::write_f32(v));
                    } else if l.unsigned_analog {
                        if !force && same(C::read_i16([c[0], c[1]]) as u16 as f32, v) {
                            continue;
                        }
                        let q = v.round();
                        if q.is_nan() || !(0.0..=65535.0).contains(&q) {
                            return Err(Error::Unrepresentable(format!(
                                "analog frame {}, word {j} = {v} does not fit in an unsigned 16-bit integer",
                                first_frame + f
                            )));
                        }
                        c.copy_from_slice(&C::write_i16(q as u16 as i16));
                    } else {
                        if !force && same(C::read_i16([c[0], c[1]]) as f32, v) {
                            continue;
                        }
                        let q = int16(v, || format!("analog frame {}, word {j}", first_frame + f))?;
                        c.copy_from_slice(&C::write_i16(q));
                    }
                }
            }
        }
        Ok(())
    }
}
