//! Lengths in POINT:UNITS: the one table of length units every crate of the workspace reads.

/// A unit name that is no length this table knows: exports that must write metres refuse
/// it rather than guess a scale.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{unit:?} is no length unit c3dfix knows (mm, cm, dm, m, in and their spellings)")]
pub struct UnknownUnit {
    /// The name as the file stores it.
    pub unit: String,
}

/// Millimetres per unit of a length unit's name ("mm", "cm", "dm", "m", "in", and the
/// spellings writers use: "metres", "meter", "inch", the four-letter "mete" of a field cut
/// to four characters), case and surrounding blanks ignored.
pub fn length_mm(unit: &str) -> Result<f64, UnknownUnit> {
    match unit.trim().to_ascii_lowercase().as_str() {
        "mm" | "millimetre" | "millimetres" | "millimeter" | "millimeters" => Ok(1.0),
        "cm" | "centimetre" | "centimetres" | "centimeter" | "centimeters" => Ok(10.0),
        "dm" => Ok(100.0),
        "m" | "mete" | "meter" | "meters" | "metre" | "metres" => Ok(1000.0),
        "in" | "inch" | "inches" => Ok(25.4),
        _ => Err(UnknownUnit {
            unit: unit.to_string(),
        }),
    }
}

/// Millimetres per unit of POINT:UNITS for thresholds given in mm (repair's spike and
/// expected-error limits): a unit [`length_mm`] does not know is taken as millimetres, the
/// C3D default, since a threshold's scale is no output. Outputs that must state a unit
/// (the OpenSim exports) call [`length_mm`] and refuse an unknown one.
pub fn mm_per_unit(units: &str) -> f64 {
    length_mm(units).unwrap_or(1.0)
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
        assert_eq!(length_mm("Metres"), Ok(1000.0));
        assert_eq!(length_mm("dm"), Ok(100.0));
    }

    #[test]
    fn an_unknown_unit_is_refused_by_name() {
        let e = length_mm("furlong").unwrap_err();
        assert_eq!(e.unit, "furlong");
        assert!(e.to_string().contains("\"furlong\""), "{e}");
        assert!(length_mm("").is_err());
        assert_eq!(mm_per_unit("furlong"), 1.0);
    }
}
