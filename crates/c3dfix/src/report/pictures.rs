//! What the page draws per trial, small: each marker's coverage over time, each plate's
//! vertical force with the events, and the three worst fills before and after. Kept compact
//! (runs rather than samples, a few hundred values per curve) so that a page of a thousand
//! trials stays a few megabytes.

use crate::gaps::GapInfo;
use crate::{Direction, ForcePlatforms};
use serde::Serialize;
use std::collections::BTreeMap;

/// Values per force curve: one per bucket of samples, the bucket's largest push, so no
/// contact's peak is lost between buckets.
const FORCE_POINTS: usize = 300;
/// Frames drawn per fill curve at most (longer windows are drawn every n-th frame): a small
/// picture is about as many pixels wide.
const FILL_POINTS: usize = 120;
/// Steps a fill curve's coordinates are rounded to, over each axis' range in the window: a
/// thousandth of the picture's height, far below a pixel, and the page a third the size.
const FILL_STEPS: f64 = 1000.0;
/// Fills drawn per trial.
const WORST_FILLS: usize = 3;

/// The pictures of one trial.
#[derive(Debug, Clone, Serialize, PartialEq, Default)]
pub struct Pictures {
    /// The markers with a sample missing before or after (the others were recorded
    /// throughout), in the file's order.
    pub coverage: Vec<Coverage>,
    pub forces: Vec<ForceCurve>,
    /// The file's events and the detected ones, on the file's time base.
    pub events: Vec<Mark>,
    pub fills: Vec<FillCurve>,
}

/// One marker's samples that were not recorded.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct Coverage {
    pub label: String,
    pub runs: Vec<Run>,
}

/// `[first frame, last frame, kind, expected error mm or null]`: kind 0 still missing, 1
/// filled. Frames in the file's numbering.
#[derive(Debug, Clone, Copy, Serialize, PartialEq)]
pub struct Run(pub usize, pub usize, pub u8, pub Option<f64>);

/// One plate's vertical force: `values[k]` (N) at `start + k × step` seconds.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct ForceCurve {
    pub plate: usize,
    pub start: f64,
    pub step: f64,
    pub values: Vec<f32>,
}

/// One event on the force picture.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct Mark {
    /// Seconds, on the file's time base.
    pub time: f64,
    /// `LFS`, `RFO`, or the event's own label.
    pub short: String,
    pub detected: bool,
}

impl Mark {
    pub(super) fn new(context: &str, label: &str, time: f64, detected: bool) -> Mark {
        let side = match context.trim().to_ascii_lowercase().as_str() {
            "left" => "L",
            "right" => "R",
            _ => "",
        };
        let short = match label.trim().to_ascii_lowercase().as_str() {
            "foot strike" => format!("{side}FS"),
            "foot off" => format!("{side}FO"),
            _ => label.trim().to_string(),
        };
        Mark {
            time,
            short,
            detected,
        }
    }
}

/// One fill drawn before and after: the marker's samples over a window around the gap,
/// `null` where missing.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct FillCurve {
    pub label: String,
    pub first_frame: usize,
    pub last_frame: usize,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub expected_error_mm: Option<f64>,
    /// The frame of the first value, and frames between values.
    pub window_first: usize,
    pub stride: usize,
    pub before: Vec<Option<[f64; 3]>>,
    pub after: Vec<Option<[f64; 3]>>,
}

/// A gap the repair filled, with its expected error when the repair's summary gives it.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct Fill {
    pub label: String,
    pub first_frame: usize,
    pub last_frame: usize,
    pub expected_error_mm: Option<f64>,
}

/// `(a, b)` less the stretches of `minus` (all inclusive, sorted).
fn subtract(a: usize, b: usize, minus: &[(usize, usize)]) -> Vec<(usize, usize)> {
    let mut out = Vec::new();
    let mut from = a;
    for &(x, y) in minus.iter().filter(|&&(x, y)| y >= a && x <= b) {
        if x > from {
            out.push((from, x - 1));
        }
        from = from.max(y + 1);
    }
    if from <= b {
        out.push((from, b));
    }
    out
}

/// Each marker's runs: without a repaired copy its gaps as missing; with one, what the copy
/// still misses, and the rest of each original gap as filled (coloured by the expected error
/// of the fill it lies in, when known).
pub(super) fn coverage(
    c: &c3d::C3d,
    before: &[GapInfo],
    after: Option<&[GapInfo]>,
    fills: &[Fill],
) -> Vec<Coverage> {
    let b = by_label(before);
    let a = after.map(by_label);
    let labels = c.point_labels();
    let mut out = Vec::new();
    let markers = crate::markers::split_unlabelled(c, &repair::Unlabelled::common()).labelled;
    for i in markers {
        let label = &labels[i];
        let gone = b.get(label.as_str()).map(Vec::as_slice).unwrap_or(&[]);
        let mut runs: Vec<Run> = match &a {
            None => gone.iter().map(|&(x, y)| Run(x, y, 0, None)).collect(),
            Some(a) => {
                let still = a.get(label.as_str()).map(Vec::as_slice).unwrap_or(&[]);
                let mut runs: Vec<Run> = still.iter().map(|&(x, y)| Run(x, y, 0, None)).collect();
                for &(x, y) in gone {
                    for (p, q) in subtract(x, y, still) {
                        let err = fills
                            .iter()
                            .find(|f| &f.label == label && f.first_frame <= q && f.last_frame >= p)
                            .and_then(|f| f.expected_error_mm);
                        runs.push(Run(p, q, 1, err));
                    }
                }
                runs
            }
        };
        if runs.is_empty() {
            continue;
        }
        runs.sort_by_key(|r| r.0);
        out.push(Coverage {
            label: label.clone(),
            runs,
        });
    }
    out
}

/// Each plate's force along the lab's up (the plates' corners, else `up`), the largest push
/// of each bucket of samples.
pub(super) fn forces(fp: &ForcePlatforms, up: Option<Direction>) -> Vec<ForceCurve> {
    let Some(up) = crate::axes::platforms_up(fp).or(up) else {
        return Vec::new();
    };
    let sign = if up.positive { 1.0 } else { -1.0 };
    fp.platforms
        .iter()
        .map(|p| {
            let n = p.force.len();
            let per = n.div_ceil(FORCE_POINTS).max(1);
            let values = p
                .force
                .chunks(per)
                .map(|ch| {
                    ch.iter()
                        .map(|f| (f[up.axis] * sign) as f32)
                        .fold(f32::NEG_INFINITY, f32::max)
                })
                .map(|v| if v.is_finite() { v } else { 0.0 })
                .collect();
            let step = if p.rate > 0.0 && p.rate.is_finite() {
                per as f64 / p.rate
            } else {
                0.0
            };
            ForceCurve {
                plate: p.index,
                start: fp.start_time,
                step,
                values,
            }
        })
        .collect()
}

/// The three fills most worth a look: the largest expected errors when the repair's summary
/// gives them, else the longest fills.
pub(super) fn worst_fills(
    c: &c3d::C3d,
    copy: &c3d::C3d,
    before: &[GapInfo],
    after: &[GapInfo],
    fills: &[Fill],
) -> Vec<FillCurve> {
    let mut chosen: Vec<Fill> = if fills.is_empty() {
        let a = by_label(after);
        before
            .iter()
            .flat_map(|g| {
                let still = a.get(g.label.as_str()).map(Vec::as_slice).unwrap_or(&[]);
                subtract(g.first_frame, g.last_frame, still)
                    .into_iter()
                    .map(|(p, q)| Fill {
                        label: g.label.clone(),
                        first_frame: p,
                        last_frame: q,
                        expected_error_mm: None,
                    })
            })
            .collect()
    } else {
        fills.to_vec()
    };
    chosen.sort_by(|x, y| {
        let e = |f: &Fill| f.expected_error_mm.unwrap_or(-1.0);
        e(y).total_cmp(&e(x))
            .then((y.last_frame - y.first_frame).cmp(&(x.last_frame - x.first_frame)))
            .then(x.first_frame.cmp(&y.first_frame))
    });
    chosen
        .iter()
        .filter_map(|f| curve(c, copy, f))
        .take(WORST_FILLS)
        .collect()
}

/// The samples of one marker around one fill, in the trial and in its copy.
fn curve(c: &c3d::C3d, copy: &c3d::C3d, f: &Fill) -> Option<FillCurve> {
    let (i, j) = (c.point_index(&f.label)?, copy.point_index(&f.label)?);
    let first = c.first_frame();
    let frames = c.frames().min(copy.frames());
    let (a, b) = (
        f.first_frame.checked_sub(first)?,
        f.last_frame.checked_sub(first)?,
    );
    if b >= frames {
        return None;
    }
    let pad = (b - a + 1).clamp(10, 200);
    let (lo, hi) = (a.saturating_sub(pad), (b + pad).min(frames - 1));
    let stride = (hi - lo + 1).div_ceil(FILL_POINTS).max(1);
    let sample = |t: &c3d::C3d, p: usize, k: usize| {
        let pts = t.points();
        let x = pts.index(k, p);
        pts.is_valid_at(x).then(|| pts.xyz[x].map(f64::from))
    };
    let at = (lo..=hi).step_by(stride);
    let mut before: Vec<Option<[f64; 3]>> = at.clone().map(|k| sample(c, i, k)).collect();
    let mut after: Vec<Option<[f64; 3]>> = at.map(|k| sample(copy, j, k)).collect();
    rounded(&mut before, &mut after);
    Some(FillCurve {
        label: f.label.clone(),
        first_frame: f.first_frame,
        last_frame: f.last_frame,
        expected_error_mm: f.expected_error_mm,
        window_first: lo + first,
        stride,
        before,
        after,
    })
}

/// Both curves' coordinates rounded to a power of ten near [`FILL_STEPS`] steps of each
/// axis' range, so the page carries the digits a picture shows, in any unit.
fn rounded(a: &mut [Option<[f64; 3]>], b: &mut [Option<[f64; 3]>]) {
    for axis in 0..3 {
        let (lo, hi) = a
            .iter()
            .chain(b.iter())
            .flatten()
            .map(|p| p[axis])
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), v| {
                (l.min(v), h.max(v))
            });
        let range = hi - lo;
        if !(range.is_finite() && range > 0.0) {
            continue;
        }
        let q = 10f64.powf((range / FILL_STEPS).log10().floor());
        for p in a.iter_mut().chain(b.iter_mut()).flatten() {
            p[axis] = (p[axis] / q).round() * q;
            // The product can land a last bit off the decimal; its shortest form is then
            // the decimal itself.
            p[axis] = format!("{:.*}", (-q.log10()).max(0.0) as usize, p[axis])
                .parse()
                .unwrap_or(p[axis]);
        }
    }
}

/// The gaps of `c`, with the frames of each, by label: what coverage and the fills read.
fn by_label(g: &[GapInfo]) -> BTreeMap<&str, Vec<(usize, usize)>> {
    let mut m: BTreeMap<&str, Vec<(usize, usize)>> = BTreeMap::new();
    for x in g {
        m.entry(&x.label)
            .or_default()
            .push((x.first_frame, x.last_frame));
    }
    m
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fill_curves_keep_the_digits_a_picture_shows() {
        let mut a = vec![Some([1234.5678, 0.012345, 7.0]), None];
        let mut b = vec![
            Some([1334.5678, 0.013345, 7.0]),
            Some([1300.0, 0.0125, 7.0]),
        ];
        rounded(&mut a, &mut b);
        assert_eq!(a[0], Some([1234.6, 0.012345, 7.0]));
        assert_eq!(b[0], Some([1334.6, 0.013345, 7.0]));
        assert_eq!(a[1], None);
    }

    #[test]
    fn subtract_leaves_the_filled_parts() {
        assert_eq!(subtract(10, 20, &[]), vec![(10, 20)]);
        assert_eq!(
            subtract(10, 20, &[(12, 13), (18, 25)]),
            vec![(10, 11), (14, 17)]
        );
        assert_eq!(subtract(10, 20, &[(0, 30)]), vec![]);
        assert_eq!(subtract(10, 20, &[(0, 5), (30, 40)]), vec![(10, 20)]);
    }
}
