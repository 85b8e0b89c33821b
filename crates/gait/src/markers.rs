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
//! Beyond single names: a side may follow the name (`HEEL_L`, French `TLNG`: [`canonical`]);
//! numbered foot cluster markers (`LFT1`…) stand for a side without heel or toe names, told
//! apart by position ([`cluster_heel_toe`]); a pelvis may be a numbered cluster (`PV1`…),
//! CMU's waist markers or the trochanters; and a set that marks one leg only gives that
//! side ([`find_markers`]).
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
    "tln",
    "talon",
    // IOR/CAST's calcaneus (`RCA`), last: a bare "ca" is no other set's heel.
    "ca",
];
const ANKLE: &[&str] = &["ank", "lmal", "fal", "ankle", "lma", "mal", "mall", "mm"];
/// Toe names, best first: the second metatarsal head (Plug-in Gait's TOE) before the first
/// and fifth, and a lateral toe marker (`LLA_TOE`, tsalemink's AUC set) last.
const TOE: &[&str] = &[
    "toe", "to", "mt2", "fm2", "toetip", "ttoe", "toefoot", "met", "mt1", "fm1", "p1mt", "met1",
    "mt5", "fm5", "p5mt", "met5", "mh1", "mh5", "latoe",
    // IOR/CAST's metatarsal heads by Roman numeral: second (`RIIMH`), first (`RIMH`), fifth
    // (`RVMH`), in the order above.
    "iimh", "imh", "vmh", "fmh", "fm",
];
/// Beginnings of labels that name a part of the foot with a qualifier after it
/// (`L.Heel.Bottom`, `LHeelTop`, `LCalcExt`; `L.MT1.Dorsal`, `RToeTip2`): when a side has
/// no heel or no toe by the names above, its markers named so (and those above) are the
/// foot's landmarks, whose heel and toe are told by their positions ([`cluster_heel_toe`]).
const HEEL_STEMS: &[&str] = &["heel", "calc"];
const TOE_STEMS: &[&str] = &["toe", "mt", "met", "hallux", "forefoot"];
/// Markers standing alone for the pelvis (sacrum, mid-PSIS).
const SACRUM: &[&str] = &[
    "sacr", "sacrum", "sac", "vsac", "mpsi", "sacral", "s1", "ppsi", "pelv", "pelvis",
];
/// Paired pelvis markers: PSIS first (their mean is the sacrum; CMU's back waist markers
/// `LBWT`/`RBWT` sit on them), then ASIS (CMU's front waist `LFWT`/`RFWT`), then the greater
/// trochanters (`LTRO`, `L_FTC`), which travel with the pelvis over a stride and stand for
/// it in sets that mark no pelvis landmark.
const PSIS: &[&str] = &["psi", "psis", "ips", "pis", "bwt", "eips"];
const ASIS: &[&str] = &["asi", "asis", "ias", "ais", "fwt", "eias"];
const TROCHANTER: &[&str] = &["tro", "troc", "gtr", "ftc", "gt"];
/// French names that carry their side as a last letter, `G` (gauche) or `D` (droite), with
/// no separator (`TLNG`, talon gauche; `MT1D`; `GTG`, grand trochanter gauche; `EIASD`).
const FRENCH_SUFFIXED: &[&str] = &[
    "tln", "talon", "mt1", "mt2", "mt5", "orteil", "gt", "eias", "eips",
];
/// Stems of numbered foot cluster markers (`LFT1`…`LFT3`, `LFOOT1`): markers fixed to the
/// shoe or foot with no landmark named, whose heel and toe are told by their positions
/// ([`cluster_heel_toe`]).
const FOOT_CLUSTER: &[&str] = &["ft", "foot", "foo"];
/// Stems of numbered pelvis cluster markers (`PV1`…`PV4`, `RPV1`…`RPV3`): their mean
/// travels with the pelvis.
const PELVIS_CLUSTER: &[&str] = &["pv", "pel", "pelv", "pelvis"];

/// The label as searched: [`normalise`]d, with a side given after the name moved before it
/// (`HEEL_L`, `Toe.Right` → `lheel`, `rtoe`: a separator, then `l`, `r`, `left` or `right`;
/// French `TLNG`, `MT1D` → `ltln`, `rmt1`, for the names in `FRENCH_SUFFIXED` only, since a
/// final `g` or `d` is otherwise part of a name).
pub fn canonical(label: &str) -> String {
    let bare = label.rsplit(':').next().unwrap_or(label).trim();
    if let Some((head, tail)) = bare.rsplit_once(['_', '.', '-', ' ']) {
        let side = match tail.to_ascii_lowercase().as_str() {
            "l" | "left" => Some('l'),
            "r" | "right" => Some('r'),
            _ => None,
        };
        let head = normalise(head);
        if let (Some(side), false) = (side, head.is_empty()) {
            return format!("{side}{head}");
        }
    }
    let n = normalise(bare);
    if let Some(stem) = n.strip_suffix('g').filter(|s| FRENCH_SUFFIXED.contains(s)) {
        return format!("l{stem}");
    }
    if let Some(stem) = n.strip_suffix('d').filter(|s| FRENCH_SUFFIXED.contains(s)) {
        return format!("r{stem}");
    }
    n
}

/// One-letter French names with their side as a second letter, `D` (droite) or `G` (gauche),
/// as `c3d-samples`' `admarche2` writes a whole body (`PD` pied, `CD` cheville, `JD` jambe,
/// `GD` genou, `FD` fémur, `BD` bassin, `ED` épaule): the letters of the roles searched,
/// with the names they are searched as. The forefoot marker (`P`) lies 136 mm ahead of the
/// ankle's (`C`) along the walk and 30 mm lower there; `B` sits at the pelvis's front height.
const FRENCH_ONE_LETTER: &[(char, &str)] = &[('p', "toe"), ('c', "ank"), ('b', "asi")];

/// The least number of one-letter sided pairs (`PD`/`PG` …) that make a label set a
/// one-letter French set: a whole body named so, not a stray `CG` (a centre of gravity) or
/// `PD` among longer names.
const FRENCH_ONE_LETTER_PAIRS: usize = 5;

/// Every label as searched ([`canonical`]); in a one-letter French set (see
/// `FRENCH_ONE_LETTER`), its forefoot, ankle and pelvis markers under the names searched.
pub fn canonical_all(labels: &[String]) -> Vec<String> {
    let mut norm: Vec<String> = labels.iter().map(|l| canonical(l)).collect();
    let one_letter = |n: &str, side: char| {
        let b = n.as_bytes();
        b.len() == 2 && b[0].is_ascii_lowercase() && b[1] as char == side
    };
    let pairs = norm
        .iter()
        .filter(|n| one_letter(n, 'd'))
        .filter(|n| {
            norm.iter()
                .any(|m| one_letter(m, 'g') && m.as_bytes()[0] == n.as_bytes()[0])
        })
        .count();
    let has = |n: &str| norm.iter().any(|m| m == n);
    if pairs < FRENCH_ONE_LETTER_PAIRS || !(has("pd") && has("pg")) {
        return norm;
    }
    for n in norm.iter_mut() {
        let b = n.as_bytes();
        if b.len() != 2 {
            continue;
        }
        let side = match b[1] {
            b'd' => 'r',
            b'g' => 'l',
            _ => continue,
        };
        if let Some((_, name)) = FRENCH_ONE_LETTER.iter().find(|(c, _)| *c as u8 == b[0]) {
            *n = format!("{side}{name}");
        }
    }
    norm
}

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
    /// Left and right: the side's heel and toe lists both hold its foot cluster markers
    /// (no heel or toe label known), to be told apart by [`cluster_heel_toe`].
    pub foot_cluster: [bool; 2],
    /// Left and right: the markers among which the heel and toe were told apart by their
    /// positions (a cluster or the foot's landmarks), once they have been; empty otherwise.
    pub by_position: [Vec<usize>; 2],
    /// Other markers that stood in for a role's chosen one where it is missing, as the
    /// caller filled them (see [`candidates`]).
    pub stand_ins: Vec<StandIn>,
}

/// A marker standing in for a role's chosen marker over the frames it is missing.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct StandIn {
    /// `lheel`, `ltoe`, `rheel` or `rtoe`.
    pub role: &'static str,
    /// The role's chosen marker and the one standing in (point indices).
    pub chosen: usize,
    pub marker: usize,
    /// Frames filled.
    pub frames: usize,
    /// The marker was found by moving rigidly with the chosen one, not by its name.
    pub rigid: bool,
}

/// The markers of `side` (`'l'` or `'r'`) named as a heel (`heel`) or as a toe part,
/// best first by the preference of their names: a role's candidates, of which the first
/// seen stands in where the chosen one is missing (MOtoNMS' right foot: `RIMH` missing
/// where `RVMH` is seen).
pub fn candidates(labels: &[String], side: char, heel: bool) -> Vec<usize> {
    let norm = canonical_all(labels);
    let parts = if heel { HEEL } else { TOE };
    let mut out = Vec::new();
    for part in parts {
        for (i, n) in norm.iter().enumerate() {
            if split_side(n).is_some_and(|(s, rest)| s == side && rest == *part)
                && !out.contains(&i)
            {
                out.push(i);
            }
        }
    }
    out
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
    let norm = canonical_all(labels);
    find_sided(&norm, side, ANKLE)
}

/// Whether `part` is one of `stems` followed by digits (or by nothing): `ft1`, `pv4`.
fn numbered(part: &str, stems: &[&str]) -> bool {
    let stem = part.trim_end_matches(|c: char| c.is_ascii_digit());
    stems.contains(&stem)
}

/// The foot cluster markers of `side` (file order).
fn foot_cluster(norm: &[String], side: char) -> Vec<usize> {
    norm.iter()
        .enumerate()
        .filter(|(_, n)| {
            split_side(n).is_some_and(|(s, rest)| s == side && numbered(rest, FOOT_CLUSTER))
        })
        .map(|(i, _)| i)
        .collect()
}

/// The foot landmarks of `side` (file order): its markers whose label names a heel or a
/// toe part ([`HEEL`], [`TOE`]) or begins with one ([`HEEL_STEMS`], [`TOE_STEMS`]), when
/// they hold at least one of each kind and three markers or more, or one of each kind
/// with a qualified name among them (`L.Heel.Bottom` and `L.MT1`). Their heel and toe are
/// then the rearmost and the foremost along the walking direction, as for a cluster: where
/// names are ambiguous (three heel markers, two metatarsal heads, `Heel.Top` and
/// `Heel.Bottom`), the positions are not.
fn foot_landmarks(norm: &[String], side: char) -> Option<Vec<usize>> {
    let mut heels = 0;
    let mut toes = 0;
    let mut qualified = false;
    let mut out = Vec::new();
    for (i, n) in norm.iter().enumerate() {
        let Some((s, rest)) = split_side(n) else {
            continue;
        };
        if s != side {
            continue;
        }
        let heel_stem = HEEL_STEMS.iter().any(|h| rest.starts_with(h));
        let toe_stem = TOE_STEMS.iter().any(|t| rest.starts_with(t));
        let exact_heel = HEEL.contains(&rest);
        let exact_toe = TOE.contains(&rest);
        if exact_heel || heel_stem {
            heels += 1;
        } else if exact_toe || toe_stem {
            toes += 1;
        } else {
            continue;
        }
        qualified |= (heel_stem && !exact_heel) || (toe_stem && !exact_toe);
        out.push(i);
    }
    (heels > 0 && toes > 0 && (out.len() >= 3 || qualified)).then_some(out)
}

/// The pelvis cluster markers, sided or not (`PV1`, `RPV2`), if at least two.
fn pelvis_cluster(norm: &[String]) -> Option<Vec<usize>> {
    let v: Vec<usize> = norm
        .iter()
        .enumerate()
        .filter(|(_, n)| {
            let has_digit = n.chars().any(|c| c.is_ascii_digit());
            has_digit
                && (numbered(n, PELVIS_CLUSTER)
                    || split_side(n).is_some_and(|(_, rest)| numbered(rest, PELVIS_CLUSTER)))
        })
        .map(|(i, _)| i)
        .collect();
    (v.len() >= 2).then_some(v)
}

/// One side's heel and toe as found (either may be missing).
struct SideFoot {
    heel: Result<Vec<usize>>,
    toe: Result<Vec<usize>>,
    ankle: bool,
    cluster: bool,
    /// A name was given by a person for this side's heel or toe.
    named: bool,
}

impl SideFoot {
    fn complete(&self) -> bool {
        self.heel.is_ok() && self.toe.is_ok()
    }
}

/// Choose the markers of each role among `labels` (the point labels, in file order),
/// taking `names` first where given.
///
/// A side whose heel or toe is found by no name (a set that marks one leg only) is left
/// empty, and the detectors give that side no events, as long as the other side has both
/// and no name was given for it; with neither side complete the error names the first
/// role missing. A side with no heel or toe names but numbered foot cluster markers gets
/// the whole cluster in both roles, with [`MarkerChoice::foot_cluster`] set: the caller
/// tells heel from toe by their positions ([`cluster_heel_toe`]).
pub fn find_markers(labels: &[String], names: &MarkerNames) -> Result<MarkerChoice> {
    let norm = canonical_all(labels);
    let left = side_foot(labels, &norm, 'l', &names.left_heel, &names.left_toe);
    let right = side_foot(labels, &norm, 'r', &names.right_heel, &names.right_toe);
    enough_feet(labels, &left, &right)?;
    let pelvis = pelvis_markers(labels, &norm, &names.pelvis)?;
    Ok(choice(&left, &right, pelvis))
}

/// The error of a role found by no name: what was looked for.
fn no_marker(what: &str, looked: String) -> Error {
    Error::NoMarker {
        what: what.to_string(),
        looked_for: looked,
    }
}

/// One foot role's markers: the names `given` by a person, else the first label of `side`
/// by the preference of `parts` (a list of name lists, tried in turn), else why not.
fn foot_role(
    labels: &[String],
    norm: &[String],
    given: &Option<Vec<String>>,
    role: &str,
    side: char,
    parts: &[&[&str]],
) -> Result<Vec<usize>> {
    if let Some(g) = given {
        return by_names(labels, role, g);
    }
    parts
        .iter()
        .find_map(|p| find_sided(norm, side, p))
        .map(|i| vec![i])
        .ok_or_else(|| {
            let mut looked: Vec<String> = parts
                .iter()
                .flat_map(|p| p.iter().take(4))
                .map(|p| format!("{}{}", side.to_ascii_uppercase(), p.to_ascii_uppercase()))
                .collect();
            looked.push(format!("{}FT1…", side.to_ascii_uppercase()));
            no_marker(role, looked.join(", "))
        })
}

/// One side's heel and toe: by name (the ankle standing in for a missing heel), else its
/// numbered foot cluster, else its foot landmarks, each in both roles to be told apart by
/// position ([`foot_cluster`], [`foot_landmarks`]).
fn side_foot(
    labels: &[String],
    norm: &[String],
    side: char,
    heel: &Option<Vec<String>>,
    toe: &Option<Vec<String>>,
) -> SideFoot {
    let prefix = side.to_string();
    let mut f = SideFoot {
        heel: foot_role(
            labels,
            norm,
            heel,
            &format!("{prefix}heel"),
            side,
            &[HEEL, ANKLE],
        ),
        toe: foot_role(labels, norm, toe, &format!("{prefix}toe"), side, &[TOE]),
        ankle: heel.is_none() && find_sided(norm, side, HEEL).is_none(),
        cluster: false,
        named: heel.is_some() || toe.is_some(),
    };
    let by_position = |markers: Vec<usize>| SideFoot {
        heel: Ok(markers.clone()),
        toe: Ok(markers),
        ankle: false,
        cluster: true,
        named: false,
    };
    if !f.named && !f.complete() {
        let cluster = foot_cluster(norm, side);
        if !cluster.is_empty() {
            f = by_position(cluster);
        }
    }
    if !f.named && (!f.complete() || f.ankle) && !f.cluster {
        if let Some(landmarks) = foot_landmarks(norm, side) {
            f = by_position(landmarks);
        }
    }
    f
}

/// Whether the feet found will do: some foot marker at all, and each side that is
/// incomplete either left out (the other side complete, nothing named for it) or the
/// reason its first missing role gives.
fn enough_feet(labels: &[String], left: &SideFoot, right: &SideFoot) -> Result<()> {
    let any_foot = |f: &SideFoot| f.named || f.cluster || f.heel.is_ok() || f.toe.is_ok();
    if !any_foot(left) && !any_foot(right) {
        return Err(Error::NoFootMarkers {
            markers: labels.iter().filter(|l| !l.trim().is_empty()).count(),
        });
    }
    for (this, other) in [(left, right), (right, left)] {
        if !this.complete() && (this.named || !other.complete()) {
            this.heel.clone()?;
            this.toe.clone()?;
        }
    }
    Ok(())
}

/// The pelvis markers: named by a person, else the sacrum alone, the PSIS pair, the ASIS
/// pair, a pelvis cluster or the trochanters, in that order.
fn pelvis_markers(
    labels: &[String],
    norm: &[String],
    given: &Option<Vec<String>>,
) -> Result<Vec<usize>> {
    if let Some(g) = given {
        return by_names(labels, "pelvis", g);
    }
    let alone = SACRUM.iter().find_map(|s| norm.iter().position(|n| n == s));
    let pair = |parts: &[&str]| match (find_sided(norm, 'l', parts), find_sided(norm, 'r', parts)) {
        (Some(l), Some(r)) => Some(vec![l, r]),
        _ => None,
    };
    alone
        .map(|i| vec![i])
        .or_else(|| pair(PSIS))
        .or_else(|| pair(ASIS))
        .or_else(|| pelvis_cluster(norm))
        .or_else(|| pair(TROCHANTER))
        .ok_or_else(|| {
            no_marker(
                "pelvis",
                "SACR, LPSI+RPSI, LASI+RASI, PV1+PV2…, LTRO+RTRO".into(),
            )
        })
}

/// The choice made of the two sides (an incomplete side left empty) and the pelvis.
fn choice(left: &SideFoot, right: &SideFoot, pelvis: Vec<usize>) -> MarkerChoice {
    let take = |f: &SideFoot| {
        if f.complete() {
            (
                f.heel.clone().unwrap_or_default(),
                f.toe.clone().unwrap_or_default(),
            )
        } else {
            (Vec::new(), Vec::new())
        }
    };
    let ((left_heel, left_toe), (right_heel, right_toe)) = (take(left), take(right));
    MarkerChoice {
        heel_is_ankle: [
            left.complete() && left.ankle && !left.cluster,
            right.complete() && right.ankle && !right.cluster,
        ],
        foot_cluster: [
            left.complete() && left.cluster,
            right.complete() && right.cluster,
        ],
        left_heel,
        right_heel,
        left_toe,
        right_toe,
        pelvis,
        by_position: Default::default(),
        stand_ins: Vec::new(),
    }
}

/// Which of a foot cluster's markers are its heel and its toe (indices into `markers`):
/// the one farthest back along the walking direction, relative to the cluster's centre,
/// and the one farthest forward (the median over the frames where every marker, the
/// pelvis and the direction are known). `direction` is the walking direction per frame
/// (unit, horizontal; NaN where unknown). `None` without such a frame.
pub fn cluster_heel_toe(markers: &[&[[f64; 3]]], direction: &[[f64; 3]]) -> Option<(usize, usize)> {
    let n = markers.len();
    if n == 0 {
        return None;
    }
    let mut along: Vec<Vec<f64>> = vec![Vec::new(); n];
    for (f, d) in direction.iter().enumerate() {
        let ps: Option<Vec<[f64; 3]>> = markers
            .iter()
            .map(|m| {
                m.get(f)
                    .copied()
                    .filter(|p| p.iter().all(|v| v.is_finite()))
            })
            .collect();
        let Some(ps) = ps else { continue };
        if !d.iter().all(|v| v.is_finite()) {
            continue;
        }
        let mut c = [0.0; 3];
        for p in &ps {
            for k in 0..3 {
                c[k] += p[k] / n as f64;
            }
        }
        for (i, p) in ps.iter().enumerate() {
            along[i].push((0..3).map(|k| (p[k] - c[k]) * d[k]).sum());
        }
    }
    let med: Vec<f64> = along
        .iter()
        .map(|v| crate::signal::quantile(v, 0.5).unwrap_or(f64::NAN))
        .collect();
    if med.iter().any(|v| !v.is_finite()) {
        return None;
    }
    let heel = (0..n).min_by(|&a, &b| med[a].total_cmp(&med[b]))?;
    let toe = (0..n).max_by(|&a, &b| med[a].total_cmp(&med[b]))?;
    Some((heel, toe))
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
        assert!(
            e.to_string()
                .contains("no foot markers: none of the trial's 6 markers"),
            "{e}"
        );
        // A set with a heel but no toe says which role is missing.
        let l2 = labels(&["LHEE", "RHEE", "SACR"]);
        let e = find_markers(&l2, &MarkerNames::default()).unwrap_err();
        assert_eq!(
            e.to_string(),
            "no ltoe marker: looked for LTOE, LTO, LMT2, LFM2, LFT1…"
        );
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

    #[test]
    fn clusters_waists_trochanters_and_one_sided_sets() {
        // C3D.org's foot triads and pelvis cluster (sample_01's Eb015): the whole cluster
        // in both roles, to be told apart by position.
        let l = labels(&[
            "RFT1", "RFT2", "RFT3", "LFT1", "LFT2", "LFT3", "RSK1", "PV1", "PV2", "PV3", "pv4",
        ]);
        let m = find_markers(&l, &MarkerNames::default()).unwrap();
        assert_eq!(m.foot_cluster, [true, true]);
        assert_eq!(
            (m.left_heel.clone(), m.right_toe.clone()),
            (vec![3, 4, 5], vec![0, 1, 2])
        );
        assert_eq!(m.pelvis, vec![7, 8, 9, 10]);
        assert_eq!(m.heel_is_ankle, [false, false]);
        // CMU's waist markers; a named heel and toe win over a cluster.
        let l = labels(&[
            "Male:LBWT",
            "Male:RBWT",
            "Male:LHEE",
            "Male:LTOE",
            "Male:RHEE",
            "Male:RTOE",
        ]);
        let m = find_markers(&l, &MarkerNames::default()).unwrap();
        assert_eq!(
            (m.pelvis.clone(), m.foot_cluster),
            (vec![0, 1], [false, false])
        );
        // Trochanters when no pelvis landmark is marked (sample_27's kyowadengyo).
        let l = labels(&["LTRO", "RTRO", "LANK", "RANK", "LMT5", "RMT5"]);
        let m = find_markers(&l, &MarkerNames::default()).unwrap();
        assert_eq!(
            (m.pelvis.clone(), m.left_toe.clone()),
            (vec![0, 1], vec![4])
        );
        // One leg marked (sample_21): the other side is empty, not an error.
        let l = labels(&["LASI", "SACR", "RASI", "RANK", "RHEE", "RTOE"]);
        let m = find_markers(&l, &MarkerNames::default()).unwrap();
        assert_eq!(
            (m.right_heel.clone(), m.right_toe.clone()),
            (vec![4], vec![5])
        );
        assert!(m.left_heel.is_empty() && m.left_toe.is_empty());
        // ... unless a name was given for it.
        let n = MarkerNames::parse(&["lheel=SACR".into()]).unwrap();
        assert!(find_markers(&l, &n).is_err());
    }

    #[test]
    fn a_clusters_heel_is_its_rearmost_marker_and_its_toe_its_foremost() {
        // Walking along +y: marker 0 in front, 1 on top, 2 behind (Eb015's LFT1-3).
        let frames = 50;
        let at = |x: f64, y: f64, z: f64| -> Vec<[f64; 3]> {
            (0..frames).map(|f| [x, y + 10.0 * f as f64, z]).collect()
        };
        let (a, b, c) = (
            at(250.0, 230.0, 37.0),
            at(212.0, 220.0, 89.0),
            at(243.0, 160.0, 38.0),
        );
        let dir = vec![[0.0, 1.0, 0.0]; frames];
        let got = cluster_heel_toe(&[&a, &b, &c], &dir);
        assert_eq!(got, Some((2, 0)));
        // Walking the other way swaps them; no direction, no answer.
        let back = vec![[0.0, -1.0, 0.0]; frames];
        assert_eq!(cluster_heel_toe(&[&a, &b, &c], &back), Some((0, 2)));
        let none = vec![[f64::NAN; 3]; frames];
        assert_eq!(cluster_heel_toe(&[&a, &b, &c], &none), None);
    }

    #[test]
    fn a_one_letter_french_set_names_its_forefoot_ankle_and_pelvis() {
        // c3d-samples' admarche2: pied, cheville, jambe, genou, fémur, bassin, épaule per
        // side, then SS, C7 and OG.
        let l = labels(&[
            "PD", "CD", "JD", "GD", "FD", "BD", "ED", "PG", "CG", "JG", "GG", "FG", "BG", "EG",
            "SS", "C7", "OG",
        ]);
        let m = find_markers(&l, &MarkerNames::default()).unwrap();
        assert_eq!(
            (m.right_toe.clone(), m.right_heel.clone()),
            (vec![0], vec![1])
        );
        assert_eq!(
            (m.left_toe.clone(), m.left_heel.clone()),
            (vec![7], vec![8])
        );
        assert_eq!(m.heel_is_ankle, [true, true]);
        assert_eq!(m.pelvis, vec![12, 5]);
        // A stray `CG` or `PD` among longer names is no such set.
        let stray = labels(&[
            "LHEE", "RHEE", "LTOE", "RTOE", "SACR", "PD", "PG", "CG", "CD",
        ]);
        assert_eq!(canonical_all(&stray)[5..], ["pd", "pg", "cg", "cd"]);
    }

    #[test]
    fn anatomical_landmark_sets_and_qualified_names() {
        // IOR/CAST (MOtoNMS' Padova walks): calcaneus and metatarsal heads by numeral.
        let l = labels(&[
            "RPSIS", "LPSIS", "RLM", "LLM", "RMM", "LMM", "RCA", "LCA", "RVMH", "LVMH", "RIMH",
            "LIMH", "RIIT", "LIIT",
        ]);
        let m = find_markers(&l, &MarkerNames::default()).unwrap();
        assert_eq!(
            (m.left_heel.clone(), m.left_toe.clone(), m.right_toe.clone()),
            (vec![7], vec![11], vec![10])
        );
        assert_eq!(m.heel_is_ankle, [false, false]);
        assert_eq!(m.foot_cluster, [false, false]);
        // RBDS: three heel markers with qualifiers and two metatarsal heads, told apart by
        // position (the whole set in both roles).
        let l = labels(&[
            "L.ASIS",
            "L.Heel.Bottom",
            "L.Heel.Lateral",
            "L.Heel.Top",
            "L.MT1",
            "L.MT5",
            "L.PSIS",
            "R.Heel.Top",
            "R.MT1",
            "R.PSIS",
        ]);
        let m = find_markers(&l, &MarkerNames::default()).unwrap();
        assert_eq!(m.foot_cluster, [true, true]);
        assert_eq!(m.left_heel, vec![1, 2, 3, 4, 5]);
        assert_eq!(m.right_toe, vec![7, 8]);
        assert_eq!(m.pelvis, vec![6, 9]);
        // An ankle-and-toe set keeps the ankle for the heel (no landmark names a heel).
        let l = labels(&["LANK", "RANK", "LTOE", "RTOE", "LMT5", "RMT5", "SACR"]);
        let m = find_markers(&l, &MarkerNames::default()).unwrap();
        assert_eq!(
            (m.heel_is_ankle, m.foot_cluster),
            ([true, true], [false, false])
        );
        // Hand and wrist names that begin like foot parts are no foot.
        let l = labels(&["RCAR", "LCAR", "RMETA", "SACR"]);
        assert!(matches!(
            find_markers(&l, &MarkerNames::default()),
            Err(Error::NoFootMarkers { markers: 4 })
        ));
    }

    #[test]
    fn sides_written_after_the_name() {
        // A French set (c3d-samples' marche281): talon, 1st metatarsal, great trochanter,
        // gauche / droite.
        let l = labels(&["MT1G", "MT5G", "TLNG", "GTG", "MT1D", "TLND", "GTD", "CDG"]);
        let m = find_markers(&l, &MarkerNames::default()).unwrap();
        assert_eq!(
            (m.left_heel.clone(), m.left_toe.clone()),
            (vec![2], vec![0])
        );
        assert_eq!(
            (m.right_heel.clone(), m.right_toe.clone()),
            (vec![5], vec![4])
        );
        assert_eq!(m.pelvis, vec![3, 6]);
        // Separated suffixes; a final g or d elsewhere is part of the name.
        assert_eq!(canonical("Sub:HEEL_L"), "lheel");
        assert_eq!(canonical("Toe.Right"), "rtoe");
        assert_eq!(canonical("SACR"), "sacr");
        assert_eq!(canonical("HEAD"), "head");
        assert_eq!(canonical("L_HEEL"), "lheel");
    }
}
