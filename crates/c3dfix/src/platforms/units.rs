//! Which unit a plate's numbers are in.
//!
//! The manual has every distance of a file in POINT:UNITS ("POINT:UNITS … affects the scaling
//! values stored in the CAL_MATRIX, and ANALOG:SCALE"), so plate moments are N × POINT:UNITS
//! and type 1's COP is in POINT:UNITS. ANALOG:UNITS is a label, and the bytes show it can be
//! wrong: sample_03's moment channels say "Nm" in a mm file, yet only N·mm puts their COP on
//! the plate. A label naming another length is therefore reported, not applied.

use kinetics::PlateKind;

/// Millimetres per unit of a length unit's name, or `None` for a name that is no length
/// (the workspace's one table, [`c3d::units::length_mm`]).
pub(super) fn length_mm(unit: &str) -> Option<f64> {
    c3d::units::length_mm(unit).ok()
}

/// Millimetres per unit of a moment unit's length ("Nmm", "N.m", "N*mm", "N·m", "N-m").
pub(super) fn moment_length_mm(unit: &str) -> Option<f64> {
    let rest = unit.trim().strip_prefix(['N', 'n'])?;
    length_mm(rest.trim_start_matches(['.', '*', '·', ' ', '-']))
}

/// The plate's channels whose ANALOG:UNITS label names a length other than POINT:UNITS
/// (`point_mm` millimetres): (channel, label).
pub(super) fn mislabelled(
    kind: PlateKind,
    used: &[usize],
    analog_units: &[String],
    point_mm: f64,
) -> Vec<(usize, String)> {
    let unit_of = |k: usize| analog_units.get(k - 1).map_or("", |s| s.trim());
    let labelled: Vec<(usize, Option<f64>)> = match kind {
        PlateKind::Type1 => vec![
            (used[3], length_mm(unit_of(used[3]))),
            (used[5], moment_length_mm(unit_of(used[5]))),
        ],
        PlateKind::Type2 | PlateKind::Type4 => {
            vec![(used[3], moment_length_mm(unit_of(used[3])))]
        }
        PlateKind::Type3 => Vec::new(),
    };
    labelled
        .into_iter()
        .filter(|(_, mm)| mm.is_some_and(|mm| (mm / point_mm - 1.0).abs() > 1e-9))
        .map(|(k, _)| (k, unit_of(k).to_string()))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn moment_units() {
        assert_eq!(moment_length_mm("Nmm"), Some(1.0));
        assert_eq!(moment_length_mm("N.m"), Some(1000.0));
        assert_eq!(moment_length_mm("N*mm"), Some(1.0));
        assert_eq!(moment_length_mm("Nm"), Some(1000.0));
        assert_eq!(moment_length_mm("V"), None);
        assert_eq!(moment_length_mm("N"), None);
    }

    #[test]
    fn labels_naming_another_length() {
        let units: Vec<String> = ["N", "N", "N", "Nm", "Nm", "Nm"]
            .iter()
            .map(|s| s.to_string())
            .collect();
        let used = [1, 2, 3, 4, 5, 6];
        assert_eq!(
            mislabelled(PlateKind::Type2, &used, &units, 1.0),
            vec![(4, "Nm".to_string())]
        );
        assert!(mislabelled(PlateKind::Type2, &used, &units, 1000.0).is_empty());
        assert!(mislabelled(PlateKind::Type3, &used, &units, 1.0).is_empty());
    }
}
