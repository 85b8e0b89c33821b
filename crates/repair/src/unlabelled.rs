//! Which trajectories are unlabelled: the one rule every stage and front end asks.
//!
//! A capture system that loses a marker and finds it again often starts a new trajectory it
//! cannot name, and exports it under a placeholder instead of the marker's label. Those
//! points are candidates for the marker's gaps (see [`crate::reclaim`]), not markers: no
//! fill, swap search or summary speaks of them. The placeholders seen in the corpora and
//! the systems' manuals are recognised here ([`is_common_placeholder`]); a lab with its own
//! adds a glob ([`Unlabelled::with_pattern`]).

use std::fmt;
use std::str::FromStr;

/// The rule: the common placeholders, and optionally a user's glob.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Unlabelled {
    pattern: Option<Glob>,
}

impl Unlabelled {
    /// The common placeholders only.
    pub fn common() -> Unlabelled {
        Unlabelled::default()
    }

    /// The common placeholders and labels matching `pattern`.
    pub fn with_pattern(pattern: Glob) -> Unlabelled {
        Unlabelled {
            pattern: Some(pattern),
        }
    }

    /// The user's glob, if any.
    pub fn pattern(&self) -> Option<&Glob> {
        self.pattern.as_ref()
    }

    /// Whether a point of this label is unlabelled.
    pub fn is_unlabelled(&self, label: &str) -> bool {
        is_common_placeholder(label) || self.pattern.as_ref().is_some_and(|g| g.matches(label))
    }
}

/// The placeholders capture systems write for a trajectory they could not label, in any
/// case, with surrounding blanks ignored and after a subject prefix (`Subject:`):
///
/// - an empty label (MotionMonitor's `sample_24`),
/// - `*` and a number (Vicon Nexus: `*51` in the c3d-labs walkway trials, pyCGM's `*115`,
///   the puppeteer walk's `*1`),
/// - `Unlabeled`/`Unlabelled` and `uname`, alone or followed by a number, possibly after a
///   blank, `_`, `-`, `*` or `#` (`Unlabeled 3`, OptiTrack Motive; `uname*2`, Cortex).
///
/// A label of digits alone is a name (`2000` in the golf and basketball trials of
/// c3d-samples number their markers), not a placeholder.
pub fn is_common_placeholder(label: &str) -> bool {
    let l = label.trim();
    let l = l.rsplit(':').next().unwrap_or(l).trim();
    if l.is_empty() {
        return true;
    }
    let digits_after = |rest: &str| {
        let rest = rest.trim_start_matches([' ', '_', '-', '*', '#']);
        rest.chars().all(|c| c.is_ascii_digit())
    };
    if let Some(rest) = l.strip_prefix('*') {
        return rest.chars().all(|c| c.is_ascii_digit());
    }
    let lower = l.to_ascii_lowercase();
    ["unlabeled", "unlabelled", "uname"]
        .iter()
        .any(|p| lower.strip_prefix(p).is_some_and(digits_after))
}

/// A label glob: `*` any run of characters, `?` one character, everything else itself
/// (case-insensitive, surrounding blanks of the label ignored).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Glob(String);

impl Glob {
    /// Whether `label` matches.
    pub fn matches(&self, label: &str) -> bool {
        let p: Vec<char> = self.0.to_lowercase().chars().collect();
        let s: Vec<char> = label.trim().to_lowercase().chars().collect();
        glob_match(&p, &s)
    }
}

/// Iterative wildcard matching with one backtrack point (the last `*`): linear in practice,
/// never exponential.
fn glob_match(p: &[char], s: &[char]) -> bool {
    let (mut i, mut j) = (0, 0);
    let mut star: Option<(usize, usize)> = None;
    while j < s.len() {
        if i < p.len() && (p[i] == '?' || p[i] == s[j]) {
            i += 1;
            j += 1;
        } else if i < p.len() && p[i] == '*' {
            star = Some((i, j));
            i += 1;
        } else if let Some((si, sj)) = star {
            i = si + 1;
            j = sj + 1;
            star = Some((si, sj + 1));
        } else {
            return false;
        }
    }
    p[i..].iter().all(|&c| c == '*')
}

impl fmt::Display for Glob {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

impl FromStr for Glob {
    type Err = crate::ParseError;

    /// Any non-empty text; a glob of blanks would match only empty labels, which are
    /// unlabelled anyway, so it is refused as a likely mistake.
    fn from_str(s: &str) -> Result<Glob, crate::ParseError> {
        if s.trim().is_empty() {
            return Err(crate::ParseError::Malformed {
                what: "unlabelled pattern",
                given: s.to_string(),
                expected: "a label glob such as \"M*\" or \"?unk*\"",
            });
        }
        Ok(Glob(s.trim().to_string()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_corpora_placeholders_are_unlabelled_and_names_are_not() {
        for l in [
            "*51",
            " *115 ",
            "*",
            "",
            "   ",
            "Unlabeled 3",
            "unlabelled",
            "UNLABELED_12",
            "uname*2",
            "Uname 7",
            "Subject:*12",
        ] {
            assert!(is_common_placeholder(l), "{l:?}");
        }
        for l in [
            "LASI",
            "2000",
            "100000",
            "Point    1",
            "#",
            "*LASI",
            "Unlabeled marker on the box",
            "R.Shoulder",
            "Stick 1",
            "username",
        ] {
            assert!(!is_common_placeholder(l), "{l:?}");
        }
    }

    #[test]
    fn a_glob_adds_a_labs_own_placeholder() {
        let g: Glob = "M?_*".parse().unwrap();
        let u = Unlabelled::with_pattern(g);
        assert!(u.is_unlabelled("m1_x") && u.is_unlabelled("M2_") && u.is_unlabelled("*3"));
        assert!(!u.is_unlabelled("M12_x") && !u.is_unlabelled("LASI"));
        let star: Glob = "*".parse().unwrap();
        assert!(star.matches("anything") && star.matches(""));
        let mid: Glob = "a*b*c".parse().unwrap();
        assert!(mid.matches("aXXbYYc") && mid.matches("abc") && !mid.matches("acb"));
        assert!(" ".parse::<Glob>().is_err());
    }
}
