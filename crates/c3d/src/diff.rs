//! Comparing two C3D files: header fields, parameters (added, removed, changed, reordered,
//! locked and description changes), point data per marker and analog data per channel.
//!
//! Values are compared as numbers, never as bits: −0.0 and +0.0 are the same coordinate (a
//! DEC round trip turns one into the other), and two NaN are the same missing value. With
//! [`DiffOptions::data`] only what the data mean is compared, not how they are laid out: see
//! [`LAYOUT_PARAMETERS`] and [`diff_with`].

use crate::file::C3d;
use crate::parameters::Record;
use serde::Serialize;

/// How two files differ. Empty lists everywhere means "the same" (see [`Diff::is_empty`]).
#[derive(Debug, Clone, Default, Serialize)]
pub struct Diff {
    pub format: Vec<FieldChange>,
    pub header: Vec<FieldChange>,
    pub parameters: Vec<ParamChange>,
    /// Parameters present in both files but in another order.
    pub parameters_reordered: bool,
    pub points: PointsDiff,
    pub analog: AnalogDiff,
}

#[derive(Debug, Clone, Serialize)]
pub struct FieldChange {
    pub field: String,
    pub a: String,
    pub b: String,
}

#[derive(Debug, Clone, Serialize)]
pub struct ParamChange {
    /// `GROUP` or `GROUP:PARAMETER`.
    pub name: String,
    /// "added", "removed", "value", "dimensions", "type", "locked", "description".
    pub change: String,
    pub a: Option<String>,
    pub b: Option<String>,
}

#[derive(Debug, Clone, Default, Serialize)]
pub struct PointsDiff {
    /// Frame counts when they differ.
    pub frames: Option<(usize, usize)>,
    pub only_in_a: Vec<String>,
    pub only_in_b: Vec<String>,
    pub markers: Vec<MarkerDiff>,
}

/// One marker present in both files whose samples differ.
#[derive(Debug, Clone, Serialize)]
pub struct MarkerDiff {
    pub label: String,
    /// Frames where the coordinates moved by more than the tolerance, or validity, residual
    /// or camera mask changed.
    pub frames_changed: usize,
    /// Largest 3D displacement between samples valid in both, in POINT:UNITS.
    pub max_displacement: f64,
    /// First and last changed frame, numbered as the first file numbers them
    /// ([`C3d::frame_number`]).
    pub first_frame: Option<usize>,
    pub last_frame: Option<usize>,
    pub became_valid: usize,
    pub became_invalid: usize,
    /// Frames whose residual or camera mask changed while validity did not.
    pub flags_changed: usize,
}

#[derive(Debug, Clone, Default, Serialize)]
pub struct AnalogDiff {
    /// Sample counts when they differ.
    pub samples: Option<(usize, usize)>,
    pub only_in_a: Vec<String>,
    pub only_in_b: Vec<String>,
    pub channels: Vec<ChannelDiff>,
}

#[derive(Debug, Clone, Serialize)]
pub struct ChannelDiff {
    pub label: String,
    pub samples_changed: usize,
    /// Largest difference in physical units.
    pub max_difference: f64,
}

impl Diff {
    pub fn is_empty(&self) -> bool {
        self.format.is_empty()
            && self.header.is_empty()
            && self.parameters.is_empty()
            && !self.parameters_reordered
            && self.points.frames.is_none()
            && self.points.only_in_a.is_empty()
            && self.points.only_in_b.is_empty()
            && self.points.markers.is_empty()
            && self.analog.samples.is_none()
            && self.analog.only_in_a.is_empty()
            && self.analog.only_in_b.is_empty()
            && self.analog.channels.is_empty()
    }
}

/// How to compare.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct DiffOptions {
    /// Coordinates closer than this (POINT:UNITS) count as equal.
    pub tolerance: f64,
    /// Compare the data only (points, their validity, residuals and camera masks, analog
    /// values in physical units, labels, every parameter that carries meaning, the header's
    /// frames, rate and events), not the layout a conversion may legitimately move: the
    /// processor and number format, POINT:SCALE, where the sections start and how many
    /// blocks they take ([`LAYOUT_PARAMETERS`]), the order of the parameter records.
    pub data: bool,
}

/// Parameters that say how the data are stored rather than what they are: a conversion
/// (processor, integer ⇄ float, another scale) rewrites them with the data unchanged.
/// ANALOG:OFFSET, SCALE, GEN_SCALE, FORMAT and BITS turn stored words into physical values;
/// the data comparison compares those values, so the words' encoding is layout.
pub const LAYOUT_PARAMETERS: [&str; 7] = [
    "POINT:DATA_START",
    "POINT:SCALE",
    "ANALOG:OFFSET",
    "ANALOG:SCALE",
    "ANALOG:GEN_SCALE",
    "ANALOG:FORMAT",
    "ANALOG:BITS",
];

/// Header fields that are layout (see [`DiffOptions::data`]): where the sections start,
/// the key byte, the label/range section and POINT:SCALE's copy. The analog words per frame
/// are compared as the analog data themselves (channels and samples).
const LAYOUT_HEADER: [&str; 8] = [
    "parameter_block",
    "key",
    "scale",
    "data_start",
    "label_range_key",
    "label_range_block",
    "analog_per_frame",
    "analog_samples_per_frame",
];

/// Parameters that restate what the data comparison compares by its effective value
/// (counts, frames, the first frame, the rate): a writer may add or drop them, as a
/// conversion adds POINT:FRAMES or POINT:RATE where a file had only the header's word.
/// As data they are compared through [`C3d::frames`], [`C3d::point_count`],
/// [`C3d::analog_channels`], [`C3d::first_frame`] and [`C3d::point_rate`].
const RESTATED: [&str; 7] = [
    "POINT:USED",
    "POINT:FRAMES",
    "POINT:LONG_FRAMES",
    "POINT:RATE",
    "ANALOG:USED",
    "TRIAL:ACTUAL_START_FIELD",
    "TRIAL:ACTUAL_END_FIELD",
];

/// Two numbers the same: equal as numbers (−0.0 = +0.0), or both NaN.
fn same_number(x: f64, y: f64) -> bool {
    x == y || (x.is_nan() && y.is_nan())
}

/// Compare `a` with `b`. Coordinates within `tolerance` (POINT:UNITS) count as equal; analog
/// values are compared exactly in physical units.
pub fn diff(a: &C3d, b: &C3d, tolerance: f64) -> Diff {
    diff_with(
        a,
        b,
        &DiffOptions {
            tolerance,
            data: false,
        },
    )
}

/// Compare `a` with `b` as `opts` says.
pub fn diff_with(a: &C3d, b: &C3d, opts: &DiffOptions) -> Diff {
    let mut d = Diff::default();
    let tolerance = opts.tolerance;
    let field = |f: &str, x: String, y: String| FieldChange {
        field: f.into(),
        a: x,
        b: y,
    };
    if !opts.data && a.processor() != b.processor() {
        d.format.push(field(
            "processor",
            a.processor().name().into(),
            b.processor().name().into(),
        ));
    }
    if !opts.data && a.format() != b.format() {
        d.format.push(field(
            "number format",
            a.format().name().into(),
            b.format().name().into(),
        ));
    }
    header_diff(a, b, &mut d.header, opts.data);
    if opts.data {
        let mut effective = |f: &str, x: String, y: String| {
            if x != y {
                d.header.push(field(f, x, y));
            }
        };
        effective(
            "first frame",
            a.first_frame().to_string(),
            b.first_frame().to_string(),
        );
        effective(
            "point rate",
            a.point_rate().to_string(),
            b.point_rate().to_string(),
        );
        effective(
            "analog channels",
            a.analog_channels().to_string(),
            b.analog_channels().to_string(),
        );
        effective(
            "analog rate",
            a.analog_rate().to_string(),
            b.analog_rate().to_string(),
        );
    }
    param_diff(a, b, &mut d, opts.data);
    d.points = points_diff(a, b, tolerance);
    d.analog = analog_diff(a, b);
    if opts.data && a.analog_channels() == 0 && b.analog_channels() == 0 {
        // No channel, no analog data, whatever samples per frame the header announced.
        d.analog.samples = None;
    }
    d
}

fn header_diff(a: &C3d, b: &C3d, out: &mut Vec<FieldChange>, data: bool) {
    let (Ok(serde_json::Value::Object(x)), Ok(serde_json::Value::Object(y))) = (
        serde_json::to_value(&a.header),
        serde_json::to_value(&b.header),
    ) else {
        return;
    };
    for (k, va) in &x {
        if data && LAYOUT_HEADER.contains(&k.as_str()) {
            continue;
        }
        let vb = y.get(k).cloned().unwrap_or(serde_json::Value::Null);
        if !same_json(va, &vb) {
            out.push(FieldChange {
                field: k.clone(),
                a: va.to_string(),
                b: vb.to_string(),
            });
        }
    }
}

/// `s` without the trailing spaces and NULs that pad C3D text.
fn padded(s: &str) -> &str {
    s.trim_end_matches([' ', '\0'])
}

/// JSON values equal, numbers as numbers (see [`same_number`]).
fn same_json(x: &serde_json::Value, y: &serde_json::Value) -> bool {
    use serde_json::Value as J;
    match (x, y) {
        (J::Number(p), J::Number(q)) => match (p.as_f64(), q.as_f64()) {
            (Some(u), Some(v)) => same_number(u, v),
            _ => p == q,
        },
        (J::Array(p), J::Array(q)) => {
            p.len() == q.len() && p.iter().zip(q).all(|(u, v)| same_json(u, v))
        }
        _ => x == y,
    }
}

/// A record's key: `GROUP` or `GROUP:NAME` (by group name, so renumbered groups still match).
fn keys(c: &C3d) -> Vec<(String, &Record)> {
    let group_name = |id: u8| {
        c.parameters
            .groups()
            .find(|g| g.id == id)
            .map_or_else(|| format!("#{id}"), |g| g.name.to_ascii_uppercase())
    };
    c.parameters
        .records
        .iter()
        .map(|r| match r {
            Record::Group(g) => (g.name.to_ascii_uppercase(), r),
            Record::Parameter(p) => (
                format!("{}:{}", group_name(p.group_id), p.name.to_ascii_uppercase()),
                r,
            ),
        })
        .collect()
}

fn show_value(p: &crate::parameters::Parameter) -> String {
    let s = match &p.value {
        crate::parameters::Value::Char(_) => format!("{:?}", p.as_strings()),
        _ => format!("{:?}", p.as_f32s()),
    };
    if s.chars().count() > 120 {
        let cut: String = s.chars().take(117).collect();
        format!("{cut}...")
    } else {
        s
    }
}

fn param_diff(a: &C3d, b: &C3d, d: &mut Diff, data: bool) {
    // As data, a group record says nothing beyond its name and description: one without a
    // description that a writer adds (or drops) for parameters it numbers is layout.
    let layout = |(n, r): &(String, &Record)| {
        !(data
            && (LAYOUT_PARAMETERS.contains(&n.as_str())
                || RESTATED.contains(&n.as_str())
                || matches!(r, Record::Group(g) if padded(&g.description).is_empty())))
    };
    // C3D pads text with spaces or NULs; as data the padding means nothing.
    let text = |s: &str| {
        if data {
            padded(s).to_string()
        } else {
            s.to_string()
        }
    };
    let (ka, kb): (Vec<_>, Vec<_>) = (
        keys(a).into_iter().filter(layout).collect(),
        keys(b).into_iter().filter(layout).collect(),
    );
    let names_a: Vec<String> = ka.iter().map(|(n, _)| n.clone()).collect();
    let names_b: Vec<String> = kb.iter().map(|(n, _)| n.clone()).collect();
    // Files may repeat a parameter: pair the k-th occurrences.
    let pairs = match_labels(&names_a, &names_b);
    let ch = |name: &str, change: &str, x: Option<String>, y: Option<String>| ParamChange {
        name: name.into(),
        change: change.into(),
        a: x,
        b: y,
    };
    // A group and a parameter are both locked or not and carry a description, compared alike:
    // (locked, description) of the record in `a`, then in `b`.
    let flags = |out: &mut Vec<ParamChange>, name: &str, x: (bool, &str), y: (bool, &str)| {
        if x.0 != y.0 {
            out.push(ch(
                name,
                "locked",
                Some(x.0.to_string()),
                Some(y.0.to_string()),
            ));
        }
        if text(x.1) != text(y.1) {
            out.push(ch(name, "description", Some(x.1.into()), Some(y.1.into())));
        }
    };
    for (i, (name, ra)) in ka.iter().enumerate() {
        let Some(rb) = pairs[i].map(|j| kb[j].1) else {
            d.parameters.push(ch(name, "removed", None, None));
            continue;
        };
        match (ra, rb) {
            (Record::Group(x), Record::Group(y)) => {
                flags(
                    &mut d.parameters,
                    name,
                    (x.locked, &x.description),
                    (y.locked, &y.description),
                );
            }
            (Record::Parameter(x), Record::Parameter(y)) => {
                let numeric =
                    |v: &crate::parameters::Value| !matches!(v, crate::parameters::Value::Char(_));
                // As data, a number is a number whatever its type (an integer file's
                // int16 may be a float's float).
                let as_numbers = data && numeric(&x.value) && numeric(&y.value);
                if x.value.type_name() != y.value.type_name() && !as_numbers {
                    d.parameters.push(ch(
                        name,
                        "type",
                        Some(x.value.type_name().into()),
                        Some(y.value.type_name().into()),
                    ));
                } else if x.dims != y.dims {
                    d.parameters.push(ch(
                        name,
                        "dimensions",
                        Some(format!("{:?}", x.dims)),
                        Some(format!("{:?}", y.dims)),
                    ));
                }
                let same_value = if numeric(&x.value)
                    && numeric(&y.value)
                    && (as_numbers || x.value.type_name() == y.value.type_name())
                {
                    let (u, v) = (x.as_f32s(), y.as_f32s());
                    u.len() == v.len()
                        && u.iter()
                            .zip(&v)
                            .all(|(s, t)| same_number(*s as f64, *t as f64))
                } else {
                    x.value == y.value
                };
                if !same_value {
                    d.parameters
                        .push(ch(name, "value", Some(show_value(x)), Some(show_value(y))));
                }
                flags(
                    &mut d.parameters,
                    name,
                    (x.locked, &x.description),
                    (y.locked, &y.description),
                );
            }
            _ => d.parameters.push(ch(name, "type", None, None)),
        }
    }
    for name in unmatched(&names_b, &pairs) {
        d.parameters.push(ch(&name, "added", None, None));
    }
    // Reordered: the matched records of `b`, taken in `a`'s order, are not ascending.
    let order: Vec<usize> = pairs.iter().flatten().copied().collect();
    d.parameters_reordered = !data && order.windows(2).any(|w| w[0] > w[1]);
}

fn points_diff(a: &C3d, b: &C3d, tol: f64) -> PointsDiff {
    let mut out = PointsDiff::default();
    let (pa, pb) = (a.points(), b.points());
    if pa.frames() != pb.frames() {
        out.frames = Some((pa.frames(), pb.frames()));
    }
    let (la, lb) = (a.point_labels(), b.point_labels());
    let frames = pa.frames().min(pb.frames());
    let found = per_label(&la, &lb, |i, j, label| {
        let mut m = MarkerDiff {
            label: label.clone(),
            frames_changed: 0,
            max_displacement: 0.0,
            first_frame: None,
            last_frame: None,
            became_valid: 0,
            became_invalid: 0,
            flags_changed: 0,
        };
        for f in 0..frames {
            let (ka, kb) = (pa.index(f, i), pb.index(f, j));
            let (va, vb) = (pa.is_valid_at(ka), pb.is_valid_at(kb));
            let mut changed = false;
            if va != vb {
                changed = true;
                if vb {
                    m.became_valid += 1;
                } else {
                    m.became_invalid += 1;
                }
            }
            if va && vb {
                let (x, y) = (pa.xyz[ka], pb.xyz[kb]);
                let dist = (0..3)
                    .map(|k| (x[k] as f64 - y[k] as f64).powi(2))
                    .sum::<f64>()
                    .sqrt();
                m.max_displacement = m.max_displacement.max(dist);
                let flags = !same_number(pa.residual[ka] as f64, pb.residual[kb] as f64)
                    || pa.camera_mask[ka] != pb.camera_mask[kb];
                if dist > tol {
                    changed = true;
                } else if flags {
                    changed = true;
                    m.flags_changed += 1;
                }
            }
            if changed {
                m.frames_changed += 1;
                m.first_frame.get_or_insert(a.frame_number(f));
                m.last_frame = Some(a.frame_number(f));
            }
        }
        (m.frames_changed > 0).then_some(m)
    });
    (out.only_in_a, out.markers, out.only_in_b) = found;
    out
}

/// The labels of `a` paired with those of `b` (see [`match_labels`]), as points and analog
/// channels are compared alike: `compare(i, j, label)` judges the pair of `a`'s i-th and
/// `b`'s j-th and says what changed, if anything. Returns the labels only in `a`, the
/// changes (both in `a`'s order) and the labels only in `b`.
fn per_label<T>(
    la: &[String],
    lb: &[String],
    mut compare: impl FnMut(usize, usize, &String) -> Option<T>,
) -> (Vec<String>, Vec<T>, Vec<String>) {
    let pairs = match_labels(la, lb);
    let mut only_in_a = Vec::new();
    let mut changed = Vec::new();
    for (i, label) in la.iter().enumerate() {
        match pairs[i] {
            None => only_in_a.push(label.clone()),
            Some(j) => changed.extend(compare(i, j, label)),
        }
    }
    (only_in_a, changed, unmatched(lb, &pairs))
}

/// Pair labels of `a` with labels of `b`: the k-th occurrence of a label in `a` with its k-th
/// occurrence in `b` (files may repeat labels, and blank ones are common).
fn match_labels(a: &[String], b: &[String]) -> Vec<Option<usize>> {
    a.iter()
        .enumerate()
        .map(|(i, l)| {
            let k = a[..i].iter().filter(|x| *x == l).count();
            b.iter()
                .enumerate()
                .filter(|(_, x)| *x == l)
                .nth(k)
                .map(|(j, _)| j)
        })
        .collect()
}

fn unmatched(b: &[String], pairs: &[Option<usize>]) -> Vec<String> {
    (0..b.len())
        .filter(|j| !pairs.contains(&Some(*j)))
        .map(|j| b[j].clone())
        .collect()
}

fn analog_diff(a: &C3d, b: &C3d) -> AnalogDiff {
    let mut out = AnalogDiff::default();
    let (aa, ab) = (a.analog(), b.analog());
    if aa.samples() != ab.samples() {
        out.samples = Some((aa.samples(), ab.samples()));
    }
    let (la, lb) = (a.analog_labels(), b.analog_labels());
    let (ca, cb) = (a.analog_calibration(), b.analog_calibration());
    let n = aa.samples().min(ab.samples());
    let found = per_label(&la, &lb, |i, j, label| {
        let mut c = ChannelDiff {
            label: label.clone(),
            samples_changed: 0,
            max_difference: 0.0,
        };
        for s in 0..n {
            let x = ca.physical(i, aa.raw[s * aa.channels() + i]) as f64;
            let y = cb.physical(j, ab.raw[s * ab.channels() + j]) as f64;
            if !same_number(x, y) {
                c.samples_changed += 1;
                c.max_difference = c.max_difference.max((x - y).abs());
            }
        }
        (c.samples_changed > 0).then_some(c)
    });
    (out.only_in_a, out.channels, out.only_in_b) = found;
    out
}
