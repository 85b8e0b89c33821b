//! Comparing two C3D files: header fields, parameters (added, removed, changed, reordered,
//! locked and description changes), point data per marker and analog data per channel.

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
    /// First and last changed frame (0-based).
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

/// Compare `a` with `b`. Coordinates within `tolerance` (POINT:UNITS) count as equal; analog
/// values are compared exactly in raw units and reported in physical ones.
pub fn diff(a: &C3d, b: &C3d, tolerance: f64) -> Diff {
    let mut d = Diff::default();
    let field = |f: &str, x: String, y: String| FieldChange {
        field: f.into(),
        a: x,
        b: y,
    };
    if a.processor() != b.processor() {
        d.format.push(field(
            "processor",
            a.processor().name().into(),
            b.processor().name().into(),
        ));
    }
    if a.format() != b.format() {
        d.format.push(field(
            "number format",
            a.format().name().into(),
            b.format().name().into(),
        ));
    }
    header_diff(a, b, &mut d.header);
    param_diff(a, b, &mut d);
    d.points = points_diff(a, b, tolerance);
    d.analog = analog_diff(a, b);
    d
}

fn header_diff(a: &C3d, b: &C3d, out: &mut Vec<FieldChange>) {
    let (Ok(serde_json::Value::Object(x)), Ok(serde_json::Value::Object(y))) = (
        serde_json::to_value(&a.header),
        serde_json::to_value(&b.header),
    ) else {
        return;
    };
    for (k, va) in &x {
        let vb = y.get(k).cloned().unwrap_or(serde_json::Value::Null);
        if *va != vb {
            out.push(FieldChange {
                field: k.clone(),
                a: va.to_string(),
                b: vb.to_string(),
            });
        }
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

fn param_diff(a: &C3d, b: &C3d, d: &mut Diff) {
    let (ka, kb) = (keys(a), keys(b));
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
    for (i, (name, ra)) in ka.iter().enumerate() {
        let Some(rb) = pairs[i].map(|j| kb[j].1) else {
            d.parameters.push(ch(name, "removed", None, None));
            continue;
        };
        match (ra, rb) {
            (Record::Group(x), Record::Group(y)) => {
                if x.locked != y.locked {
                    d.parameters.push(ch(
                        name,
                        "locked",
                        Some(x.locked.to_string()),
                        Some(y.locked.to_string()),
                    ));
                }
                if x.description != y.description {
                    d.parameters.push(ch(
                        name,
                        "description",
                        Some(x.description.clone()),
                        Some(y.description.clone()),
                    ));
                }
            }
            (Record::Parameter(x), Record::Parameter(y)) => {
                if x.value.type_name() != y.value.type_name() {
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
                let same_value = match (&x.value, &y.value) {
                    (crate::parameters::Value::Float(p), crate::parameters::Value::Float(q)) => {
                        p.len() == q.len()
                            && p.iter().zip(q).all(|(u, v)| u.to_bits() == v.to_bits())
                    }
                    (p, q) => p == q,
                };
                if !same_value {
                    d.parameters
                        .push(ch(name, "value", Some(show_value(x)), Some(show_value(y))));
                }
                if x.locked != y.locked {
                    d.parameters.push(ch(
                        name,
                        "locked",
                        Some(x.locked.to_string()),
                        Some(y.locked.to_string()),
                    ));
                }
                if x.description != y.description {
                    d.parameters.push(ch(
                        name,
                        "description",
                        Some(x.description.clone()),
                        Some(y.description.clone()),
                    ));
                }
            }
            _ => d.parameters.push(ch(name, "type", None, None)),
        }
    }
    for name in unmatched(&names_b, &pairs) {
        d.parameters.push(ch(&name, "added", None, None));
    }
    // Reordered: the matched records of `b`, taken in `a`'s order, are not ascending.
    let order: Vec<usize> = pairs.iter().flatten().copied().collect();
    d.parameters_reordered = order.windows(2).any(|w| w[0] > w[1]);
}

fn points_diff(a: &C3d, b: &C3d, tol: f64) -> PointsDiff {
    let mut out = PointsDiff::default();
    let (pa, pb) = (a.points(), b.points());
    if pa.frames() != pb.frames() {
        out.frames = Some((pa.frames(), pb.frames()));
    }
    let (la, lb) = (a.point_labels(), b.point_labels());
    let frames = pa.frames().min(pb.frames());
    let pairs = match_labels(&la, &lb);
    for (i, label) in la.iter().enumerate() {
        let Some(j) = pairs[i] else {
            out.only_in_a.push(label.clone());
            continue;
        };
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
                let flags = pa.residual[ka].to_bits() != pb.residual[kb].to_bits()
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
                m.first_frame.get_or_insert(f);
                m.last_frame = Some(f);
            }
        }
        if m.frames_changed > 0 {
            out.markers.push(m);
        }
    }
    out.only_in_b = unmatched(&lb, &pairs);
    out
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
    let pairs = match_labels(&la, &lb);
    for (i, label) in la.iter().enumerate() {
        let Some(j) = pairs[i] else {
            out.only_in_a.push(label.clone());
            continue;
        };
        let mut c = ChannelDiff {
            label: label.clone(),
            samples_changed: 0,
            max_difference: 0.0,
        };
        for s in 0..n {
            let x = ca.physical(i, aa.raw[s * aa.channels() + i]) as f64;
            let y = cb.physical(j, ab.raw[s * ab.channels() + j]) as f64;
            if x.to_bits() != y.to_bits() {
                c.samples_changed += 1;
                c.max_difference = c.max_difference.max((x - y).abs());
            }
        }
        if c.samples_changed > 0 {
            out.channels.push(c);
        }
    }
    out.only_in_b = unmatched(&lb, &pairs);
    out
}
