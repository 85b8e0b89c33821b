//! The pictures of a C3D file as `c3dfix plot` draws them, with the events the file brings
//! (and the detector's when asked): one function per kind of picture, so the command and the
//! Python package write the same bytes for the same file.

use super::{render, render_forces, Format, Plot};
use crate::marks::{self, Mark};
use crate::Result;
use c3d::C3d;
use std::path::Path;

/// The events a plot draws: the file's own, and the detector's with `detect`; none where the
/// file states no rate (the axis is then in frames or samples). `path` names the file in the
/// detector's errors.
pub fn drawn_events(c: &C3d, path: &Path, detect: bool) -> Result<Vec<Mark>> {
    let rate = c.point_rate();
    if rate.is_nan() || rate <= 0.0 {
        return Ok(Vec::new());
    }
    let mut events = marks::from_file(c);
    if detect {
        events.extend(marks::detected(c, path)?);
    }
    Ok(events)
}

/// The markers' coordinates against time (and the analog channel `analog` below them) of
/// `c`, read from `path` and titled `name`, over `original` when given, as `format` bytes.
pub fn markers_picture(
    file: (&C3d, &Path, &str),
    original: Option<(&C3d, &str)>,
    markers: &[String],
    analog: Option<&str>,
    detect_events: bool,
    format: Format,
) -> Result<Vec<u8>> {
    let (c, path, name) = file;
    let mut plot = Plot::gather((c, name), original, markers, analog)?;
    plot.events = drawn_events(c, path, detect_events)?;
    render(&plot, format)
}

/// The force plates of `c` (read from `path`, titled `name`) computed with `opts`, as
/// `format` bytes. `warn` is given each of the plates' warnings as soon as they are known,
/// so a front end says them even when the picture then cannot be drawn.
pub fn forces_picture(
    file: (&C3d, &Path, &str),
    opts: &c3dfix::ForceOptions,
    detect_events: bool,
    format: Format,
    warn: &mut dyn FnMut(String),
) -> Result<Vec<u8>> {
    let (c, path, name) = file;
    let fp = c3dfix::force_platforms(c, opts)?;
    for w in &fp.warnings {
        warn(w.to_string());
    }
    let events = drawn_events(c, path, detect_events)?;
    render_forces(&fp, name, &events, format)
}
