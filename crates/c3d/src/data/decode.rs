//! Stored samples → the model's arrays: points and analog, one codec per file, in parallel
//! chunks of frames for long trials.

use super::Layout;
use crate::analog::Analog;
use crate::points::{decode_float_word, decode_word, model_sample, Points};
use crate::processor::{Codec, CodecFn};

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
            let bytes = &self.bytes[..l.frames * fb];
            if chunk >= l.frames {
                decode_points::<C>(l, bytes, &mut xyz, &mut residual, &mut camera_mask);
            } else {
                forkpool::install(|| {
                    xyz.par_chunks_mut(per)
                        .zip(residual.par_chunks_mut(per))
                        .zip(camera_mask.par_chunks_mut(per))
                        .zip(bytes.par_chunks(chunk * fb))
                        .for_each(|(((x, r), m), b)| {
                            decode_points::<C>(l, b, x, r, m);
                        });
                });
            }
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

/// One stored point sample (`c`: 16 bytes of float data or 8 of integers) as the model holds
/// it: coordinates, residual (−1 when missing by [`is_missing`]) and camera mask. Every
/// reading of samples goes through here, so they all agree on which are missing.
#[inline(always)]
pub(super) fn decode_sample<C: Codec>(c: &[u8], l: &Layout) -> ([f32; 3], f32, u8) {
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
