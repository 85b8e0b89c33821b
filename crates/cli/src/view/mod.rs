//! `c3dfix view`: one self-contained HTML page that plays a trial in 3D — data, code and
//! styles inlined, nothing fetched, so it can be mailed or opened offline.
//!
//! The page's code is plain canvas 2D with its own small projection (`viewer.js`): no library
//! to vendor, and a 100-marker × 10 000-frame trial still plays smoothly.

pub mod pack;
pub mod sticks;

use anyhow::{bail, Result};
use c3d::C3d;
use serde::Serialize;

const TEMPLATE: &str = include_str!("viewer.html");
const SCRIPT: &str = include_str!("viewer.js");

/// What the page needs to know besides the samples.
#[derive(Serialize)]
struct Meta<'a> {
    title: String,
    file: &'a str,
    original: Option<&'a str>,
    labels: Vec<String>,
    units: String,
    rate: f32,
    first_frame: usize,
    frames: usize,
    count: usize,
    /// Vertical axis of the data (0 x, 1 y, 2 z).
    up: usize,
    sticks: Vec<(usize, usize)>,
}

/// The axis along which markers spread most within a frame: a standing body is taller than it
/// is wide, so this is the vertical one whichever convention the lab used. Z when unsure.
pub fn up_axis(c: &C3d) -> usize {
    let p = c.points();
    let step = (p.frames() / 64).max(1);
    let mut spread = [Vec::new(), Vec::new(), Vec::new()];
    for f in (0..p.frames()).step_by(step) {
        let mut lo = [f32::INFINITY; 3];
        let mut hi = [f32::NEG_INFINITY; 3];
        let mut n = 0;
        for i in 0..p.count() {
            if p.is_valid(f, i) {
                let v = p.xyz[p.index(f, i)];
                for a in 0..3 {
                    lo[a] = lo[a].min(v[a]);
                    hi[a] = hi[a].max(v[a]);
                }
                n += 1;
            }
        }
        if n >= 2 {
            for a in 0..3 {
                spread[a].push(hi[a] - lo[a]);
            }
        }
    }
    let median = |v: &mut Vec<f32>| {
        v.sort_by(f32::total_cmp);
        v.get(v.len() / 2).copied().unwrap_or(0.0)
    };
    let m: Vec<f32> = spread.iter_mut().map(median).collect();
    if m[2] >= m[0] && m[2] >= m[1] {
        2
    } else if m[1] >= m[0] {
        1
    } else {
        0
    }
}

fn escape_html(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// JSON that is safe inside a `<script>` element.
fn script_json<T: Serialize>(v: &T) -> Result<String> {
    Ok(serde_json::to_string(v)?
        .replace('<', "\\u003c")
        .replace('>', "\\u003e")
        .replace('&', "\\u0026"))
}

/// The viewer page for `file` (the repaired data when comparing), with `original` drawn beside
/// it and its markers matched by label. Stick pairs index `file`'s markers.
pub fn page(
    file: (&C3d, &str),
    original: Option<(&C3d, &str)>,
    sticks: Vec<(usize, usize)>,
) -> Result<String> {
    let (c, name) = file;
    let p = c.points();
    if p.count() == 0 {
        bail!("{name} has no 3D points to show");
    }
    let labels = c.point_labels();
    let all: Vec<Option<usize>> = (0..p.count()).map(Some).collect();
    let packed = pack::pack(p, &all, p.frames());
    let orig = match original {
        Some((o, oname)) => {
            if o.points().count() == 0 {
                bail!("{oname} has no 3D points to compare with");
            }
            let order: Vec<Option<usize>> = labels.iter().map(|l| o.point_index(l)).collect();
            if order.iter().all(Option::is_none) {
                bail!("{oname} shares no marker label with {name}");
            }
            Some(pack::pack(o.points(), &order, p.frames()))
        }
        None => None,
    };
    let title = match original {
        Some((_, oname)) => format!("{name} vs {oname}"),
        None => name.to_string(),
    };
    let meta = Meta {
        title: title.clone(),
        file: name,
        original: original.map(|(_, n)| n),
        labels,
        units: c.point_units(),
        rate: c.point_rate(),
        first_frame: c.first_frame(),
        frames: p.frames(),
        count: p.count(),
        up: up_axis(c),
        sticks,
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
    ];
    Ok(fill(TEMPLATE, &fields))
}

/// Replace each `{{KEY}}` of `template` in one pass, so text put in (a marker label, say) is
/// never taken for a placeholder itself. Unknown keys are kept as they are.
fn fill(template: &str, fields: &[(&str, String)]) -> String {
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
