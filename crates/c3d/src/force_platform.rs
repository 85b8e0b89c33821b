//! The FORCE_PLATFORM group, read into one description per plate.
//!
//! The format crate only says what the parameters hold; turning analog channels into forces
//! is the `kinetics` crate's job. Reading is lenient per plate: a parameter that is missing,
//! of the wrong size or pointing outside the analog data is reported as a [`PlateProblem`]
//! naming the plate and the parameter, and that plate alone is left without it — the other
//! plates and the rest of the file still read.
//!
//! The manual's pages: FORCE_PLATFORM:USED, TYPE, CHANNEL (an array (rows, USED) of 1-based
//! analog channel numbers), CORNERS (3, 4, USED) in POINT:UNITS, ORIGIN (3, USED),
//! CAL_MATRIX (n, n, plates) stored column by column, ZERO (2) — the first and last frame of
//! the baseline, 0 meaning none. FPCOPPOLY (6, 2, USED) is the Kistler centre-of-pressure
//! correction that Qualisys writes for type-3 plates: P1..P6 for x, then for y.

use crate::parameters::{Parameter, Parameters};
use serde::Serialize;

/// What FORCE_PLATFORM says about one plate.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PlateParams {
    /// 1-based, as the manual numbers plates.
    pub index: usize,
    /// FORCE_PLATFORM:TYPE.
    pub kind: i32,
    /// 1-based analog channel numbers (FORCE_PLATFORM:CHANNEL's column for this plate),
    /// trailing zeros dropped. Checked against the analog channel count.
    pub channels: Vec<usize>,
    /// The four corners in the lab frame, POINT:UNITS, in the manual's quadrant order
    /// (+x+y, −x+y, −x−y, +x−y of the plate's own axes).
    pub corners: Option<[[f64; 3]; 4]>,
    /// FORCE_PLATFORM:ORIGIN as stored (its sign is judged by the kinetics).
    pub origin: Option<[f64; 3]>,
    /// FORCE_PLATFORM:CAL_MATRIX for this plate, row-major (converted from the manual's
    /// column order), `n × n` with `n` the matrix's first dimension.
    pub cal_matrix: Option<Vec<f64>>,
    /// FPCOPPOLY: the six x then six y coefficients of Kistler's COP correction.
    pub cop_poly: Option<[f64; 12]>,
}

/// A FORCE_PLATFORM parameter that could not be used for a plate.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PlateProblem {
    /// 1-based plate number; 0 for a problem of the whole group.
    pub plate: usize,
    /// The parameter at fault, e.g. "FORCE_PLATFORM:CHANNEL".
    pub parameter: String,
    pub message: String,
}

/// The plates of a file as FORCE_PLATFORM describes them.
#[derive(Debug, Clone, PartialEq, Default, Serialize)]
pub struct PlatformParams {
    pub plates: Vec<PlateParams>,
    /// FORCE_PLATFORM:ZERO: 1-based first and last frame of the baseline, counted from the
    /// trial's first stored frame; `None` for none (absent, [0, 0], or a range that ends
    /// before it starts, such as Vicon's [1, 0]).
    pub zero: Option<[usize; 2]>,
    pub problems: Vec<PlateProblem>,
}

/// More plates than any lab has: a USED beyond it is a corrupt parameter, not a lab.
const MAX_PLATES: usize = 1024;

/// Read FORCE_PLATFORM from `ps`; `analog_channels` is the file's analog channel count, which
/// every CHANNEL entry must fall within.
pub fn platform_params(ps: &Parameters, analog_channels: usize) -> PlatformParams {
    let mut out = PlatformParams::default();
    let used = match ps.get("FORCE_PLATFORM", "USED").map(|p| p.as_i32s()) {
        None => return out,
        Some(v) => v.first().copied().unwrap_or(0),
    };
    if used <= 0 {
        return out;
    }
    let mut used = used as usize;
    if used > MAX_PLATES {
        out.problems.push(problem(
            0,
            "USED",
            format!("{used} plates is beyond any lab; read as {MAX_PLATES}"),
        ));
        used = MAX_PLATES;
    }
    let types = ps
        .get("FORCE_PLATFORM", "TYPE")
        .map(|p| p.as_i32s())
        .unwrap_or_default();
    let channel = ps.get("FORCE_PLATFORM", "CHANNEL");
    let rows = channel.map(|p| column_length(p, used)).unwrap_or(0);
    let channels = channel.map(|p| p.as_i32s()).unwrap_or_default();
    let corners = ps.get("FORCE_PLATFORM", "CORNERS");
    let origins = ps.get("FORCE_PLATFORM", "ORIGIN");
    let cal = ps.get("FORCE_PLATFORM", "CAL_MATRIX");
    let poly = ps.get("FORCE_PLATFORM", "FPCOPPOLY");

    for k in 0..used {
        let index = k + 1;
        let Some(&kind) = types.get(k) else {
            out.problems.push(problem(
                index,
                "TYPE",
                format!("has {} entries, none for plate {index}", types.len()),
            ));
            continue;
        };
        let mut plate = PlateParams {
            index,
            kind,
            channels: Vec::new(),
            corners: None,
            origin: None,
            cal_matrix: None,
            cop_poly: None,
        };
        let problems = &mut out.problems;
        match channel {
            None => problems.push(problem(index, "CHANNEL", "is missing".into())),
            Some(_) => {
                let col = channels.get(k * rows..(k + 1) * rows).unwrap_or(&[]);
                if let Some(c) = plate_channels(col, index, analog_channels, problems) {
                    plate.channels = c;
                }
            }
        }
        plate.corners = plate_corners(corners, k, used, problems);
        plate.origin = plate_origin(origins, k, used, problems);
        if let Some(p) = cal {
            plate.cal_matrix = cal_matrix_of(p, k);
        }
        if let Some(p) = poly {
            plate.cop_poly = slice_of(p, &[6, 2], k).map(|v| {
                let mut a = [0.0; 12];
                a.copy_from_slice(&v);
                a
            });
        }
        out.plates.push(plate);
    }
    out.zero = zero_frames(ps);
    out
}

/// Plate `index`'s column of CHANNEL (trailing zeros dropped), each an analog channel of the
/// file's `analog_channels`; None, with the problem said, for an empty column or a channel
/// the file does not have.
fn plate_channels(
    col: &[i32],
    index: usize,
    analog_channels: usize,
    problems: &mut Vec<PlateProblem>,
) -> Option<Vec<usize>> {
    let mut col: Vec<i32> = col.to_vec();
    while col.last() == Some(&0) {
        col.pop();
    }
    if col.is_empty() {
        problems.push(problem(
            index,
            "CHANNEL",
            format!("has no channels for plate {index}"),
        ));
        None
    } else if let Some(bad) = col.iter().find(|&&c| c < 1 || c as usize > analog_channels) {
        problems.push(problem(
            index,
            "CHANNEL",
            format!(
                "names analog channel {bad}, but the file has {analog_channels} analog channels"
            ),
        ));
        None
    } else {
        Some(col.iter().map(|&c| c as usize).collect())
    }
}

/// Plate `k`'s four corners from CORNERS (3 × 4 × `used`); None, with the problem said,
/// when the parameter is missing or shaped otherwise.
fn plate_corners(
    corners: Option<&Parameter>,
    k: usize,
    used: usize,
    problems: &mut Vec<PlateProblem>,
) -> Option<[[f64; 3]; 4]> {
    let index = k + 1;
    match corners {
        None => {
            problems.push(problem(index, "CORNERS", "is missing".into()));
            None
        }
        Some(p) => match slice_of(p, &[3, 4], k) {
            Some(v) => Some([
                [v[0], v[1], v[2]],
                [v[3], v[4], v[5]],
                [v[6], v[7], v[8]],
                [v[9], v[10], v[11]],
            ]),
            None => {
                problems.push(problem(
                    index,
                    "CORNERS",
                    format!("has dimensions {:?}; (3, 4, {used}) expected", p.dims),
                ));
                None
            }
        },
    }
}

/// Plate `k`'s ORIGIN (3 × `used`); None, with the problem said, when the parameter is
/// missing or shaped otherwise.
fn plate_origin(
    origins: Option<&Parameter>,
    k: usize,
    used: usize,
    problems: &mut Vec<PlateProblem>,
) -> Option<[f64; 3]> {
    let index = k + 1;
    match origins {
        None => {
            problems.push(problem(index, "ORIGIN", "is missing".into()));
            None
        }
        Some(p) => match slice_of(p, &[3], k) {
            Some(v) => Some([v[0], v[1], v[2]]),
            None => {
                problems.push(problem(
                    index,
                    "ORIGIN",
                    format!("has dimensions {:?}; (3, {used}) expected", p.dims),
                ));
                None
            }
        },
    }
}

/// FORCE_PLATFORM:ZERO as a range of frames, from 1.
fn zero_frames(ps: &Parameters) -> Option<[usize; 2]> {
    ps.get("FORCE_PLATFORM", "ZERO")
        .map(|p| p.as_i32s())
        .and_then(|z| match z.as_slice() {
            // [0, 0] is none; a first frame of 0 means the first frame (files write [0, 10]
            // for the first ten frames); a last frame before the first is none.
            [a, b, ..] if *b >= 1 && *b >= (*a).max(1) => Some([(*a).max(1) as usize, *b as usize]),
            _ => None,
        })
}

fn problem(plate: usize, name: &str, message: String) -> PlateProblem {
    PlateProblem {
        plate,
        parameter: format!("FORCE_PLATFORM:{name}"),
        message,
    }
}

/// Rows per plate of a (rows, plates) array: its first dimension, or all of it for a
/// one-dimensional array of a single plate.
fn column_length(p: &Parameter, used: usize) -> usize {
    match p.dims.as_slice() {
        [rows, _, ..] => *rows as usize,
        [n] if used == 1 => *n as usize,
        [n] => *n as usize / used.max(1),
        [] => 1,
    }
}

/// Plate `k`'s block of an array whose leading dimensions are `lead` (e.g. [3, 4] for
/// CORNERS), or `None` when the array's leading dimensions differ or it has no block `k`.
fn slice_of(p: &Parameter, lead: &[usize], k: usize) -> Option<Vec<f64>> {
    let dims: Vec<usize> = p.dims.iter().map(|&d| d as usize).collect();
    if dims.len() < lead.len() || dims[..lead.len()] != *lead {
        return None;
    }
    let block: usize = lead.iter().product();
    let values = p.as_f32s();
    values
        .get(k * block..(k + 1) * block)
        .map(|v| v.iter().map(|&x| x as f64).collect())
}

/// Plate `k`'s CAL_MATRIX (n, n, plates), turned from the manual's column order to
/// row-major. A matrix of zero plates (dims (6, 6, 0), seen in files that carry none) is
/// absent.
fn cal_matrix_of(p: &Parameter, k: usize) -> Option<Vec<f64>> {
    let n = *p.dims.first()? as usize;
    if n == 0 || p.dims.get(1).copied().map(usize::from) != Some(n) {
        return None;
    }
    let cols = slice_of(p, &[n, n], k)?;
    let mut rowm = vec![0.0; n * n];
    for c in 0..n {
        for r in 0..n {
            rowm[r * n + c] = cols[c * n + r];
        }
    }
    Some(rowm)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::parameters::Value;

    fn params(with: &[(&str, Vec<u8>, Value)]) -> Parameters {
        let mut ps = Parameters::new();
        for (name, dims, v) in with {
            ps.set("FORCE_PLATFORM", name, dims.clone(), v.clone())
                .expect("set");
        }
        ps
    }

    fn corners(n: usize) -> Value {
        Value::Float((0..12 * n).map(|i| i as f32).collect())
    }

    #[test]
    fn one_plate_of_each_parameter() {
        let ps = params(&[
            ("USED", vec![], Value::Int(vec![2])),
            ("TYPE", vec![2], Value::Int(vec![2, 4])),
            (
                "CHANNEL",
                vec![6, 2],
                Value::Int((1..=12).map(|c| c as i16).collect()),
            ),
            ("CORNERS", vec![3, 4, 2], corners(2)),
            (
                "ORIGIN",
                vec![3, 2],
                Value::Float(vec![1.0, 2.0, -40.0, 0.0, 0.0, -38.0]),
            ),
            (
                "CAL_MATRIX",
                vec![6, 6, 1],
                Value::Float((0..36).map(|i| i as f32).collect()),
            ),
            ("ZERO", vec![2], Value::Int(vec![1, 10])),
        ]);
        let fp = platform_params(&ps, 12);
        assert!(fp.problems.is_empty(), "{:?}", fp.problems);
        assert_eq!(fp.plates.len(), 2);
        assert_eq!(fp.plates[1].channels, vec![7, 8, 9, 10, 11, 12]);
        assert_eq!(
            fp.plates[1].corners.expect("corners")[0],
            [12.0, 13.0, 14.0]
        );
        assert_eq!(fp.plates[1].origin, Some([0.0, 0.0, -38.0]));
        // Column order on disk: element (row 0, column 1) is the 7th stored value.
        let cal = fp.plates[0].cal_matrix.as_ref().expect("cal");
        assert_eq!(cal[1], 6.0);
        assert_eq!(cal[6], 1.0);
        assert!(fp.plates[1].cal_matrix.is_none());
        assert_eq!(fp.zero, Some([1, 10]));
    }

    #[test]
    fn a_bad_plate_is_reported_and_the_others_kept() {
        let ps = params(&[
            ("USED", vec![], Value::Int(vec![2])),
            ("TYPE", vec![2], Value::Int(vec![2, 2])),
            (
                "CHANNEL",
                vec![6, 2],
                Value::Int(vec![1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 99]),
            ),
            ("CORNERS", vec![3, 2], Value::Float(vec![0.0; 6])),
            ("ORIGIN", vec![3, 2], Value::Float(vec![0.0; 6])),
            ("ZERO", vec![2], Value::Int(vec![0, 0])),
        ]);
        let fp = platform_params(&ps, 12);
        assert_eq!(fp.plates.len(), 2);
        assert_eq!(fp.plates[0].channels.len(), 6);
        assert!(fp.plates[1].channels.is_empty());
        assert!(fp
            .problems
            .iter()
            .any(|p| p.plate == 2 && p.parameter == "FORCE_PLATFORM:CHANNEL"));
        assert!(fp
            .problems
            .iter()
            .any(|p| p.plate == 1 && p.parameter == "FORCE_PLATFORM:CORNERS"));
        assert_eq!(fp.zero, None);
    }

    #[test]
    fn no_group_no_plates() {
        let fp = platform_params(&Parameters::new(), 0);
        assert!(fp.plates.is_empty() && fp.problems.is_empty());
    }
}
