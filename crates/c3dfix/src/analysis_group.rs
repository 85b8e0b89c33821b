//! Writing gait-cycle parameters into the ANALYSIS group as Vicon Nexus writes it: USED,
//! NAMES, SUBJECTS, CONTEXTS, UNITS, DESCRIPTIONS, VALUES, in that order, strings of
//! Nexus' widths (32, 32, 16, 12, 48 characters, wider when a value needs it), VALUES as
//! floats, read from the Nexus files of the corpora (`sample_11/2198928.c3d`,
//! `HansUniVie__MuscleLength__test.c3d`): one row per value, Left's then Right's.
//!
//! Rows of the file with another name or context (another program's values) are kept;
//! rows with the same context and name as ours are replaced. Only parameter records
//! change: the c3d crate's patched writing keeps every other byte of the file.

use crate::error::{Error, Result};
use c3d::{C3d, Value};
use gait::params::Parameter;

/// Nexus' string widths: NAMES, SUBJECTS, CONTEXTS, UNITS, DESCRIPTIONS.
const WIDTHS: [(&str, usize); 5] = [
    ("NAMES", 32),
    ("SUBJECTS", 32),
    ("CONTEXTS", 16),
    ("UNITS", 12),
    ("DESCRIPTIONS", 48),
];

/// One row: name, subject, context, unit, description (in [`WIDTHS`]' order) and value.
#[derive(Debug, Clone, PartialEq)]
struct Row {
    text: [String; 5],
    value: f32,
}

fn existing(c: &C3d) -> Vec<Row> {
    let ps = &c.parameters;
    let values = ps
        .get("ANALYSIS", "VALUES")
        .map(|p| p.as_f32s())
        .unwrap_or_default();
    let used = ps
        .get_i32("ANALYSIS", "USED")
        .map_or(values.len(), |u| (u.max(0) as usize).min(values.len()));
    let cols: Vec<Vec<String>> = WIDTHS
        .iter()
        .map(|(name, _)| ps.get_strings("ANALYSIS", name).unwrap_or_default())
        .collect();
    (0..used)
        .map(|i| Row {
            text: std::array::from_fn(|k| {
                cols[k]
                    .get(i)
                    .map(|s| s.trim_end().to_string())
                    .unwrap_or_default()
            }),
            value: values[i],
        })
        .collect()
}

fn set(c: &mut C3d, name: &str, dims: Vec<u8>, v: Value) -> Result<()> {
    c.parameters
        .set("ANALYSIS", name, dims, v)
        .map_err(|e| Error::options(format!("ANALYSIS:{name}: {e}")))
}

/// What [`write_parameters`] did.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
pub struct Written {
    /// Rows written (ours).
    pub added: usize,
    /// The file's rows of the same context and name, replaced.
    pub replaced: usize,
    /// Rows the group holds now.
    pub total: usize,
}

/// Write `params` into the ANALYSIS group of `c` (see the module's documentation), with the
/// trial's subject (SUBJECTS:NAMES, else the subject of the file's first row, else none).
pub fn write_parameters(c: &mut C3d, params: &[Parameter]) -> Result<Written> {
    let mut rows = existing(c);
    let before = rows.len();
    let ours = |r: &Row| {
        params.iter().any(|p| {
            r.text[0].trim().eq_ignore_ascii_case(p.name)
                && r.text[2].trim().eq_ignore_ascii_case(p.context)
        })
    };
    rows.retain(|r| !ours(r));
    let replaced = before - rows.len();
    let subject = c
        .parameters
        .get_strings("SUBJECTS", "NAMES")
        .and_then(|v| v.first().map(|s| s.trim().to_string()))
        .or_else(|| rows.first().map(|r| r.text[1].clone()))
        .unwrap_or_default();
    for p in params {
        rows.push(Row {
            text: [
                p.name.to_string(),
                subject.clone(),
                p.context.to_string(),
                p.unit.to_string(),
                String::new(),
            ],
            value: p.value as f32,
        });
    }
    let n = rows.len();
    let n8 = u8::try_from(n)
        .map_err(|_| Error::options(format!("{n} values; the ANALYSIS group holds at most 255")))?;
    set(c, "USED", vec![], Value::Int(vec![n as i16]))?;
    for (k, (name, min)) in WIDTHS.iter().enumerate() {
        let width = rows
            .iter()
            .map(|r| r.text[k].len())
            .max()
            .unwrap_or(0)
            .max(*min);
        let w8 = u8::try_from(width).map_err(|_| {
            Error::options(format!("ANALYSIS:{name}: a string longer than 255 bytes"))
        })?;
        let mut bytes = Vec::with_capacity(width * n);
        for r in &rows {
            let mut b = r.text[k].as_bytes().to_vec();
            b.resize(width, b' ');
            bytes.extend_from_slice(&b);
        }
        set(c, name, vec![w8, n8], Value::Char(bytes))?;
    }
    set(
        c,
        "VALUES",
        vec![n8],
        Value::Float(rows.iter().map(|r| r.value).collect()),
    )?;
    Ok(Written {
        added: params.len(),
        replaced,
        total: n,
    })
}
