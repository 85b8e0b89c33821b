//! What a repair records in the file it writes, and what a later repair reads back, so that
//! repairing a repaired file changes nothing (docs/reruns.md).
//!
//! The samples themselves cannot say who filled them: c3dfix writes residual 0 and camera
//! mask 0, the C3D manual's mark for any processed point, which capture software writes for
//! its own fills too. So the file carries a parameter group, `C3DFIX`:
//!
//! - `FILLED` (float, rows of 3): point number (1 = the first of POINT:LABELS), first and
//!   last frame number (the file's own numbering) of every stretch c3dfix filled, over all
//!   its runs on the file.
//! - `LEFT` (float, rows of 6): point number, first and last frame number, reason code and
//!   two values of every gap the last run left unfilled (see [`reason_code`]).
//! - `FILL` (char): the fill settings the gaps in `LEFT` were judged under.
//! - `FILTER`, `SPIKES` (char): the low-pass filter and the spike removal applied, if any.
//! - `SWAPS` (char): the swap stage applied (`--swaps fix`), if any, and `UNDONE` (float,
//!   rows of 4): point numbers of the two markers (the second 0 for a jump), first and last
//!   frame number of every label swap exchanged back and every label jump made a gap.
//! - `RECLAIM` (char): the reclaim stage applied (`--reclaim on`), if any, and `RECLAIMED`
//!   (float, rows of 4): point numbers of the marker and of the unlabelled point, first and
//!   last frame number of every stretch of recorded samples moved from the one to the other
//!   (issue 47). Those samples are data, as recorded, not fills.
//!
//! A later repair (the rule, applied in [`repair::repair_trial_after`]): samples in `FILLED`
//! are kept and are no data (no donor, no context, never a spike), so fills never breed
//! fills; a gap in `LEFT` under the same fill settings is left again with its reason, not
//! judged again; a filter, a spike removal or a swap stage the file records is not applied a
//! second time (an exchange undone and found again would be exchanged back: a rerun must not
//! undo the first run's work).
//! Rows of more than 255 go into further dimensions of 255 (C3D dimensions are one byte),
//! padded with rows of zeros, which name no point; a record holds at most 32 767 bytes, so
//! longer lists continue in `FILLED2`, `FILLED3`, … (`LEFT2`, …), as POINT:LABELS2 does.

use repair::SkipReason;

/// The fill settings a gap is left under, as `FILL` records them: a gap left under other
/// settings is judged again.
pub fn fill_settings(o: &crate::RepairOptions) -> String {
    let limit = o
        .max_expected_error_mm
        .map_or("off".to_string(), |e| format!("{e}"));
    let mut s = format!(
        "--fill {} --max-gap {} --max-expected-error {limit}",
        o.fill, o.max_gap
    );
    if o.zero_invalid {
        s.push_str(" --zero-invalid");
    }
    // Which points are markers decides which gaps there are: a pattern asked for is part of
    // the settings (none asked for writes what earlier runs wrote).
    if let Some(p) = &o.unlabelled {
        s.push_str(&format!(" --unlabelled {p}"));
    }
    s
}

/// The spike removal asked for, as `SPIKES` records it (`None`: none asked for).
pub fn spike_settings(o: &crate::RepairOptions) -> Option<String> {
    let spec = o.spikes?;
    let mut s = format!(
        "--spikes {spec} --spike-mode {} --spike-min-mm {}",
        o.spike_mode, o.spike_min_mm
    );
    if o.spike_classic {
        s.push_str(" --spike-classic");
    }
    Some(s)
}

/// The swap stage asked for, as `SWAPS` records it (`None`: nothing to record, the stage
/// changes the file only when fixing).
pub fn swap_settings(o: &crate::RepairOptions) -> Option<String> {
    (o.swaps == crate::SwapsMode::Fix).then(|| "--swaps fix".to_string())
}

/// The reclaim stage asked for, as `RECLAIM` records it (`None`: nothing to record, the
/// stage changes the file only when on).
pub fn reclaim_settings(o: &crate::RepairOptions) -> Option<String> {
    (o.reclaim == crate::ReclaimMode::On).then(|| "--reclaim on".to_string())
}

/// One label swap (two points) or jump (one point) a repair undid: point indices (0-based)
/// and frame indices (0-based, inclusive).
#[derive(Debug, Clone, PartialEq, Eq, PartialOrd, Ord)]
pub struct Undone {
    pub points: Vec<usize>,
    pub first: usize,
    pub last: usize,
}

/// The parameter group c3dfix records its work in.
pub const GROUP: &str = "C3DFIX";

/// One gap an earlier run left.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Left {
    /// Point index (0-based, into POINT:LABELS) and frame indices (0-based, inclusive).
    pub point: usize,
    pub first_index: usize,
    pub last_index: usize,
    pub reason: SkipReason,
}

/// What the `C3DFIX` group of a file says (frames as 0-based indices into the file).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Record {
    /// `(point, first, last)`: stretches c3dfix filled.
    pub filled: Vec<(usize, usize, usize)>,
    pub left: Vec<Left>,
    pub fill: Option<String>,
    pub filter: Option<String>,
    pub spikes: Option<String>,
    pub swaps: Option<String>,
    /// Swaps exchanged back and jumps made gaps, over all runs.
    pub undone: Vec<Undone>,
    pub reclaim: Option<String>,
    /// Recorded samples moved from unlabelled points into markers, over all runs.
    pub reclaimed: Vec<Reclaimed>,
}

/// One move a repair made, for the file's record: point indices and 0-based frames.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub struct Reclaimed {
    pub point: usize,
    pub source: usize,
    pub first: usize,
    pub last: usize,
}

/// A reason as `LEFT` stores it: a code and two values (the reason's numbers, 0 without).
pub fn reason_code(r: SkipReason) -> [f32; 3] {
    match r {
        SkipReason::MethodNone => [1.0, 0.0, 0.0],
        SkipReason::TooLong { max_gap } => [2.0, max_gap as f32, 0.0],
        SkipReason::TouchesEdge => [3.0, 0.0, 0.0],
        SkipReason::NoDonors => [4.0, 0.0, 0.0],
        SkipReason::NoContext => [5.0, 0.0, 0.0],
        SkipReason::Degenerate => [6.0, 0.0, 0.0],
        SkipReason::Implausible { step_ratio } => [7.0, step_ratio as f32, 0.0],
        SkipReason::Uncertain {
            expected_error,
            max_expected_error,
        } => [8.0, expected_error as f32, max_expected_error as f32],
    }
}

/// The reason [`reason_code`] stored, or `None` for a code it never writes.
pub fn reason_of(code: f32, a: f32, b: f32) -> Option<SkipReason> {
    Some(match code as i32 {
        1 => SkipReason::MethodNone,
        2 => SkipReason::TooLong {
            max_gap: a.max(0.0) as usize,
        },
        3 => SkipReason::TouchesEdge,
        4 => SkipReason::NoDonors,
        5 => SkipReason::NoContext,
        6 => SkipReason::Degenerate,
        7 => SkipReason::Implausible {
            step_ratio: a as f64,
        },
        8 => SkipReason::Uncertain {
            expected_error: a as f64,
            max_expected_error: b as f64,
        },
        _ => return None,
    })
}

/// The name of the `k`-th parameter (0-based) holding rows of `name`: `name`, `name2`, …
/// (a record holds at most 32 767 bytes, as POINT:LABELS2 continues POINT:LABELS).
fn part(name: &str, k: usize) -> String {
    if k == 0 {
        name.to_string()
    } else {
        format!("{name}{}", k + 1)
    }
}

/// Rows one parameter holds: whole dimensions of 255 rows in about 30 000 bytes (a
/// record's offset to the next is a signed 16-bit word: 32 767 bytes at most).
fn rows_per_part(cols: usize) -> usize {
    (30_000 / (cols * 4) / 255).max(1) * 255
}

/// Rows of `cols` floats of `GROUP:name` and its continuations; none when absent or not
/// shaped so.
fn rows(c: &c3d::C3d, name: &str, cols: usize) -> Vec<Vec<f32>> {
    let mut out = Vec::new();
    for k in 0.. {
        let Some(p) = c.param(GROUP, &part(name, k)) else {
            break;
        };
        if p.dims.first().map(|&d| d as usize) != Some(cols) {
            break;
        }
        out.extend(p.as_f32s().chunks_exact(cols).map(<[f32]>::to_vec));
    }
    out
}

fn string(c: &c3d::C3d, name: &str) -> Option<String> {
    let s = c.parameters.get_strings(GROUP, name)?.join(" ");
    let s = s.trim();
    (!s.is_empty()).then(|| s.to_string())
}

impl Record {
    /// The record of `c` (empty for a file c3dfix never repaired). Rows that name no point
    /// of the file or frames outside it are ignored: a record edited by hand can make a
    /// rerun do more work, never write outside the data.
    pub fn read(c: &c3d::C3d) -> Record {
        let (points, frames) = (c.point_count(), c.frames());
        let first_frame = c.first_frame() as f64;
        // Point number and frame numbers to indices, if inside the file.
        let place = |row: &[f32]| -> Option<(usize, usize, usize)> {
            let p = row[0] as f64;
            let (a, b) = (row[1] as f64 - first_frame, row[2] as f64 - first_frame);
            let ok = p >= 1.0 && p <= points as f64 && a >= 0.0 && a <= b && b < frames as f64;
            ok.then(|| (p as usize - 1, a as usize, b as usize))
        };
        let filled = rows(c, "FILLED", 3)
            .iter()
            .filter_map(|r| place(r))
            .collect();
        let left = rows(c, "LEFT", 6)
            .iter()
            .filter_map(|r| {
                let (point, first, last) = place(r)?;
                Some(Left {
                    point,
                    first_index: first,
                    last_index: last,
                    reason: reason_of(r[3], r[4], r[5])?,
                })
            })
            .collect();
        let undone = rows(c, "UNDONE", 4)
            .iter()
            .filter_map(|r| {
                let (a, first, last) = place(&[r[0], r[2], r[3]])?;
                let mut points = vec![a];
                if r[1] != 0.0 {
                    points.push(place(&[r[1], r[2], r[3]])?.0);
                }
                Some(Undone {
                    points,
                    first,
                    last,
                })
            })
            .collect();
        let reclaimed = rows(c, "RECLAIMED", 4)
            .iter()
            .filter_map(|r| {
                let (point, first, last) = place(&[r[0], r[2], r[3]])?;
                let (source, _, _) = place(&[r[1], r[2], r[3]])?;
                Some(Reclaimed {
                    point,
                    source,
                    first,
                    last,
                })
            })
            .collect();
        Record {
            filled,
            left,
            fill: string(c, "FILL"),
            filter: string(c, "FILTER"),
            spikes: string(c, "SPIKES"),
            swaps: string(c, "SWAPS"),
            undone,
            reclaim: string(c, "RECLAIM"),
            reclaimed,
        }
    }

    /// The record's stretches as the file stores them, row after row: points numbered from
    /// 1, frames in the file's numbering (from `first_frame`).
    fn tables(&self, first_frame: f32) -> Tables {
        let filled: Vec<[f32; 3]> = self
            .filled
            .iter()
            .map(|&(p, a, b)| {
                [
                    (p + 1) as f32,
                    a as f32 + first_frame,
                    b as f32 + first_frame,
                ]
            })
            .collect();
        let left: Vec<[f32; 6]> = self
            .left
            .iter()
            .map(|l| {
                let r = reason_code(l.reason);
                [
                    (l.point + 1) as f32,
                    l.first_index as f32 + first_frame,
                    l.last_index as f32 + first_frame,
                    r[0],
                    r[1],
                    r[2],
                ]
            })
            .collect();
        let undone: Vec<[f32; 4]> = self
            .undone
            .iter()
            .map(|u| {
                let point = |k: usize| u.points.get(k).map_or(0.0, |&p| (p + 1) as f32);
                [
                    point(0),
                    point(1),
                    u.first as f32 + first_frame,
                    u.last as f32 + first_frame,
                ]
            })
            .collect();
        let reclaimed: Vec<[f32; 4]> = self
            .reclaimed
            .iter()
            .map(|r| {
                [
                    (r.point + 1) as f32,
                    (r.source + 1) as f32,
                    r.first as f32 + first_frame,
                    r.last as f32 + first_frame,
                ]
            })
            .collect();
        Tables {
            filled: filled.concat(),
            left: left.concat(),
            undone: undone.concat(),
            reclaimed: reclaimed.concat(),
        }
    }

    /// Write the record into `c`'s parameters. A parameter whose value is unchanged keeps its
    /// bytes, so a rerun that changes nothing writes the file it read.
    pub fn write(&self, c: &mut c3d::C3d) -> c3d::Result<()> {
        let Tables {
            filled,
            left,
            undone,
            reclaimed,
        } = self.tables(c.first_frame() as f32);
        let ps = &mut c.parameters;
        if reclaimed.is_empty() {
            remove_rows(ps, "RECLAIMED");
        } else {
            set_rows(
                ps,
                "RECLAIMED",
                &reclaimed,
                4,
                "recorded samples moved from unlabelled points: marker point number, unlabelled point number, first frame, last frame",
            )?;
        }
        set_string(
            ps,
            "RECLAIM",
            self.reclaim.as_deref(),
            "reclaim stage c3dfix applied",
        )?;
        if undone.is_empty() {
            remove_rows(ps, "UNDONE");
        } else {
            set_rows(
                ps,
                "UNDONE",
                &undone,
                4,
                "label swaps undone: point numbers (second 0 for a jump), first frame, last frame",
            )?;
        }
        set_rows(
            ps,
            "FILLED",
            &filled,
            3,
            "stretches c3dfix filled: point number, first frame, last frame",
        )?;
        set_rows(
            ps,
            "LEFT",
            &left,
            6,
            "gaps c3dfix left: point number, first frame, last frame, reason code, values",
        )?;
        set_string(
            ps,
            "FILL",
            self.fill.as_deref(),
            "fill settings LEFT was judged under",
        )?;
        set_string(
            ps,
            "FILTER",
            self.filter.as_deref(),
            "low-pass filter c3dfix applied",
        )?;
        set_string(
            ps,
            "SPIKES",
            self.spikes.as_deref(),
            "spike removal c3dfix applied",
        )?;
        set_string(
            ps,
            "SWAPS",
            self.swaps.as_deref(),
            "label swap stage c3dfix applied",
        )?;
        for r in &mut ps.records {
            if let c3d::Record::Group(g) = r {
                if g.name == GROUP && g.description.is_empty() {
                    g.description = "what c3dfix repair did (docs/reruns.md)".into();
                }
            }
        }
        Ok(())
    }
}

/// A record's stretches as the rows of its parameters, one row after another.
struct Tables {
    filled: Vec<f32>,
    left: Vec<f32>,
    undone: Vec<f32>,
    reclaimed: Vec<f32>,
}

/// The dimensions of `rows` rows of `cols`: `[cols, rows]`, or further dimensions of 255
/// when there are more than 255 rows (padded with rows of zeros).
fn dims_for(cols: usize, rows: usize) -> Vec<u8> {
    let mut dims = vec![cols as u8];
    let mut m = rows;
    while m > 255 {
        dims.push(255);
        m = m.div_ceil(255);
    }
    dims.push(m as u8);
    dims
}

pub(crate) fn set_rows(
    ps: &mut c3d::Parameters,
    name: &str,
    values: &[f32],
    cols: usize,
    what: &str,
) -> c3d::Result<()> {
    let chunks: Vec<&[f32]> = values.chunks(rows_per_part(cols) * cols).collect();
    for (k, chunk) in chunks.iter().enumerate() {
        let dims = dims_for(cols, chunk.len() / cols);
        let total: usize = dims.iter().map(|&d| d as usize).product();
        let mut v = chunk.to_vec();
        v.resize(total, 0.0);
        let n = part(name, k);
        ps.set(GROUP, &n, dims, c3d::Value::Float(v))?;
        describe(ps, &n, what);
    }
    // Continuations an earlier, longer record left.
    for k in chunks.len().. {
        if !ps.remove(GROUP, &part(name, k)) {
            break;
        }
    }
    Ok(())
}

/// Remove `GROUP:name` and its continuations: a record of no rows is no parameter, so a
/// repair that undid nothing adds none.
fn remove_rows(ps: &mut c3d::Parameters, name: &str) {
    for k in 0.. {
        if !ps.remove(GROUP, &part(name, k)) {
            break;
        }
    }
}

fn set_string(
    ps: &mut c3d::Parameters,
    name: &str,
    s: Option<&str>,
    what: &str,
) -> c3d::Result<()> {
    match s {
        None => {
            ps.remove(GROUP, name);
        }
        Some(s) => {
            // One char dimension holds 255 characters at most.
            let s: String = s.chars().take(255).collect();
            ps.set_strings(GROUP, name, &[s])?;
            describe(ps, name, what);
        }
    }
    Ok(())
}

fn describe(ps: &mut c3d::Parameters, name: &str, what: &str) {
    if let Some(p) = ps.get_mut(GROUP, name) {
        if p.description.is_empty() {
            p.description = what.into();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parts_stay_under_a_record() {
        assert_eq!(rows_per_part(3), 2295);
        assert_eq!(rows_per_part(6), 1020);
        assert_eq!(rows_per_part(4), 1785);
        assert!(rows_per_part(6) * 6 * 4 < 30_000 && rows_per_part(3) * 3 * 4 < 30_000);
        assert_eq!(part("FILLED", 1), "FILLED2");
    }

    #[test]
    fn dims_grow_by_255() {
        assert_eq!(dims_for(3, 10), vec![3, 10]);
        assert_eq!(dims_for(3, 255), vec![3, 255]);
        assert_eq!(dims_for(3, 256), vec![3, 255, 2]);
        assert_eq!(dims_for(6, 70_000), vec![6, 255, 255, 2]);
    }

    #[test]
    fn every_reason_reads_back() {
        let all = [
            SkipReason::MethodNone,
            SkipReason::TooLong { max_gap: 200 },
            SkipReason::TouchesEdge,
            SkipReason::NoDonors,
            SkipReason::NoContext,
            SkipReason::Degenerate,
            SkipReason::Implausible { step_ratio: 2.5 },
            SkipReason::Uncertain {
                expected_error: 71.25,
                max_expected_error: 20.0,
            },
        ];
        for r in all {
            let [c, a, b] = reason_code(r);
            assert_eq!(reason_of(c, a, b), Some(r));
        }
    }
}
