//! The viewer (`c3dfix view`): one self-contained HTML page that plays a trial in 3D — data, code and
//! styles inlined, nothing fetched, so it can be mailed or opened offline.
//!
//! The page's code is plain canvas 2D with its own small projection (`viewer.js`): no library
//! to vendor, and a 100-marker × 10 000-frame trial still plays smoothly.

mod file_page;
pub mod pack;
pub mod skeleton;
pub mod sticks;

use crate::{Error, Result};
use c3d::{C3d, Points};
use serde::Serialize;

pub use file_page::file_page;

const TEMPLATE: &str = include_str!("viewer.html");
const SCRIPT: &str = include_str!("viewer.js");

/// What the page needs to know besides the samples.
#[derive(Serialize)]
struct Meta<'a> {
    title: String,
    file: &'a str,
    original: Option<&'a str>,
    /// "c3d" (markers) or "bvh" (a skeleton): decides the legend.
    kind: &'static str,
    labels: Vec<String>,
    units: String,
    rate: f32,
    first_frame: usize,
    frames: usize,
    count: usize,
    /// Vertical axis of the data (0 x, 1 y, 2 z).
    up: usize,
    /// Whether up is the axis' positive direction (else the page turns the scene over).
    up_positive: bool,
    /// Whether the file marks fills (residual 0 among positive residuals): the legend shows
    /// "filled" only then.
    fills_marked: bool,
    sticks: Vec<(usize, usize)>,
    /// Points whose traces are drawn from the start.
    traced: Vec<usize>,
    /// Whether to draw the sticks' shadow on the floor.
    shadow: bool,
    /// The force plates' outlines; their samples per frame are in the FORCES block.
    plates: Vec<pack::PlateOutline>,
    /// Data units per newton for the ground reaction arrows.
    force_scale: f64,
    /// Events marked on the time bar, at their frames.
    events: Vec<BarEvent>,
}

/// One event on the time bar: where it falls among the stored frames and how it reads.
#[derive(Serialize)]
struct BarEvent {
    /// 0-based stored frame, fractional (an event between frames sits between them).
    index: f64,
    short: String,
    full: String,
    detected: bool,
}

/// One trial as the page shows it, whichever format it came from.
pub struct Trial<'a> {
    pub name: &'a str,
    pub points: &'a Points,
    pub labels: Vec<String>,
    pub units: String,
    pub rate: f32,
    pub first_frame: usize,
}

impl<'a> Trial<'a> {
    /// A C3D file's 3D points.
    pub fn c3d(c: &'a C3d, name: &'a str) -> Trial<'a> {
        Trial {
            name,
            points: c.points(),
            labels: c.point_labels(),
            units: c.point_units(),
            rate: c.point_rate(),
            first_frame: c.first_frame(),
        }
    }
}

/// How the page draws a trial.
pub struct Style {
    /// "c3d" or "bvh".
    pub kind: &'static str,
    /// Stick pairs, as indices of the shown trial's points.
    pub sticks: Vec<(usize, usize)>,
    /// Points traced from the start.
    pub traced: Vec<usize>,
    /// Draw the sticks' shadow on the floor.
    pub shadow: bool,
    /// Force plates with their ground reaction per frame.
    pub plates: Option<pack::PlateFrames>,
    /// The lab's up ([`c3dfix::axes::up`] for a C3D file, [`c3dfix::axes::points_up`] for a
    /// skeleton); `None` (no frame with two valid points): +z.
    pub up: Option<c3dfix::Direction>,
    /// Whether a residual of 0 marks a computed sample in this file (see [`fills_marked`]).
    pub fills_marked: bool,
    /// Events to mark on the time bar (times on the file's base).
    pub events: Vec<crate::marks::Mark>,
}

/// Whether the file's residuals tell filled samples from measured ones: a residual of 0
/// marks a computed sample (the C3D manual's mark, which repair writes), but only where the
/// writer records residuals at all. A file whose every valid sample has residual 0 (some
/// writers store 0 everywhere) marks no fills, so nothing is shown as filled.
pub fn fills_marked(p: &Points) -> bool {
    (0..p.xyz.len()).any(|k| p.is_valid_at(k) && p.residual[k] > 0.0)
}

/// The markers of `c` (model outputs left out: angles and moments are no positions to draw)
/// as their own points, labels, and for each point of `c` its index among them.
fn markers_only(c: &C3d) -> (Points, Vec<String>, Vec<Option<usize>>) {
    let keep = c3dfix::markers::marker_indices(c);
    let src = c.points();
    let mut p = Points::new(src.frames(), keep.len());
    let mut new_index = vec![None; src.count()];
    for (j, &i) in keep.iter().enumerate() {
        new_index[i] = Some(j);
    }
    for f in 0..src.frames() {
        for (j, &i) in keep.iter().enumerate() {
            let (from, to) = (src.index(f, i), p.index(f, j));
            p.xyz[to] = src.xyz[from];
            p.residual[to] = src.residual[from];
            p.camera_mask[to] = src.camera_mask[from];
        }
    }
    let all = c.point_labels();
    let labels = keep.iter().map(|&i| all[i].clone()).collect();
    (p, labels, new_index)
}

/// The events within the stored frames, placed on them: frame `n` of the capture is at
/// (`n` − 1) / rate, the first stored frame is `first_frame`, so an event at `t` s falls at
/// index `t` × rate − (`first_frame` − 1). None without a rate.
fn bar_events(
    events: &[crate::marks::Mark],
    rate: f32,
    first_frame: usize,
    frames: usize,
) -> Vec<BarEvent> {
    let rate = rate as f64;
    if !(rate > 0.0 && rate.is_finite()) || frames == 0 {
        return Vec::new();
    }
    events
        .iter()
        .map(|e| (e, e.time * rate - first_frame.saturating_sub(1) as f64))
        .filter(|(_, i)| *i >= -0.5 && *i <= frames as f64 - 0.5)
        .map(|(e, index)| BarEvent {
            index,
            short: e.short.clone(),
            full: e.full.clone(),
            detected: e.detected,
        })
        .collect()
}

pub(crate) fn escape_html(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// JSON that is safe inside a `<script>` element.
pub(crate) fn script_json<T: Serialize>(v: &T) -> Result<String> {
    Ok(serde_json::to_string(v)?
        .replace('<', "\\u003c")
        .replace('>', "\\u003e")
        .replace('&', "\\u0026"))
}

/// The viewer page for `file` (the repaired data when comparing), with `original` drawn beside
/// it and its markers matched by label. Stick pairs index `file`'s points; model outputs are
/// not drawn, nor sticks to them. The scene stands on the lab's up ([`c3dfix::axes::up`]).
pub fn page(
    file: (&C3d, &str),
    original: Option<(&C3d, &str)>,
    sticks: Vec<(usize, usize)>,
    plates: Option<&c3dfix::ForcePlatforms>,
    events: Vec<crate::marks::Mark>,
) -> Result<String> {
    let (c, name) = file;
    let (points, labels, new_index) = markers_only(c);
    if points.count() == 0 && c.point_count() > 0 {
        return Err(Error::OnlyModelOutputs { file: name.into() });
    }
    let sticks = sticks
        .into_iter()
        .filter_map(|(a, b)| Some((*new_index.get(a)?.as_ref()?, *new_index.get(b)?.as_ref()?)))
        .collect();
    let orig = match original {
        Some((o, oname)) => {
            if o.points().count() == 0 {
                return Err(Error::NothingToCompare {
                    original: oname.into(),
                });
            }
            let order: Vec<Option<usize>> = labels.iter().map(|l| o.point_index(l)).collect();
            if order.iter().all(Option::is_none) {
                return Err(Error::NoSharedLabel {
                    file: name.into(),
                    original: oname.into(),
                });
            }
            Some((Trial::c3d(o, oname), order))
        }
        None => None,
    };
    let style = Style {
        kind: "c3d",
        sticks,
        traced: Vec::new(),
        shadow: false,
        plates: plates
            .filter(|fp| !fp.platforms.is_empty())
            .map(|fp| pack::plate_frames(fp, c.frames())),
        up: c3dfix::axes::up(c).map(|u| u.up),
        fills_marked: fills_marked(&points),
        events,
    };
    let trial = Trial {
        name,
        points: &points,
        labels,
        units: c.point_units(),
        rate: c.point_rate(),
        first_frame: c.first_frame(),
    };
    render(trial, orig, style)
}

/// The viewer page for any trial; `original` comes with, for each of `file`'s points, the
/// matching point of the original (if any).
pub fn render(
    file: Trial,
    original: Option<(Trial, Vec<Option<usize>>)>,
    style: Style,
) -> Result<String> {
    let p = file.points;
    let name = file.name;
    if p.count() == 0 {
        return Err(Error::NothingToShow { file: name.into() });
    }
    let all: Vec<Option<usize>> = (0..p.count()).map(Some).collect();
    let packed = pack::pack(p, &all, p.frames(), style.fills_marked);
    let orig = original
        .as_ref()
        .map(|(o, order)| pack::pack(o.points, order, p.frames(), false));
    // Without an up (no frame holds two valid points, so no spread to compare), +z: what the
    // viewer's own spread rule gave such a trial before the library's rule replaced it.
    let up = style.up.unwrap_or(c3dfix::Direction {
        axis: 2,
        positive: true,
    });
    let oname = original.as_ref().map(|(o, _)| o.name);
    let title = match oname {
        Some(oname) => format!("{name} vs {oname}"),
        None => name.to_string(),
    };
    let meta = Meta {
        title: title.clone(),
        file: name,
        original: oname,
        kind: style.kind,
        labels: file.labels,
        units: file.units,
        rate: file.rate,
        first_frame: file.first_frame,
        frames: p.frames(),
        count: p.count(),
        up: up.axis,
        up_positive: up.positive,
        fills_marked: style.fills_marked,
        sticks: style.sticks,
        traced: style.traced,
        shadow: style.shadow,
        plates: style
            .plates
            .as_ref()
            .map_or_else(Vec::new, |p| p.outlines.clone()),
        force_scale: style.plates.as_ref().map_or(0.0, |p| p.scale),
        events: bar_events(&style.events, file.rate, file.first_frame, p.frames()),
    };
    let fields = [
        ("TITLE", escape_html(&title)),
        ("SCRIPT", SCRIPT.to_string()),
        ("META", script_json(&meta)?),
        ("XYZ", pack::base64(&packed.xyz)),
        ("FLAGS", pack::base64(&packed.flags)),
        (
            "ORIG",
            orig.map_or_else(String::new, |o| pack::base64(&o.xyz)),
        ),
        (
            "FORCES",
            style
                .plates
                .as_ref()
                .map_or_else(String::new, |p| pack::base64(&p.samples)),
        ),
    ];
    Ok(fill(TEMPLATE, &fields))
}

/// Replace each `{{KEY}}` of `template` in one pass, so text put in (a marker label, say) is
/// never taken for a placeholder itself. Unknown keys are kept as they are.
pub(crate) fn fill(template: &str, fields: &[(&str, String)]) -> String {
    let extra: usize = fields.iter().map(|(_, v)| v.len()).sum();
    let mut out = String::with_capacity(template.len() + extra);
    let mut rest = template;
    while let Some(at) = rest.find("{{") {
        out.push_str(&rest[..at]);
        let after = &rest[at + 2..];
        match after.find("}}").and_then(|end| {
            let key = &after[..end];
            fields
                .iter()
                .find(|(k, _)| *k == key)
                .map(|(_, v)| (v, end))
        }) {
            Some((v, end)) => {
                out.push_str(v);
                rest = &after[end + 2..];
            }
            None => {
                out.push_str("{{");
                rest = after;
            }
        }
    }
    out.push_str(rest);
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn placeholders_are_filled_once() {
        let f = [("A", "{{B}}".to_string()), ("B", "b".to_string())];
        assert_eq!(
            fill("x{{A}}y{{B}}z{{C}}", &f),
            "x{{B}}yb z{{C}}".replace(' ', "")
        );
    }
}
