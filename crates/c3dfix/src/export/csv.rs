//! Comma-separated tables of the points and the analog channels.

use std::fmt::Write as _;

/// A CSV field as RFC 4180 writes it: in double quotes, with quotes doubled, when it holds
/// a comma, a quote or a line break; as it is otherwise.
pub(crate) fn field(f: &str) -> std::borrow::Cow<'_, str> {
    if f.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", f.replace('"', "\"\"")).into()
    } else {
        f.into()
    }
}

/// The header of [`parameter_rows`]' table.
pub const PARAMETERS_HEADER: &str = "file,context,name,value,unit\n";

/// The gait-cycle parameters of one trial as CSV rows (`file,context,name,value,unit`, under
/// [`PARAMETERS_HEADER`]): a table of several trials is their rows one after another.
pub fn parameter_rows(file: &str, parameters: &[gait::params::Parameter]) -> String {
    let mut out = String::new();
    for p in parameters {
        let _ = writeln!(
            out,
            "{},{},{},{},{}",
            field(file),
            field(p.context),
            field(p.name),
            p.value,
            field(p.unit)
        );
    }
    out
}

/// One row per frame: the file's frame number, its time ([`c3d::C3d::frame_time`]), then
/// X/Y/Z of each of `points` (indices); a missing sample's cells are empty, as CSV readers
/// (pandas, spreadsheets) read a missing value.
pub fn points_csv(c: &c3d::C3d, points: &[usize]) -> String {
    let p = c.points();
    let labels = c.point_labels();
    let mut s = String::from("Frame,Time");
    for &i in points {
        let l = labels.get(i).map_or("", String::as_str);
        for axis in ["X", "Y", "Z"] {
            let _ = write!(s, ",{}", field(&format!("{l}_{axis}")));
        }
    }
    s.push('\n');
    for f in 0..p.frames() {
        let _ = write!(s, "{},{:.6}", c.frame_number(f), c.frame_time(f));
        for &i in points {
            if p.is_valid(f, i) {
                let [x, y, z] = p.xyz[p.index(f, i)];
                let _ = write!(s, ",{x},{y},{z}");
            } else {
                s.push_str(",,,");
            }
        }
        s.push('\n');
    }
    s
}

/// One row per analog sample, in physical units, timed on the file's base
/// ([`c3d::C3d::analog_time`]).
pub fn analog_csv(c: &c3d::C3d) -> String {
    let a = c.analog();
    let labels = c.analog_labels();
    let units = c.analog_units();
    let phys = c.analog_physical();
    let mut s = String::from("Sample,Time");
    for (l, u) in labels.iter().zip(&units) {
        let name = if u.is_empty() {
            l.clone()
        } else {
            format!("{l} ({u})")
        };
        let _ = write!(s, ",{}", field(&name));
    }
    s.push('\n');
    for k in 0..a.samples() {
        let _ = write!(s, "{},{:.6}", k + 1, c.analog_time(k));
        for ch in 0..a.channels() {
            let _ = write!(s, ",{}", phys[k * a.channels() + ch]);
        }
        s.push('\n');
    }
    s
}
