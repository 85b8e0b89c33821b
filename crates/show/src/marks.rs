//! Events as the pictures show them (`plot`, `view`): a time on the file's base, a short
//! label drawn beside the mark and the full wording for tooltips, from the file's EVENT
//! group or from the detector.

use crate::Result;
use serde::Serialize;
use std::path::Path;

/// One event to mark.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Mark {
    /// Seconds on the file's time base (`C3d::frame_time`'s, the EVENT group's).
    pub time: f64,
    /// What is drawn beside the mark: `LFS`, `RFO` as gait labs abbreviate Left Foot Strike
    /// and Right Foot Off, else the event's own label (after `L `/`R ` for a side).
    pub short: String,
    /// "Left Foot Strike 2.790 s", for tooltips.
    pub full: String,
    /// Found by the detector rather than read from the file.
    pub detected: bool,
}

/// The short label of an event of `context` (Left, Right, General…) and `label`.
pub fn short(context: &str, label: &str) -> String {
    let side = match context.trim().to_ascii_lowercase().as_str() {
        "left" => "L",
        "right" => "R",
        _ => "",
    };
    let kind = match label.trim().to_ascii_lowercase().as_str() {
        "foot strike" => Some("FS"),
        "foot off" => Some("FO"),
        _ => None,
    };
    match (kind, side) {
        (Some(k), _) => format!("{side}{k}"),
        (None, "") => label.trim().to_string(),
        (None, s) => format!("{s} {}", label.trim()),
    }
}

fn mark(context: &str, label: &str, time: f64, detected: bool) -> Mark {
    let what = [context.trim(), label.trim()]
        .iter()
        .filter(|s| !s.is_empty())
        .copied()
        .collect::<Vec<_>>()
        .join(" ");
    Mark {
        time,
        short: short(context, label),
        full: format!(
            "{what} {time:.3} s{}",
            if detected { " (detected)" } else { "" }
        ),
        detected,
    }
}

/// The events of the file's EVENT group that have a finite time, in time order.
pub fn from_file(c: &c3d::C3d) -> Vec<Mark> {
    let mut out: Vec<Mark> = c
        .events()
        .iter()
        .filter(|e| e.time.is_finite())
        .map(|e| mark(&e.context, &e.label, e.time, false))
        .collect();
    out.sort_by(|a, b| a.time.total_cmp(&b.time));
    out
}

/// The events the detector finds (as `c3dfix events --from auto`), in time order. The
/// library's own error, as the detector gives it: a front end phrases its kinds.
pub fn detected(c: &c3d::C3d, path: &Path) -> Result<Vec<Mark>, c3dfix::Error> {
    let d = c3dfix::detect_events(c, &c3dfix::EventOptions::default(), path)?;
    Ok(d.events
        .iter()
        .map(|e| mark(e.side.context(), e.kind.label(), e.time, true))
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn short_labels() {
        assert_eq!(short("Left", "Foot Strike"), "LFS");
        assert_eq!(short("Right", "Foot Off"), "RFO");
        assert_eq!(short("General", "Event"), "Event");
        assert_eq!(short("Left", "Toe Walk"), "L Toe Walk");
        assert_eq!(
            mark("Right", "Foot Off", 2.91, true).full,
            "Right Foot Off 2.910 s (detected)"
        );
    }
}
