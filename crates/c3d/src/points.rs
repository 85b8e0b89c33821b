//! 3D point data as plain arrays: what repair and viewers want, not objects per sample.

use serde::Serialize;

/// Point samples of a trial, frame-major: sample `(frame, point)` is at `frame * count + point`.
///
/// A sample is valid when its residual is not negative (the C3D manual's convention: a
/// negative fourth word marks a point that was not seen). A residual of 0 marks a point that
/// was computed rather than measured (interpolated, filtered).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Points {
    pub(crate) frames: usize,
    pub(crate) count: usize,
    /// Coordinates in POINT:UNITS.
    pub xyz: Vec<[f32; 3]>,
    /// Residual in POINT:UNITS (low byte × |POINT:SCALE|); negative = invalid.
    pub residual: Vec<f32>,
    /// Camera mask: bit n set when camera n+1 saw the point.
    pub camera_mask: Vec<u8>,
}

impl Points {
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

    #[inline]
    pub fn is_valid(&self, frame: usize, point: usize) -> bool {
        self.residual[self.index(frame, point)] >= 0.0
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

/// A stored point's fourth word, decoded as the C3D manual says: negative = invalid; else the
/// high byte is the camera mask and the low byte the residual in units of |scale|.
#[inline(always)]
pub(crate) fn decode_fourth(word: i32, abs_scale: f32) -> (f32, u8) {
    if word < 0 {
        (-1.0, 0)
    } else {
        ((word & 0xff) as f32 * abs_scale, ((word >> 8) & 0xff) as u8)
    }
}

/// The inverse of [`decode_fourth`].
#[inline(always)]
pub(crate) fn encode_fourth(residual: f32, mask: u8, abs_scale: f32, max_mask: u8) -> i32 {
    if residual < 0.0 || residual.is_nan() {
        -1
    } else {
        let r = if abs_scale > 0.0 {
            (residual / abs_scale).round().clamp(0.0, 255.0) as i32
        } else {
            0
        };
        (((mask & max_mask) as i32) << 8) | r
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fourth_word_as_the_manual_says() {
        // Cameras 1 and 3 (mask 0b101), residual 7 × 0.5 = 3.5.
        assert_eq!(decode_fourth(0x0507, 0.5), (3.5, 0b101));
        assert_eq!(decode_fourth(-1, 0.5), (-1.0, 0));
        assert_eq!(encode_fourth(3.5, 0b101, 0.5, 0x7f), 0x0507);
        assert_eq!(encode_fourth(-1.0, 3, 0.5, 0x7f), -1);
        assert_eq!(encode_fourth(0.0, 0, 0.5, 0x7f), 0);
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
}
