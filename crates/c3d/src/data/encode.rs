//! The model → stored samples: a whole data section, or samples patched into one in place.
//! Samples whose stored bytes already decode to the model's values keep their bytes.

use super::Layout;
use crate::analog::Analog;
use crate::error::{Error, Result};
use crate::points::{decode_float_word, decode_word, encode_fourth, model_sample, Points};
use crate::processor::{Codec, CodecFn};

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
