//! Rules of the format checked after reading: what a file's parameters say against each other
//! and against its data. Each broken rule is a [`Warning`] (the file is still read), so that
//! `info` can tell a user why another program may refuse the file.

use crate::data::Layout;
use crate::error::{Section, Warning};
use crate::header::Header;
use crate::parameters::{Parameters, Value};

fn warn(message: String) -> Warning {
    Warning::new(Section::Parameters, None, message)
}

/// Check what was read and append a warning per broken rule.
pub(crate) fn check(h: &Header, ps: &Parameters, layout: &Layout, out: &mut Vec<Warning>) {
    stored_types(ps, out);
    // Point parameters the data needs.
    if layout.points > 0 {
        point_parameters(ps, layout.points, layout.frames, out);
    }
    let point_rate = ps.get_f32("POINT", "RATE");
    if let Some(r) = point_rate {
        if r > 0.0 && h.frame_rate > 0.0 && (r - h.frame_rate).abs() > 1e-3 * r {
            out.push(warn(format!(
                "POINT:RATE {r} differs from the header's frame rate {}",
                h.frame_rate
            )));
        }
    }
    // Analog parameters the data needs.
    if layout.analog_channels > 0 {
        analog_parameters(ps, layout, point_rate.unwrap_or(h.frame_rate), out);
    }
    if let Some(fp) = ps.group("FORCE_PLATFORM") {
        if ps.get("FORCE_PLATFORM", "USED").is_none() && ps.parameters_of(fp.id).next().is_some() {
            out.push(warn("FORCE_PLATFORM:USED is missing".into()));
        }
    }
}

/// Text parameters whose strings have length 0 (the first dimension), and parameters the
/// manual types as integers stored otherwise.
fn stored_types(ps: &Parameters, out: &mut Vec<Warning>) {
    for (g, p) in [
        ("POINT", "LABELS"),
        ("POINT", "DESCRIPTIONS"),
        ("POINT", "UNITS"),
        ("ANALOG", "LABELS"),
        ("ANALOG", "DESCRIPTIONS"),
        ("ANALOG", "UNITS"),
    ] {
        if let Some(prm) = ps.get(g, p) {
            if matches!(prm.value, Value::Char(_)) && prm.dims.first() == Some(&0) {
                out.push(warn(format!("{g}:{p} has strings of length 0")));
            }
        }
    }
    for (g, p) in [
        ("POINT", "USED"),
        ("POINT", "DATA_START"),
        ("ANALOG", "USED"),
        ("ANALOG", "OFFSET"),
        ("FORCE_PLATFORM", "USED"),
        ("FORCE_PLATFORM", "TYPE"),
    ] {
        if let Some(prm) = ps.get(g, p) {
            if !matches!(prm.value, Value::Int(_) | Value::Byte(_)) {
                out.push(warn(format!(
                    "{g}:{p} is stored as {} (the manual: 16-bit integer)",
                    prm.value.type_name()
                )));
            }
        }
    }
}

/// The POINT parameters a file with `count` points needs, and its labels: blank, repeated,
/// too few.
fn point_parameters(ps: &Parameters, count: usize, frames: usize, out: &mut Vec<Warning>) {
    for p in ["USED", "SCALE", "RATE", "DATA_START", "FRAMES"] {
        if ps.get("POINT", p).is_none() {
            out.push(warn(format!("POINT:{p} is missing")));
        }
    }
    if let Some(ds) = ps.get_i32("POINT", "DATA_START") {
        if ds == 0 {
            out.push(warn("POINT:DATA_START is 0".into()));
        }
    }
    if let Some(n) = ps.get_u16("POINT", "FRAMES") {
        if (n as usize) != frames && frames <= 65535 {
            out.push(warn(format!(
                "POINT:FRAMES is {n} but the header's frame range holds {}",
                frames
            )));
        }
    }
    let labels = ps.get_strings_continued("POINT", "LABELS");
    let blank = labels
        .iter()
        .take(count)
        .filter(|l| l.trim().is_empty())
        .count();
    if blank > 0 {
        out.push(warn(format!("{blank} point labels are blank")));
    }
    let mut seen: Vec<&str> = Vec::new();
    let mut repeated: Vec<&str> = Vec::new();
    for l in labels
        .iter()
        .take(count)
        .map(|l| l.trim())
        .filter(|l| !l.is_empty())
    {
        if seen.contains(&l) {
            if !repeated.contains(&l) {
                repeated.push(l);
            }
        } else {
            seen.push(l);
        }
    }
    if !repeated.is_empty() {
        let shown: Vec<&str> = repeated.iter().take(8).copied().collect();
        out.push(warn(format!(
            "{} point labels repeat ({}{})",
            repeated.len(),
            shown.join(", "),
            if repeated.len() > 8 { ", …" } else { "" }
        )));
    }
    if labels.len() < count {
        out.push(warn(format!(
            "POINT:LABELS names {} of {} points",
            labels.len(),
            count
        )));
    }
}

/// The ANALOG parameters stored analog data needs: the group, its rate against the point
/// rate `rate`, a scale and offset for every channel.
fn analog_parameters(ps: &Parameters, layout: &Layout, rate: f32, out: &mut Vec<Warning>) {
    let channels = layout.analog_channels;
    if ps.group("ANALOG").is_none() {
        out.push(warn(
            "analog data is stored but there is no ANALOG group (no labels, rate or calibration)"
                .into(),
        ));
        return;
    }
    for p in ["USED", "RATE", "SCALE", "OFFSET", "GEN_SCALE"] {
        if ps.get("ANALOG", p).is_none() {
            out.push(warn(format!("ANALOG:{p} is missing")));
        }
    }
    if let Some(ar) = ps.get_f32("ANALOG", "RATE") {
        let want = rate * layout.analog_samples_per_frame as f32;
        if rate > 0.0 && (ar - want).abs() > 1e-3 * want.max(1.0) {
            out.push(warn(format!(
                "ANALOG:RATE {ar} is not {} samples per frame × the point rate {rate}",
                layout.analog_samples_per_frame
            )));
        }
    }
    for p in ["SCALE", "OFFSET"] {
        if let Some(prm) = ps.get("ANALOG", p) {
            if prm.value.len() < channels {
                out.push(warn(format!(
                    "ANALOG:{p} has {} values for {} channels (the rest default)",
                    prm.value.len(),
                    channels
                )));
            }
        }
    }
}
