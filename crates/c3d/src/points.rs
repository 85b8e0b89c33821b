//! 3D point data as plain arrays: what repair and viewers want, not objects per sample.

use serde::Serialize;

/// Point samples of a trial, frame-major: sample `(frame, point)` is at `frame * count + point`.
///
/// Whether a sample is missing is decided in one place, [`is_missing`], for every command and
/// library entry point. A residual of 0 marks a point that was computed rather than measured
/// (interpolated, filtered).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Points {
    pub(crate) frames: usize,
    pub(crate) count: usize,
    /// Coordinates in POINT:UNITS.
    pub xyz: Vec<[f32; 3]>,
    /// Residual in POINT:UNITS (low byte × |POINT:SCALE|); −1 for a missing sample.
    pub residual: Vec<f32>,
    /// Camera mask (7 bits): bit n set when camera n+1 saw the point.
    pub camera_mask: Vec<u8>,
}

/// A sample a program writes rather than a camera system measured, as the C3D manual marks
/// it: a computed one (filled, filtered, set by hand) keeps its coordinates with residual 0
/// and no cameras; a missing one is at the origin with residual −1 and no cameras. The one
/// statement of that rule, for the repair's write-back and the Python package's setter.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Mark {
    Computed([f32; 3]),
    Missing,
}

impl Mark {
    /// The sample as stored: coordinates, residual, camera mask.
    pub fn stored(self) -> ([f32; 3], f32, u8) {
        match self {
            Mark::Computed(xyz) => (xyz, 0.0, 0),
            Mark::Missing => ([0.0; 3], -1.0, 0),
        }
    }
}

impl Points {
    /// Set sample `k` (see [`Points::index`]) as `mark` says.
    pub fn mark(&mut self, k: usize, mark: Mark) {
        let (xyz, residual, cameras) = mark.stored();
        self.xyz[k] = xyz;
        self.residual[k] = residual;
        self.camera_mask[k] = cameras;
    }

    /// `frames` × `count` samples, all invalid at the origin.
    pub fn new(frames: usize, count: usize) -> Points {
        let n = frames * count;
        Points {
            frames,
            count,
            xyz: vec![[0.0; 3]; n],
            residual: vec![-1.0; n],
            camera_mask: vec![0; n],
        }
    }

    pub fn frames(&self) -> usize {
        self.frames
    }

    /// Number of points per frame.
    pub fn count(&self) -> usize {
        self.count
    }

    #[inline]
    pub fn index(&self, frame: usize, point: usize) -> usize {
        frame * self.count + point
    }

    /// Whether sample `(frame, point)` holds a measured or computed position: see
    /// [`is_missing`].
    #[inline]
    pub fn is_valid(&self, frame: usize, point: usize) -> bool {
        let k = self.index(frame, point);
        !is_missing(self.xyz[k], self.residual[k])
    }

    /// Whether the sample at flat index `k` (see [`Points::index`]) is valid.
    #[inline]
    pub fn is_valid_at(&self, k: usize) -> bool {
        !is_missing(self.xyz[k], self.residual[k])
    }

    /// Number of valid samples of one point.
    pub fn valid_count(&self, point: usize) -> usize {
        (0..self.frames)
            .filter(|&f| self.is_valid(f, point))
            .count()
    }

    /// The validity of one point over all frames.
    pub fn validity(&self, point: usize) -> Vec<bool> {
        (0..self.frames).map(|f| self.is_valid(f, point)).collect()
    }

    /// One point's coordinates over all frames.
    pub fn trajectory(&self, point: usize) -> Vec<[f32; 3]> {
        (0..self.frames)
            .map(|f| self.xyz[self.index(f, point)])
            .collect()
    }

    /// One point's residuals over all frames.
    pub fn residuals(&self, point: usize) -> Vec<f32> {
        (0..self.frames)
            .map(|f| self.residual[self.index(f, point)])
            .collect()
    }

    /// Runs of invalid frames of one point, as `(first, last)` frame indices (0-based).
    pub fn gaps(&self, point: usize) -> Vec<(usize, usize)> {
        let mut out = Vec::new();
        let mut start = None;
        for f in 0..self.frames {
            match (self.is_valid(f, point), start) {
                (false, None) => start = Some(f),
                (true, Some(s)) => {
                    out.push((s, f - 1));
                    start = None;
                }
                _ => {}
            }
        }
        if let Some(s) = start {
            out.push((s, self.frames - 1));
        }
        out
    }
}

/// The one definition of a missing point sample, from the C3D manual: the fourth word of a
/// stored point, taken as a 16-bit signed integer, is negative when the point was not seen.
/// In float files the word is stored as a float, and −1.0 and 65535.0 are both the word
/// 0xFFFF. Readers put −1 in the model's residual for such samples; a sample whose
/// coordinates are not finite is missing too, however its fourth word reads, since no reader
/// can place it.
#[inline(always)]
pub fn is_missing(xyz: [f32; 3], residual: f32) -> bool {
    // Written so that a NaN residual is missing too.
    let measured = residual >= 0.0;
    !(measured && xyz[0].is_finite() && xyz[1].is_finite() && xyz[2].is_finite())
}

/// A stored point's fourth word, decoded as the C3D manual says: negative = missing; else
/// bits 8–14 are the camera mask (7 cameras; bit 15 is the sign) and the low byte the
/// residual in units of |scale|.
#[inline(always)]
pub(crate) fn decode_word(word: i16, abs_scale: f32) -> (f32, u8) {
    if word < 0 {
        (-1.0, 0)
    } else {
        ((word & 0xff) as f32 * abs_scale, ((word >> 8) & 0x7f) as u8)
    }
}

/// The fourth word of a float file as the 16-bit word it stands for, when it is one.
///
/// The manual stores the same 16-bit word as in integer files, converted to a float. Writers
/// differ in how they convert it: most write the signed value (−1.0 for a missing point),
/// some the unsigned one (65535.0, the word 0xFFFF, as Vicon and Qualisys exports do). Both
/// are the same word, so an integral value in −32768…65535 is taken modulo 2¹⁶ and read as a
/// signed 16-bit integer. Anything else (fractions, huge or non-finite values) is not a
/// 16-bit word at all.
#[inline(always)]
pub(crate) fn float_word(w: f32) -> Option<i16> {
    if (-32768.0..=65535.0).contains(&w) {
        // In this range the conversion truncates exactly; the value is integral when it
        // survives the round trip (cheaper than `fract`, a library call on baseline x86-64).
        let i = w as i32;
        if i as f32 == w {
            return Some(i as u16 as i16);
        }
    }
    None
}

/// A float file's fourth word decoded: through [`float_word`] when it is a 16-bit word.
/// Otherwise (some writers store other values there, e.g. the bit pattern 0x7F007F00 in
/// `marche281.c3d`) the sign still decides — negative or non-finite is missing — and the
/// residual and mask come from the value's integral part saturated to 32 bits, so that such a
/// sample stays valid with the reading it always had; the reader warns once per file.
#[inline(always)]
pub(crate) fn decode_float_word(w: f32, abs_scale: f32) -> (f32, u8) {
    match float_word(w) {
        Some(word) => decode_word(word, abs_scale),
        None if w.is_nan() || w < 0.0 || w.is_infinite() => (-1.0, 0),
        None => {
            let i = w as i32;
            ((i & 0xff) as f32 * abs_scale, ((i >> 8) & 0x7f) as u8)
        }
    }
}

/// A sample as the model holds it: residual −1 and mask 0 when it is missing by
/// [`is_missing`], else what its fourth word says.
#[inline(always)]
pub(crate) fn model_sample(xyz: [f32; 3], fourth: (f32, u8)) -> (f32, u8) {
    if is_missing(xyz, fourth.0) {
        (-1.0, 0)
    } else {
        fourth
    }
}

/// The fourth word for a sample of the model, the inverse of [`decode_word`]: −1 for a
/// missing sample (by [`is_missing`], so non-finite coordinates are written as missing too).
#[inline(always)]
pub(crate) fn encode_fourth(xyz: [f32; 3], residual: f32, mask: u8, abs_scale: f32) -> i16 {
    if is_missing(xyz, residual) {
        -1
    } else {
        let r = if abs_scale > 0.0 {
            (residual / abs_scale).round().clamp(0.0, 255.0) as i16
        } else {
            0
        };
        (((mask & 0x7f) as i16) << 8) | r
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fourth_word_as_the_manual_says() {
        // Cameras 1 and 3 (mask 0b101), residual 7 × 0.5 = 3.5.
        assert_eq!(decode_word(0x0507, 0.5), (3.5, 0b101));
        assert_eq!(decode_word(-1, 0.5), (-1.0, 0));
        let p = [1.0, 2.0, 3.0];
        assert_eq!(encode_fourth(p, 3.5, 0b101, 0.5), 0x0507);
        assert_eq!(encode_fourth(p, -1.0, 3, 0.5), -1);
        assert_eq!(encode_fourth(p, 0.0, 0, 0.5), 0);
        // The mask has 7 bits: bit 15 is the sign.
        assert_eq!(encode_fourth(p, 0.0, 0xff, 0.5), 0x7f00);
        assert_eq!(decode_word(0x7f00, 0.5), (0.0, 0x7f));
    }

    #[test]
    fn float_fourth_words_are_16_bit_words() {
        // Signed and unsigned spellings of the word 0xFFFF are both missing.
        assert_eq!(decode_float_word(-1.0, 0.1), (-1.0, 0));
        assert_eq!(decode_float_word(65535.0, 0.1), (-1.0, 0));
        // 0x8000..0xFFFF have the sign bit set.
        assert_eq!(decode_float_word(32768.0, 0.1), (-1.0, 0));
        assert_eq!(decode_float_word(-32768.0, 0.1), (-1.0, 0));
        assert_eq!(decode_float_word(0x0507 as f32, 0.5), (3.5, 0b101));
        assert_eq!(decode_float_word(0.0, 0.5), (0.0, 0));
        // Not 16-bit words: negative or non-finite is missing, other values valid.
        assert_eq!(decode_float_word(-0.5, 0.5), (-1.0, 0));
        assert_eq!(decode_float_word(f32::NAN, 0.5), (-1.0, 0));
        assert_eq!(decode_float_word(f32::INFINITY, 0.5), (-1.0, 0));
        assert!(decode_float_word(1.708e38, 1.0).0 >= 0.0);
        assert!(decode_float_word(12.5, 1.0).0 >= 0.0);
        assert_eq!(float_word(65535.0), Some(-1));
        assert_eq!(float_word(12.5), None);
        assert_eq!(float_word(65536.0), None);
    }

    #[test]
    fn non_finite_coordinates_are_missing() {
        assert!(is_missing([f32::NAN, 0.0, 0.0], 1.0));
        assert!(is_missing([0.0, f32::INFINITY, 0.0], 0.0));
        assert!(is_missing([0.0, 0.0, 0.0], -1.0));
        assert!(is_missing([0.0, 0.0, 0.0], f32::NAN));
        assert!(!is_missing([0.0, 0.0, 0.0], 0.0));
        assert_eq!(model_sample([f32::NAN, 0.0, 0.0], (2.0, 3)), (-1.0, 0));
        assert_eq!(encode_fourth([f32::NAN, 0.0, 0.0], 2.0, 3, 1.0), -1);
        let mut p = Points::new(1, 1);
        p.residual[0] = 1.0;
        assert!(p.is_valid(0, 0));
        p.xyz[0][1] = f32::NAN;
        assert!(!p.is_valid(0, 0));
    }

    #[test]
    fn gaps_are_runs_of_invalid_frames() {
        let mut p = Points::new(6, 1);
        for f in [0, 3, 4] {
            p.residual[f] = 1.0;
        }
        assert_eq!(p.gaps(0), vec![(1, 2), (5, 5)]);
        assert_eq!(p.validity(0), vec![true, false, false, true, true, false]);
    }

    #[test]
    fn marked_samples_read_as_computed_or_missing() {
        let mut p = Points::new(2, 1);
        p.camera_mask[0] = 0b101;
        p.mark(0, Mark::Computed([1.0, 2.0, 3.0]));
        assert!(p.is_valid(0, 0));
        assert_eq!(
            (p.xyz[0], p.residual[0], p.camera_mask[0]),
            ([1.0, 2.0, 3.0], 0.0, 0)
        );
        p.mark(0, Mark::Missing);
        assert!(!p.is_valid(0, 0));
        assert_eq!(
            (p.xyz[0], p.residual[0], p.camera_mask[0]),
            ([0.0; 3], -1.0, 0)
        );
    }
}
