//! Length units: the workspace's one table ([`c3d::units`]), and metres for the outputs that
//! must state SI units (OpenSim's TRC and MOT).

pub use c3d::units::{length_mm, mm_per_unit, UnknownUnit};

/// Metres per unit of a length unit's name; an unknown name is an error, never a guessed 1.
pub fn metres_per(unit: &str) -> Result<f64, UnknownUnit> {
    length_mm(unit).map(|mm| mm / 1000.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn metres() {
        assert_eq!(metres_per("mm"), Ok(1e-3));
        assert_eq!(metres_per("m"), Ok(1.0));
        assert_eq!(metres_per("cm"), Ok(1e-2));
        assert!(metres_per("parsec").is_err());
    }
}
