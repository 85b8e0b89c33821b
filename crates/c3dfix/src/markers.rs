//! Which points of a trial are markers, and how labels name them: one notion of a marker for
//! every command and binding.

use crate::error::{Error, Result};

/// Labels of points that are model outputs, not markers: Plug-in Gait stores angles, forces,
/// moments, powers and the like as points and lists them in these POINT parameters. They are
/// never repaired nor used as donors.
pub fn model_outputs(c: &c3d::C3d) -> Vec<String> {
    [
        "ANGLES",
        "FORCES",
        "MOMENTS",
        "POWERS",
        "SCALARS",
        "REACTIONS",
    ]
    .iter()
    .flat_map(|p| c.parameters.get_strings("POINT", p).unwrap_or_default())
    .filter(|s| !s.is_empty())
    .collect()
}

/// The markers of a trial: indices of the points that are not model outputs.
pub fn marker_indices(c: &c3d::C3d) -> Vec<usize> {
    let outputs = model_outputs(c);
    c.point_labels()
        .iter()
        .enumerate()
        .filter(|(_, l)| !outputs.contains(l))
        .map(|(i, _)| i)
        .collect()
}

/// Point indices of the given labels (surrounding blanks ignored, empty names skipped); an
/// unknown label is an error that lists the labels the trial has.
pub fn select(c: &c3d::C3d, names: &[String]) -> Result<Vec<usize>> {
    let mut out = Vec::new();
    for n in names.iter().map(|n| n.trim()).filter(|n| !n.is_empty()) {
        match c.point_index(n) {
            Some(i) => out.push(i),
            None => {
                return Err(Error::options(format!(
                    "no marker {n:?}; the file has: {}",
                    c.point_labels().join(", ")
                )))
            }
        }
    }
    Ok(out)
}

/// Millimetres per POINT:UNITS unit, so that thresholds given in mm apply to any file and
/// errors are reported in mm whatever the file's unit.
pub fn mm_per_unit(units: &str) -> f64 {
    match units.trim().to_ascii_lowercase().as_str() {
        "m" | "mete" | "meter" | "meters" | "metre" | "metres" => 1000.0,
        "cm" => 10.0,
        "dm" => 100.0,
        "in" | "inch" | "inches" => 25.4,
        _ => 1.0,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn units_to_millimetres() {
        assert_eq!(mm_per_unit("m"), 1000.0);
        assert_eq!(mm_per_unit(" MM "), 1.0);
        assert_eq!(mm_per_unit("cm"), 10.0);
    }
}
