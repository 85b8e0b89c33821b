//! Which markers are the heels, the toes and the pelvis, found by their labels in the
//! common marker sets, or named by a person.
//!
//! A label is compared without its subject prefix (`Subject:LHEE` → `LHEE`), without case
//! and without separators (`L.Heel`, `l heel`, `L_FCC` → `lheel`, `lheel`, `lfcc`); then its
//! side (`l`/`left`, `r`/`right`, leading) and its part are matched against the lists below,
//! in order of preference. The lists are the names of Plug-in Gait and CGM (LHEE, LTOE,
//! SACR, LPSI, LASI), Motion Analysis' Helen Hayes set (LHEE, LTOE), Qualisys/IOR (L_FCC,
//! L_FM2, L_IPS, L_IAS), Codamotion (L.Heel, L.MT2), OpenSim's examples (LCAL, LMT2), Helen
//! Hayes' VSAC and L.TO, and other exports found in gait files (LHEEL, LP1MT, "l heel",
//! "l met", "l mall").
//!
//! Where a set has no heel marker (some Plug-in Gait models keep only LANK and LTOE), the
//! lateral malleolus stands in for it: it lies a few centimetres above and in front of the
//! heel and reaches its forward extreme at the same instant, which is all Zeni's method asks.

use crate::error::{Error, Result};

/// Heel names, best first; the ankle names after them are the fallback.
const HEEL: &[&str] = &[
    "hee",
    "heel",
    "hel",
    "cal",
    "calc",
    "fcc",
    "heelfoot",
    "heelcenter",
    "hl",
];
const ANKLE: &[&str] = &["ank", "lmal", "fal", "ankle", "lma", "mal", "mall", "mm"];
/// Toe names, best first: the second metatarsal head (Plug-in Gait's TOE) before the first
/// and fifth, and a lateral toe marker (`LLA_TOE`, tsalemink's AUC set) last.
const TOE: &[&str] = &[
    "toe", "to", "mt2", "fm2", "toetip", "ttoe", "toefoot", "met", "mt1", "fm1", "p1mt", "met1",
    "mt5", "fm5", "p5mt", "met5", "mh1", "mh5", "latoe",
];
/// Markers standing alone for the pelvis (sacrum, mid-PSIS).
const SACRUM: &[&str] = &[
    "sacr", "sacrum", "sac", "vsac", "mpsi", "sacral", "s1", "ppsi",
];
/// Paired pelvis markers: PSIS first (their mean is the sacrum), then ASIS.
const PSIS: &[&str] = &["psi", "psis", "ips", "pis"];
const ASIS: &[&str] = &["asi", "asis", "ias", "ais"];

/// The label as compared: no subject prefix, lower case, letters and digits only.
pub fn normalise(label: &str) -> String {
    let bare = label.rsplit(':').next().unwrap_or(label);
    bare.chars()
        .filter(|c| c.is_ascii_alphanumeric())
        .map(|c| c.to_ascii_lowercase())
        .collect()
}

/// The markers chosen for each role: point indices whose mean stands for the role.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct MarkerChoice {
    pub left_heel: Vec<usize>,
    pub right_heel: Vec<usize>,
    pub left_toe: Vec<usize>,
    pub right_toe: Vec<usize>,
    pub pelvis: Vec<usize>,
    /// Left and right: no heel marker was found and the ankle stands in for it.
    pub heel_is_ankle: [bool; 2],
}

/// Names given by a person for some roles (each a list whose mean is used).
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct MarkerNames {
    pub left_heel: Option<Vec<String>>,
    pub right_heel: Option<Vec<String>>,
    pub left_toe: Option<Vec<String>>,
    pub right_toe: Option<Vec<String>>,
    pub pelvis: Option<Vec<String>>,
}

impl MarkerNames {
    /// Parse `ROLE=NAME[+NAME…]` items (`lheel`, `rheel`, `ltoe`, `rtoe`, `pelvis`), e.g.
    /// `pelvis=LPSI+RPSI`.
    pub fn parse(items: &[String]) -> Result<MarkerNames> {
        let mut out = MarkerNames::default();
        for item in items {
            for part in item.split(',').filter(|s| !s.trim().is_empty()) {
                let Some((role, names)) = part.split_once('=') else {
                    return Err(Error::BadMarkerSpec(part.to_string()));
                };
                let names: Vec<String> = names
                    .split('+')
                    .map(|s| s.trim().to_string())
                    .filter(|s| !s.is_empty())
                    .collect();
                if names.is_empty() {
                    return Err(Error::BadMarkerSpec(part.to_string()));
                }
                let slot = match role.trim().to_ascii_lowercase().as_str() {
                    "lheel" | "lhee" => &mut out.left_heel,
                    "rheel" | "rhee" => &mut out.right_heel,
                    "ltoe" => &mut out.left_toe,
                    "rtoe" => &mut out.right_toe,
                    "pelvis" | "sacrum" | "sacr" => &mut out.pelvis,
                    _ => return Err(Error::BadMarkerSpec(part.to_string())),
                };
                *slot = Some(names);
            }
        }
        Ok(out)
    }
}

/// The side and part of a normalised label, if it has a side prefix.
fn split_side(n: &str) -> Option<(char, &str)> {
    for (prefix, side) in [("left", 'l'), ("right", 'r'), ("l", 'l'), ("r", 'r')] {
        if let Some(rest) = n.strip_prefix(prefix) {
            if !rest.is_empty() {
                return Some((side, rest));
            }
        }
    }
    None
}

/// The first label (by preference of `parts`, then by order in the file) of side `side`.
fn find_sided(norm: &[String], side: char, parts: &[&str]) -> Option<usize> {
    parts.iter().find_map(|part| {
        norm.iter().position(|n| {
            split_side(n).is_some_and(|(s, rest)| s == side && rest == *part)
                // "pLeftHeelFoot" (Xsens-style) and "L_Heel" spelt after the part.
                || n.strip_prefix('p').and_then(split_side).is_some_and(|(s, rest)| s == side && rest == *part)
        })
    })
}

fn by_names(labels: &[String], role: &str, names: &[String]) -> Result<Vec<usize>> {
    names
        .iter()
        .map(|name| {
            labels
                .iter()
                .position(|l| l == name)
                .or_else(|| labels.iter().position(|l| l.eq_ignore_ascii_case(name)))
                .or_else(|| {
                    let n = normalise(name);
                    labels.iter().position(|l| normalise(l) == n)
                })
                .ok_or_else(|| Error::UnknownMarker {
                    role: role.to_string(),
                    name: name.clone(),
                })
        })
        .collect()
}

/// The ankle marker of `side` (`'l'` or `'r'`) among `labels`, to stand in for a heel
/// marker that is named but never seen.
pub fn ankle_for(labels: &[String], side: char) -> Option<usize> {
    let norm: Vec<String> = labels.iter().map(|l| normalise(l)).collect();
    find_sided(&norm, side, ANKLE)
}

/// Choose the markers of each role among `labels` (the point labels, in file order),
/// taking `names` first where given.
pub fn find_markers(labels: &[String], names: &MarkerNames) -> Result<MarkerChoice> {
    let norm: Vec<String> = labels.iter().map(|l| normalise(l)).collect();
    let missing = |what: &str, looked: String| Error::NoMarker {
        what: what.to_string(),
        looked_for: looked,
    };
    let foot = |given: &Option<Vec<String>>, role: &str, side: char, parts: &[&[&str]]| {
        if let Some(g) = given {
            return by_names(labels, role, g);
        }
        parts
            .iter()
            .find_map(|p| find_sided(&norm, side, p))
            .map(|i| vec![i])
            .ok_or_else(|| {
                let looked: Vec<String> = parts
                    .iter()
                    .flat_map(|p| p.iter().take(4))
                    .map(|p| format!("{}{}", side.to_ascii_uppercase(), p.to_ascii_uppercase()))
                    .collect();
                missing(role, looked.join(", "))
            })
    };
    let left_heel = foot(&names.left_heel, "lheel", 'l', &[HEEL, ANKLE])?;
    let right_heel = foot(&names.right_heel, "rheel", 'r', &[HEEL, ANKLE])?;
    let ankle = |given: &Option<Vec<String>>, side: char| {
        given.is_none() && find_sided(&norm, side, HEEL).is_none()
    };
    let heel_is_ankle = [ankle(&names.left_heel, 'l'), ankle(&names.right_heel, 'r')];
    let left_toe = foot(&names.left_toe, "ltoe", 'l', &[TOE])?;
    let right_toe = foot(&names.right_toe, "rtoe", 'r', &[TOE])?;
    let pelvis = match &names.pelvis {
        Some(g) => by_names(labels, "pelvis", g)?,
        None => {
            let alone = SACRUM.iter().find_map(|s| norm.iter().position(|n| n == s));
            let pair = |parts: &[&str]| match (
                find_sided(&norm, 'l', parts),
                find_sided(&norm, 'r', parts),
            ) {
                (Some(l), Some(r)) => Some(vec![l, r]),
                _ => None,
            };
            alone
                .map(|i| vec![i])
                .or_else(|| pair(PSIS))
                .or_else(|| pair(ASIS))
                .ok_or_else(|| missing("pelvis", "SACR, LPSI+RPSI, LASI+RASI".into()))?
        }
    };
    Ok(MarkerChoice {
        left_heel,
        right_heel,
        left_toe,
        right_toe,
        pelvis,
        heel_is_ankle,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn labels(v: &[&str]) -> Vec<String> {
        v.iter().map(|s| s.to_string()).collect()
    }

    #[test]
    fn plug_in_gait_with_prefix() {
        let l = labels(&[
            "Matt:RHEE",
            "Matt:LHEE",
            "Matt:LTOE",
            "Matt:RTOE",
            "Matt:LPSI",
            "Matt:RPSI",
        ]);
        let m = find_markers(&l, &MarkerNames::default()).unwrap();
        assert_eq!(m.left_heel, vec![1]);
        assert_eq!(m.right_heel, vec![0]);
        assert_eq!(m.pelvis, vec![4, 5]);
    }

    #[test]
    fn other_sets_and_fallbacks() {
        let l = labels(&["L_FCC", "R_FCC", "L_FM2", "R_FM2", "L_IAS", "R_IAS"]);
        let m = find_markers(&l, &MarkerNames::default()).unwrap();
        assert_eq!(
            (m.left_heel[0], m.right_toe[0], m.pelvis.clone()),
            (0, 3, vec![4, 5])
        );
        // No heel: the ankle stands in.
        let l = labels(&["LANK", "RANK", "LTOE", "RTOE", "SACR"]);
        let m = find_markers(&l, &MarkerNames::default()).unwrap();
        assert_eq!((m.left_heel[0], m.pelvis.clone()), (0, vec![4]));
        assert_eq!(m.heel_is_ankle, [true, true]);
        let l = labels(&["l heel", "r heel", "l toe", "r toe", "sacrum"]);
        assert!(find_markers(&l, &MarkerNames::default()).is_ok());
    }

    #[test]
    fn names_given_and_errors() {
        let l = labels(&["A", "B", "C", "D", "E", "F"]);
        let e = find_markers(&l, &MarkerNames::default()).unwrap_err();
        assert!(e.to_string().contains("no lheel marker"), "{e}");
        let n = MarkerNames::parse(&[
            "lheel=A,rheel=B".into(),
            "ltoe=C".into(),
            "rtoe=d".into(),
            "pelvis=E+F".into(),
        ])
        .unwrap();
        let m = find_markers(&l, &n).unwrap();
        assert_eq!((m.right_toe[0], m.pelvis.clone()), (3, vec![4, 5]));
        assert!(MarkerNames::parse(&["knee=A".into()]).is_err());
        let n = MarkerNames::parse(&["lheel=Z".into()]).unwrap();
        assert!(matches!(
            find_markers(&l, &n),
            Err(Error::UnknownMarker { .. })
        ));
    }
}
