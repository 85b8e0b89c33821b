//! The data section: frames of point samples followed by analog samples, decoded and encoded
//! through one codec chosen per file.

use crate::analog::Analog;
use crate::error::{Error, Result};
use crate::points::{
    decode_float_word, decode_word, encode_fourth, float_word, model_sample, Points,
};
use crate::processor::{Codec, CodecFn};
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

/// Files above this many data bytes are decoded in parallel chunks of frames.
const PARALLEL_BYTES: usize = 1 << 20;

/// Data bytes per chunk when the data section is decoded in pieces: small enough that each
/// thread's chunk stays in cache, large enough that scheduling costs nothing.
const CHUNK_BYTES: usize = PARALLEL_BYTES / 4;

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

/// Decoded point samples of a run of whole frames: a chunk of a trial's point data (see
/// [`C3d::map_point_chunks`](crate::C3d::map_point_chunks)), laid out like [`Points`].
#[derive(Debug, Clone, Copy)]
pub struct PointsView<'a> {
    /// Index (0-based) of the chunk's first frame in the trial.
    pub first_frame: usize,
    /// Frames in the chunk.
    pub frames: usize,
    /// Points per frame.
    pub count: usize,
    pub xyz: &'a [[f32; 3]],
    pub residual: &'a [f32],
    pub camera_mask: &'a [u8],
}

impl PointsView<'_> {
    /// Whether sample `(frame, point)` of the chunk (`frame` counted from the chunk's first)
    /// is valid, by [`is_missing`](crate::is_missing).
    #[inline]
    pub fn is_valid(&self, frame: usize, point: usize) -> bool {
        let k = frame * self.count + point;
        !crate::points::is_missing(self.xyz[k], self.residual[k])
    }
}

/// Decode the point data chunk by chunk into per-thread buffers and give each decoded chunk
/// (with what its decoding noticed) to `f`, in parallel; the results come back in frame
/// order. Memory stays at one chunk per thread however long the trial is.
pub(crate) struct MapChunks<'a, S, F> {
    pub bytes: &'a [u8],
    pub layout: Layout,
    pub states: Vec<S>,
    pub f: F,
}

impl<S, R, F> CodecFn<Vec<R>> for MapChunks<'_, S, F>
where
    S: Send,
    R: Send,
    F: Fn(S, PointsView<'_>, DecodeNotes) -> R + Sync,
{
    fn call<C: Codec>(self) -> Vec<R> {
        use rayon::prelude::*;
        let l = self.layout;
        let fb = l.frame_bytes();
        let chunk = chunk_frames(&l);
        let f = &self.f;
        if fb == 0 || l.frames == 0 {
            return Vec::new();
        }
        let data = &self.bytes[..l.frames * fb];
        let buffers = || {
            let n = chunk * l.points;
            (vec![[0f32; 3]; n], vec![0f32; n], vec![0u8; n])
        };
        data.par_chunks(chunk * fb)
            .zip(self.states)
            .enumerate()
            .map_init(buffers, |(x, r, m), (i, (b, state))| {
                let frames = b.len() / fb;
                let n = frames * l.points;
                let mut notes = decode_points::<C>(l, b, &mut x[..n], &mut r[..n], &mut m[..n]);
                notes.first_odd = notes.first_odd.map(|s| s + i * chunk * l.points);
                let view = PointsView {
                    first_frame: i * chunk,
                    frames,
                    count: l.points,
                    xyz: &x[..n],
                    residual: &r[..n],
                    camera_mask: &m[..n],
                };
                f(state, view, notes)
            })
            .collect()
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
) -> DecodeNotes {
    let mut notes = DecodeNotes::default();
    let fb = l.frame_bytes();
    let s = l.point_scale;
    let pb = 4 * l.word_bytes() * l.points;
    for (f, frame) in bytes.chunks_exact(fb).enumerate() {
        let pbytes = &frame[..pb];
        let base = f * l.points;
        let out = base..base + l.points;
        let (xo, ro, mo) = (
            &mut xyz[out.clone()],
            &mut residual[out.clone()],
            &mut camera_mask[out],
        );
        if l.float {
            for (i, c) in pbytes.chunks_exact(16).enumerate() {
                let v = |k: usize| C::read_f32([c[k], c[k + 1], c[k + 2], c[k + 3]]);
                let p = [v(0), v(4), v(8)];
                let w = v(12);
                if float_word(w).is_none() {
                    notes.odd_fourth_words += 1;
                    notes.first_odd.get_or_insert(base + i);
                }
                xo[i] = p;
                (ro[i], mo[i]) = model_sample(p, decode_float_word(w, s));
            }
        } else {
            for (i, c) in pbytes.chunks_exact(8).enumerate() {
                let v = |k: usize| C::read_i16([c[k], c[k + 1]]);
                // Integer coordinates are always finite: the word alone decides.
                xo[i] = [v(0) as f32 * s, v(2) as f32 * s, v(4) as f32 * s];
                (ro[i], mo[i]) = decode_word(v(6), s);
            }
        }
    }
    notes
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
                    encode_point::<C>(c, &l, sample, force, (f, i))?;
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
                                "analog frame {f}, word {j} = {v} does not fit in an unsigned 16-bit integer"
                            )));
                        }
                        c.copy_from_slice(&C::write_i16(q as u16 as i16));
                    } else {
                        if !force && same(C::read_i16([c[0], c[1]]) as f32, v) {
                            continue;
                        }
                        let q = int16(v, || format!("analog frame {f}, word {j}"))?;
                        c.copy_from_slice(&C::write_i16(q));
                    }
                }
            }
        }
        Ok(())
    }
}
