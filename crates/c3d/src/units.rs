//! Lengths in POINT:UNITS, as millimetres.

/// Millimetres per unit of a POINT:UNITS string ("mm", "m", "cm", "dm", "in" and spellings
/// of them; anything else is taken as millimetres, the C3D default), so that thresholds
/// given in mm apply to any file and errors can be reported in mm whatever the file's unit.
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
    fn units_in_mm() {
        assert_eq!(mm_per_unit("m"), 1000.0);
        assert_eq!(mm_per_unit(" MM "), 1.0);
        assert_eq!(mm_per_unit("cm"), 10.0);
        assert_eq!(mm_per_unit("in"), 25.4);
    }
}
