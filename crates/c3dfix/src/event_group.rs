//! Writing detected events into the EVENT group as Vicon Nexus writes it: USED, CONTEXTS,
//! LABELS, DESCRIPTIONS, SUBJECTS, TIMES as [minutes, seconds], ICON_IDS and GENERIC_FLAGS,
//! with Nexus' string widths (16, 32, 80, 32 characters) and icon numbers (1 Foot Strike,
//! 2 Foot Off), read from Nexus files of the corpora (`sample_11/2198928.c3d`). EVENT_CONTEXT
//! is created as Nexus creates it (Left, Right, General) when absent, and given any missing
//! context when present.
//!
//! Only parameter records change; the c3d crate's patched writing keeps every other byte of
//! the file (the data section moves only when the parameter section outgrows its blocks).
//! The header's own 18-event block is left as the file has it: Nexus keeps gait events in
//! the EVENT group only, and the header block is an older, separate list.

use crate::error::{Error, Result};
use crate::events::TrialEvent;
use c3d::{C3d, Value};

/// Nexus' descriptions of its gait events.
const STRIKE_DESCRIPTION: &str =
    "The moment any part of the foot first contacts the floor during a gait cycle.";
const OFF_DESCRIPTION: &str =
    "The moment the foot ceases all contact with the floor during a gait cycle.";

/// One row of the EVENT group.
#[derive(Debug, Clone, PartialEq)]
struct Row {
    context: String,
    label: String,
    description: String,
    subject: String,
    /// [minutes, seconds].
    time: [f32; 2],
    icon: i16,
    flag: i16,
}

/// A row `replace` removes: a Foot Strike or Foot Off in any context, or any gait event as
/// labs label them ([`crate::event_labels::gait_event`]: `LHS` in General, …).
fn is_gait(context: &str, label: &str) -> bool {
    let l = label.trim();
    l.eq_ignore_ascii_case("Foot Strike")
        || l.eq_ignore_ascii_case("Foot Off")
        || crate::event_labels::gait_event(context, label).is_some()
}

/// The rows the file has (as many as EVENT:USED says, or as TIMES holds).
fn existing(c: &C3d) -> Vec<Row> {
    let ps = &c.parameters;
    let times = ps
        .get("EVENT", "TIMES")
        .map(|p| p.as_f32s())
        .unwrap_or_default();
    let pairs = times.len() / 2;
    let used = ps
        .get_i32("EVENT", "USED")
        .map_or(pairs, |u| (u.max(0) as usize).min(pairs));
    let strings = |name: &str| ps.get_strings("EVENT", name).unwrap_or_default();
    let ints = |name: &str| -> Vec<i16> {
        ps.get("EVENT", name)
            .map(|p| p.as_f32s().iter().map(|v| *v as i16).collect())
            .unwrap_or_default()
    };
    let (contexts, labels, descriptions, subjects) = (
        strings("CONTEXTS"),
        strings("LABELS"),
        strings("DESCRIPTIONS"),
        strings("SUBJECTS"),
    );
    let (icons, flags) = (ints("ICON_IDS"), ints("GENERIC_FLAGS"));
    let at = |v: &[String], i: usize| {
        v.get(i)
            .map(|s| s.trim_end().to_string())
            .unwrap_or_default()
    };
    (0..used)
        .map(|i| Row {
            context: at(&contexts, i),
            label: at(&labels, i),
            description: at(&descriptions, i),
            subject: at(&subjects, i),
            time: [times[2 * i], times[2 * i + 1]],
            icon: icons.get(i).copied().unwrap_or(0),
            flag: flags.get(i).copied().unwrap_or(0),
        })
        .collect()
}

/// `strings` as `char[width][n]`, `width` at least `min` (Nexus' width) and the longest.
fn set_chars(c: &mut C3d, group: &str, name: &str, strings: &[String], min: usize) -> Result<()> {
    let width = strings.iter().map(|s| s.len()).max().unwrap_or(0).max(min);
    let width8 = u8::try_from(width)
        .map_err(|_| Error::options(format!("{group}:{name}: a string longer than 255 bytes")))?;
    let n = u8::try_from(strings.len()).map_err(|_| {
        Error::options(format!(
            "{group}:{name}: {} events; the EVENT group holds at most 255",
            strings.len()
        ))
    })?;
    let mut bytes = Vec::with_capacity(width * strings.len());
    for s in strings {
        let mut b = s.as_bytes().to_vec();
        b.resize(width, b' ');
        bytes.extend_from_slice(&b);
    }
    c.parameters
        .set(group, name, vec![width8, n], Value::Char(bytes))
        .map_err(|e| Error::options(format!("{group}:{name}: {e}")))
}

fn set(c: &mut C3d, group: &str, name: &str, dims: Vec<u8>, v: Value) -> Result<()> {
    c.parameters
        .set(group, name, dims, v)
        .map_err(|e| Error::options(format!("{group}:{name}: {e}")))
}

/// Small integers as the file's own EVENT:`name` stores them (bytes in some writers' files),
/// else as Nexus does (int16).
fn ints_as_file_has(c: &C3d, name: &str, v: Vec<i16>) -> Value {
    match c.parameters.get("EVENT", name).map(|p| &p.value) {
        Some(Value::Byte(_)) if v.iter().all(|x| (0..=255).contains(x)) => {
            Value::Byte(v.iter().map(|x| *x as u8).collect())
        }
        _ => Value::Int(v),
    }
}

/// What [`write_events`] did.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
pub struct Written {
    /// Events added.
    pub added: usize,
    /// The file's Foot Strike / Foot Off events removed (`replace`).
    pub removed: usize,
    /// Events the group holds now.
    pub total: usize,
}

/// Add `events` to the EVENT group of `c` (after the file's own events, which are kept
/// unless `replace`, when its Foot Strike and Foot Off events are removed and its other
/// events kept). New events carry the trial's subject (SUBJECTS:NAMES, else the subject of
/// the file's first event, else none).
pub fn write_events(c: &mut C3d, events: &[TrialEvent], replace: bool) -> Result<Written> {
    let mut rows = existing(c);
    let before = rows.len();
    if replace {
        rows.retain(|r| !is_gait(&r.context, &r.label));
    }
    let removed = before - rows.len();
    let subject = c
        .parameters
        .get_strings("SUBJECTS", "NAMES")
        .and_then(|v| v.first().map(|s| s.trim().to_string()))
        .or_else(|| rows.first().map(|r| r.subject.clone()))
        .unwrap_or_default();
    for e in events {
        let minutes = (e.time / 60.0).floor().max(0.0);
        let strike = e.kind == gait::Kind::FootStrike;
        rows.push(Row {
            context: e.side.context().to_string(),
            label: e.kind.label().to_string(),
            description: if strike {
                STRIKE_DESCRIPTION
            } else {
                OFF_DESCRIPTION
            }
            .to_string(),
            subject: subject.clone(),
            time: [minutes as f32, (e.time - 60.0 * minutes) as f32],
            icon: if strike { 1 } else { 2 },
            flag: 0,
        });
    }
    let n = rows.len();
    let n8 = u8::try_from(n)
        .map_err(|_| Error::options(format!("{n} events; the EVENT group holds at most 255")))?;
    let col = |f: fn(&Row) -> &String| rows.iter().map(|r| f(r).clone()).collect::<Vec<_>>();
    set(c, "EVENT", "USED", vec![], Value::Int(vec![n as i16]))?;
    set_chars(c, "EVENT", "CONTEXTS", &col(|r| &r.context), 16)?;
    let icons = ints_as_file_has(c, "ICON_IDS", rows.iter().map(|r| r.icon).collect());
    set(c, "EVENT", "ICON_IDS", vec![n8], icons)?;
    set_chars(c, "EVENT", "LABELS", &col(|r| &r.label), 32)?;
    set_chars(c, "EVENT", "DESCRIPTIONS", &col(|r| &r.description), 80)?;
    set_chars(c, "EVENT", "SUBJECTS", &col(|r| &r.subject), 32)?;
    set(
        c,
        "EVENT",
        "TIMES",
        vec![2, n8],
        Value::Float(rows.iter().flat_map(|r| r.time).collect()),
    )?;
    let flags = ints_as_file_has(c, "GENERIC_FLAGS", rows.iter().map(|r| r.flag).collect());
    set(c, "EVENT", "GENERIC_FLAGS", vec![n8], flags)?;
    event_context(c, &rows)?;
    Ok(Written {
        added: events.len(),
        removed,
        total: n,
    })
}

/// EVENT_CONTEXT as Nexus writes it, or the file's with any missing context of `rows` added.
fn event_context(c: &mut C3d, rows: &[Row]) -> Result<()> {
    let mut labels: Vec<String> = c
        .parameters
        .get_strings("EVENT_CONTEXT", "LABELS")
        .unwrap_or_default()
        .into_iter()
        .map(|s| s.trim_end().to_string())
        .collect();
    let fresh = labels.is_empty();
    let mut descriptions: Vec<String> = c
        .parameters
        .get_strings("EVENT_CONTEXT", "DESCRIPTIONS")
        .unwrap_or_default()
        .into_iter()
        .map(|s| s.trim_end().to_string())
        .collect();
    let mut icons: Vec<i16> = c
        .parameters
        .get("EVENT_CONTEXT", "ICON_IDS")
        .map(|p| p.as_f32s().iter().map(|v| *v as i16).collect())
        .unwrap_or_default();
    let mut colours: Vec<i16> = c
        .parameters
        .get("EVENT_CONTEXT", "COLOURS")
        .map(|p| p.as_f32s().iter().map(|v| *v as i16).collect())
        .unwrap_or_default();
    // Nexus' contexts: red left, green right, blue general.
    let nexus = [
        ("Left", "Left side", [192, 0, 0]),
        ("Right", "Right side", [0, 192, 0]),
        ("General", "For other events", [0, 0, 192]),
    ];
    let wanted: Vec<&str> = if fresh {
        nexus.iter().map(|n| n.0).collect()
    } else {
        rows.iter().map(|r| r.context.as_str()).collect()
    };
    let mut changed = fresh;
    descriptions.resize(labels.len(), String::new());
    icons.resize(labels.len(), 0);
    colours.resize(3 * labels.len(), 0);
    for w in wanted {
        if w.is_empty() || labels.iter().any(|l| l.eq_ignore_ascii_case(w)) {
            continue;
        }
        let (desc, colour) = nexus
            .iter()
            .find(|n| n.0.eq_ignore_ascii_case(w))
            .map_or((String::new(), [0, 0, 0]), |n| (n.1.to_string(), n.2));
        labels.push(w.to_string());
        descriptions.push(desc);
        icons.push(0);
        colours.extend_from_slice(&colour);
        changed = true;
    }
    if !changed {
        return Ok(());
    }
    let n = labels.len();
    let n8 =
        u8::try_from(n).map_err(|_| Error::options("EVENT_CONTEXT: more than 255 contexts"))?;
    set(
        c,
        "EVENT_CONTEXT",
        "USED",
        vec![],
        Value::Int(vec![n as i16]),
    )?;
    set(c, "EVENT_CONTEXT", "ICON_IDS", vec![n8], Value::Int(icons))?;
    set_chars(c, "EVENT_CONTEXT", "LABELS", &labels, 16)?;
    set_chars(c, "EVENT_CONTEXT", "DESCRIPTIONS", &descriptions, 32)?;
    set(
        c,
        "EVENT_CONTEXT",
        "COLOURS",
        vec![3, n8],
        Value::Int(colours),
    )
}
