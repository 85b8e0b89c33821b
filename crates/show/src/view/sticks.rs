//! Which markers the viewer joins with lines: a stick figure makes a cloud of dots readable as
//! a body, and a broken stick shows a swapped or wandering marker at once.

use crate::{Error, Result};
use std::collections::HashMap;

/// Plug-in Gait segments as marker pairs; `L`/`R` variants are made from the `S` ones.
const SIDED: &[(&str, &str)] = &[
    // Leg chain from the pelvis down to the foot.
    ("SASI", "STHI"),
    ("STHI", "SKNE"),
    ("SKNE", "STIB"),
    ("STIB", "SANK"),
    ("SANK", "SHEE"),
    ("SANK", "STOE"),
    ("SHEE", "STOE"),
    // Arm chain from the shoulder to the hand.
    ("SSHO", "SELB"),
    ("SELB", "SWRA"),
    ("SELB", "SWRB"),
    ("SWRA", "SWRB"),
    ("SWRA", "SFIN"),
    ("SWRB", "SFIN"),
    ("CLAV", "SSHO"),
    ("C7", "SSHO"),
];

const CENTRE: &[(&str, &str)] = &[
    // Pelvis.
    ("LASI", "RASI"),
    ("RASI", "RPSI"),
    ("RPSI", "LPSI"),
    ("LPSI", "LASI"),
    // Trunk.
    ("C7", "T10"),
    ("C7", "CLAV"),
    ("CLAV", "STRN"),
    ("C7", "RBAK"),
    ("RBAK", "T10"),
    // Head.
    ("LFHD", "RFHD"),
    ("RFHD", "RBHD"),
    ("RBHD", "LBHD"),
    ("LBHD", "LFHD"),
];

/// The label without a "Subject:" prefix, upper-cased: how markers are matched across
/// subjects and tools.
fn bare(label: &str) -> String {
    label
        .rsplit(':')
        .next()
        .unwrap_or(label)
        .trim()
        .to_ascii_uppercase()
}

/// Stick pairs (marker indices) for the Plug-in Gait markers found in `labels`; pairs with an
/// absent marker are skipped. Without PSI markers the pelvis closes through SACR.
pub fn plug_in_gait(labels: &[String]) -> Vec<(usize, usize)> {
    let mut at: HashMap<String, usize> = HashMap::new();
    for (i, l) in labels.iter().enumerate() {
        at.entry(bare(l)).or_insert(i);
    }
    let mut names: Vec<(String, String)> = CENTRE
        .iter()
        .map(|(a, b)| (a.to_string(), b.to_string()))
        .collect();
    for side in ["L", "R"] {
        for (a, b) in SIDED {
            let s = |n: &str| {
                n.strip_prefix('S')
                    .map_or(n.to_string(), |r| format!("{side}{r}"))
            };
            names.push((s(a), s(b)));
        }
    }
    if !at.contains_key("LPSI") && !at.contains_key("RPSI") {
        names.push(("LASI".into(), "SACR".into()));
        names.push(("RASI".into(), "SACR".into()));
    }
    names
        .iter()
        .filter_map(|(a, b)| Some((*at.get(a)?, *at.get(b)?)))
        .collect()
}

/// Stick pairs from a JSON list of `[markerA, markerB]` label pairs; every label must be
/// found by `index` (which says what is available when it is not).
pub fn from_json(
    text: &str,
    source: &str,
    index: impl Fn(&str) -> Result<usize>,
) -> Result<Vec<(usize, usize)>> {
    let pairs: Vec<Vec<String>> = serde_json::from_str(text).map_err(|e| Error::SticksJson {
        file: source.into(),
        source: e,
    })?;
    let mut out = Vec::new();
    for p in pairs {
        let [a, b] = p.as_slice() else {
            return Err(Error::SticksPair {
                file: source.into(),
                found: p,
            });
        };
        out.push((index(a)?, index(b)?));
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn labels(names: &[&str]) -> Vec<String> {
        names.iter().map(|s| s.to_string()).collect()
    }

    fn named(l: &[String], pairs: &[(usize, usize)]) -> Vec<(String, String)> {
        pairs
            .iter()
            .map(|&(a, b)| (bare(&l[a]), bare(&l[b])))
            .collect()
    }

    #[test]
    fn plug_in_gait_names_give_the_expected_sticks() {
        let l = labels(&[
            "LASI", "RASI", "LPSI", "RPSI", "LTHI", "LKNE", "LTIB", "LANK", "LHEE", "LTOE", "C7",
            "T10", "CLAV", "STRN", "RBAK", "LFHD", "RFHD", "LBHD", "RBHD", "LSHO", "LELB", "LWRA",
            "LWRB", "LFIN",
        ]);
        let got = named(&l, &plug_in_gait(&l));
        for (a, b) in [
            ("LASI", "RASI"),
            ("RPSI", "LPSI"),
            ("LASI", "LTHI"),
            ("LTHI", "LKNE"),
            ("LKNE", "LTIB"),
            ("LTIB", "LANK"),
            ("LANK", "LHEE"),
            ("LANK", "LTOE"),
            ("C7", "T10"),
            ("CLAV", "STRN"),
            ("C7", "RBAK"),
            ("LFHD", "RFHD"),
            ("RBHD", "LBHD"),
            ("LSHO", "LELB"),
            ("LELB", "LWRA"),
            ("LWRB", "LFIN"),
        ] {
            assert!(
                got.contains(&(a.into(), b.into())),
                "{a}-{b} missing: {got:?}"
            );
        }
        // No right leg or arm markers: none of their sticks.
        assert!(!got.iter().any(|(a, b)| a == "RKNE" || b == "RSHO"));
        assert_eq!(got.len(), 4 + 5 + 4 + 7 + 6 + 2);
    }

    #[test]
    fn a_subject_prefix_and_case_are_ignored_and_absent_markers_skipped() {
        let l = labels(&["Bob:LASI", "Bob:rasi", "Bob:SACR", "Bob:LKNE"]);
        let got = plug_in_gait(&l);
        assert_eq!(got, vec![(0, 1), (0, 2), (1, 2)]);
        assert!(plug_in_gait(&labels(&["FOO", "BAR"])).is_empty());
    }

    #[test]
    fn sticks_from_json_resolve_labels() {
        let idx = |s: &str| match s {
            "A" => Ok(0),
            "B" => Ok(1),
            _ => Err(Error::NoMarker {
                file: "test".into(),
                name: s.into(),
                available: vec!["A".into(), "B".into()],
            }),
        };
        assert_eq!(
            from_json(r#"[["A","B"]]"#, "s.json", idx).unwrap(),
            vec![(0, 1)]
        );
        assert!(from_json(r#"[["A","C"]]"#, "s.json", idx).is_err());
        assert!(from_json(r#"[["A"]]"#, "s.json", idx).is_err());
        assert!(from_json("{}", "s.json", idx).is_err());
    }
}
