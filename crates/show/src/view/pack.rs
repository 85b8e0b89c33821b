//! Frame data packed for the viewer page: what a browser can turn into typed arrays in one
//! step. JSON per frame would be several times larger and slow to parse at 10 000 frames.

use c3d::Points;

/// Flag bit: the sample is valid (not missing by `c3d::is_missing`).
pub const VALID: u8 = 1;
/// Flag bit: the sample was computed, not measured (residual exactly 0 in a file that marks
/// fills, see [`super::fills_marked`]).
pub const FILLED: u8 = 2;

/// Coordinates as little-endian f32, frame-major (`(frame * count + marker) * 3 + axis`),
/// NaN where a sample is invalid; and one flags byte per sample.
#[derive(Debug, Clone, PartialEq)]
pub struct Packed {
    pub xyz: Vec<u8>,
    pub flags: Vec<u8>,
}

/// Pack `frames` frames of `points`, with marker `i` of the output taken from point
/// `order[i]` (`None`, or a frame past the end, gives invalid samples). This lines an original
/// file's markers up with the repaired file's by label. `fills_marked`: whether a residual
/// of 0 means filled in this file.
pub fn pack(points: &Points, order: &[Option<usize>], frames: usize, fills_marked: bool) -> Packed {
    let n = frames * order.len();
    let mut xyz = Vec::with_capacity(n * 12);
    let mut flags = Vec::with_capacity(n);
    for f in 0..frames {
        for src in order {
            let sample = src
                .filter(|&p| f < points.frames() && p < points.count())
                .map(|p| points.index(f, p))
                .filter(|&i| points.is_valid_at(i));
            let (v, fl) = match sample {
                Some(i) => {
                    let fl = if fills_marked && points.residual[i] == 0.0 {
                        VALID | FILLED
                    } else {
                        VALID
                    };
                    (points.xyz[i], fl)
                }
                None => ([f32::NAN; 3], 0),
            };
            for c in v {
                xyz.extend_from_slice(&c.to_le_bytes());
            }
            flags.push(fl);
        }
    }
    Packed { xyz, flags }
}

/// A force plate's outline as the page draws it.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct PlateOutline {
    /// 1-based, as FORCE_PLATFORM numbers it.
    pub index: usize,
    /// The four corners, lab frame, POINT:UNITS.
    pub corners: [[f32; 3]; 4],
}

/// The plates' ground reaction at each point frame, for the page's arrows.
#[derive(Debug, Clone, PartialEq)]
pub struct PlateFrames {
    pub outlines: Vec<PlateOutline>,
    /// Little-endian f32, `(frame * plates + plate) * 6`: the COP (x, y, z), then the force
    /// (x, y, z) in N; all NaN where the COP is undefined (the plate unloaded) or the frame
    /// has no analog sample.
    pub samples: Vec<u8>,
    /// Data units per newton: the largest force of the trial is drawn 1.5 times as long as
    /// a plate's side (the median plate's longest), so the arrow reads at any zoom and in
    /// any unit.
    pub scale: f64,
}

/// The analog sample shown for each point frame: the first of the frame's samples, as the
/// file interleaves them (ANALOG:RATE = samples per frame × POINT:RATE), or `None` past the
/// analog data's end.
pub fn frame_sample(fp: &c3dfix::ForcePlatforms, frame: usize, samples: usize) -> Option<usize> {
    let i = frame * fp.samples_per_frame.max(1);
    (i < samples).then_some(i)
}

/// Each plate of `fp` at each of `frames` point frames, from the first analog sample of the
/// frame ([`frame_sample`]): the arrow shows what the plate measured as the
/// markers were captured, not an average over the frame's samples.
pub fn plate_frames(fp: &c3dfix::ForcePlatforms, frames: usize) -> PlateFrames {
    let outlines = fp
        .platforms
        .iter()
        .map(|p| PlateOutline {
            index: p.index,
            corners: p.corners.map(|c| c.map(|x| x as f32)),
        })
        .collect();
    let mut samples = Vec::with_capacity(frames * fp.platforms.len() * 24);
    let mut peak: f64 = 0.0;
    // The median of the plates' longest sides: one plate with corrupt CORNERS (some vendor
    // test files hold 1e10 there) does not blow every arrow up.
    let mut sides: Vec<f64> = fp
        .platforms
        .iter()
        .map(|p| {
            (0..4)
                .map(|k| {
                    let (a, b) = (p.corners[k], p.corners[(k + 1) % 4]);
                    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
                })
                .fold(0.0, f64::max)
        })
        .filter(|s| s.is_finite())
        .collect();
    sides.sort_by(f64::total_cmp);
    let side = sides.get(sides.len() / 2).copied().unwrap_or(0.0);
    for f in 0..frames {
        for p in &fp.platforms {
            let at = frame_sample(fp, f, p.force.len());
            let v = match at {
                Some(i) => {
                    let (cop, force) = (p.cop[i], p.force[i]);
                    if cop.iter().chain(&force).all(|x| x.is_finite()) {
                        peak = peak.max(force.iter().map(|x| x * x).sum::<f64>().sqrt());
                        [cop, force]
                    } else {
                        [[f64::NAN; 3]; 2]
                    }
                }
                None => [[f64::NAN; 3]; 2],
            };
            for x in v.iter().flatten() {
                samples.extend_from_slice(&(*x as f32).to_le_bytes());
            }
        }
    }
    let scale = if peak > 0.0 && side > 0.0 {
        1.5 * side / peak
    } else {
        0.0
    };
    PlateFrames {
        outlines,
        samples,
        scale,
    }
}

/// The floats of a packed coordinate array: the inverse of the packing, for tests.
#[cfg(test)]
pub fn unpack(bytes: &[u8]) -> Vec<f32> {
    bytes
        .chunks_exact(4)
        .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
        .collect()
}

const B64: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";

/// Standard base64 with padding, as the browser's `atob` reads it.
pub fn base64(bytes: &[u8]) -> String {
    let mut s = String::with_capacity(bytes.len().div_ceil(3) * 4);
    for c in bytes.chunks(3) {
        let b = [c[0], *c.get(1).unwrap_or(&0), *c.get(2).unwrap_or(&0)];
        let v = (u32::from(b[0]) << 16) | (u32::from(b[1]) << 8) | u32::from(b[2]);
        for k in 0..4 {
            if k <= c.len() {
                s.push(B64[((v >> (18 - 6 * k)) & 63) as usize] as char);
            } else {
                s.push('=');
            }
        }
    }
    s
}

/// Decode standard base64 (padding optional); `None` on any other character.
#[cfg(test)]
pub fn unbase64(text: &str) -> Option<Vec<u8>> {
    let mut out = Vec::with_capacity(text.len() / 4 * 3);
    let (mut acc, mut bits) = (0u32, 0);
    for ch in text.bytes().filter(|&c| c != b'=') {
        let v = B64.iter().position(|&b| b == ch)? as u32;
        acc = (acc << 6) | v;
        bits += 6;
        if bits >= 8 {
            bits -= 8;
            out.push((acc >> bits) as u8);
            acc &= (1 << bits) - 1;
        }
    }
    Some(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn base64_round_trips_and_matches_the_standard() {
        assert_eq!(base64(b"Man"), "TWFu");
        assert_eq!(base64(b"Ma"), "TWE=");
        assert_eq!(base64(b"M"), "TQ==");
        for n in 0..20u8 {
            let v: Vec<u8> = (0..n).map(|i| i.wrapping_mul(37)).collect();
            assert_eq!(unbase64(&base64(&v)).as_deref(), Some(v.as_slice()));
        }
    }

    #[test]
    fn pack_then_unpack_gives_the_floats_with_nan_for_invalid() {
        let mut p = Points::new(2, 2);
        p.xyz = vec![
            [1.0, 2.0, 3.0],
            [4.5, -5.25, 6.0],
            [7.0, 8.0, 9.0],
            [0.1, 0.2, 0.3],
        ];
        p.residual = vec![1.5, 0.0, -1.0, 2.0];
        let order = [Some(0), Some(1), None];
        let k = pack(&p, &order, 3, true);
        let back = unpack(&unbase64(&base64(&k.xyz)).unwrap());
        assert_eq!(back.len(), 3 * 3 * 3);
        assert_eq!(&back[0..6], &[1.0, 2.0, 3.0, 4.5, -5.25, 6.0]);
        assert!(back[6..9].iter().all(|v| v.is_nan())); // absent marker
        assert!(back[9..12].iter().all(|v| v.is_nan())); // invalid sample
        assert_eq!(&back[12..15], &[0.1, 0.2, 0.3]);
        assert!(back[18..].iter().all(|v| v.is_nan())); // frame past the end
        assert_eq!(
            k.flags,
            vec![VALID, VALID | FILLED, 0, 0, VALID, 0, 0, 0, 0]
        );
        // A file whose residuals mark no fills: residual 0 is no fill there.
        assert_eq!(
            pack(&p, &order, 3, false).flags,
            vec![VALID, VALID, 0, 0, VALID, 0, 0, 0, 0]
        );
        assert!(super::super::fills_marked(&p));
        p.residual = vec![0.0, 0.0, -1.0, 0.0];
        assert!(!super::super::fills_marked(&p));
    }
}
