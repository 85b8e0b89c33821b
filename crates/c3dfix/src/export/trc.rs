//! The Motion Analysis TRC text format (PathFileType 4, X/Y/Z), as OpenSim reads it.

use super::header_label;
use crate::axes::Axes;
use crate::error::Result;
use std::fmt::Write as _;

/// A TRC file's text, and the labels that had to be changed to fit it (a tab or line break
/// became a space; an empty label became `PointN`, N the point's 1-based number).
#[derive(Debug, Clone, PartialEq)]
pub struct Trc {
    pub text: String,
    pub changed_labels: Vec<String>,
}

/// The TRC of the points `points` (indices, see [`super::Points`]) of `c`, named `name` in
/// its first line, turned by `axes`. Frame# is the file's own frame number and Time the
/// file's time base ([`c3d::C3d::frame_time`]), so a cropped trial keeps its frames' times.
///
/// A missing sample is written `NaN` in each of its three fields: OpenSim's reader counts
/// the fields of every row and drops trailing empty ones, so a row whose last marker is
/// missing would be short ("Unexpected number of columns"); `NaN` is what OpenSim itself
/// writes for a missing marker and reads back as missing.
pub fn trc(c: &c3d::C3d, name: &str, points: &[usize], axes: &Axes) -> Result<Trc> {
    let p = c.points();
    let labels = c.point_labels();
    let rate = c.point_rate();
    let (name, _) = header_label(name);
    let units = header_label(&c.point_units()).0;
    let mut changed = Vec::new();
    let mut s = format!("PathFileType\t4\t(X/Y/Z)\t{name}\n");
    s.push_str("DataRate\tCameraRate\tNumFrames\tNumMarkers\tUnits\tOrigDataRate\tOrigDataStartFrame\tOrigNumFrames\n");
    let first = c.first_frame();
    let _ = writeln!(
        s,
        "{rate}\t{rate}\t{}\t{}\t{}\t{rate}\t{first}\t{}",
        p.frames(),
        points.len(),
        units,
        p.frames()
    );
    s.push_str("Frame#\tTime");
    for &i in points {
        let l = labels.get(i).map_or("", String::as_str);
        let (mut clean, was_changed) = header_label(l);
        // OpenSim drops empty label fields and then counts too few: an unnamed point is
        // named by its number.
        if clean.trim().is_empty() {
            clean = format!("Point{}", i + 1);
            changed.push(l.to_string());
        } else if was_changed {
            changed.push(l.to_string());
        }
        let _ = write!(s, "\t{clean}\t\t");
    }
    s.push_str("\n\t");
    for k in 1..=points.len() {
        let _ = write!(s, "\tX{k}\tY{k}\tZ{k}");
    }
    s.push_str("\n\n");
    for f in 0..p.frames() {
        let _ = write!(s, "{}\t{:.6}", c.frame_number(f), c.frame_time(f));
        for &i in points {
            if p.is_valid(f, i) {
                let [x, y, z] = axes.apply_f32(p.xyz[p.index(f, i)]);
                let _ = write!(s, "\t{x}\t{y}\t{z}");
            } else {
                s.push_str("\tNaN\tNaN\tNaN");
            }
        }
        s.push('\n');
    }
    Ok(Trc {
        text: s,
        changed_labels: changed,
    })
}
