//! Which feet a person asks about: left, right or both. One spelling for every front (the
//! command line's `--side`, Python's `side=`), so the two cannot drift apart in what they
//! accept.

use crate::error::{Error, Result, Setting};
use gait::Side;
use std::fmt;
use std::str::FromStr;

/// The feet asked for.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Feet {
    Left,
    Right,
    #[default]
    Both,
}

impl Feet {
    /// The sides these feet are, left first.
    pub fn sides(self) -> Vec<Side> {
        match self {
            Feet::Left => vec![Side::Left],
            Feet::Right => vec![Side::Right],
            Feet::Both => Side::BOTH.to_vec(),
        }
    }

    /// The name as people write it.
    pub fn name(self) -> &'static str {
        match self {
            Feet::Left => "left",
            Feet::Right => "right",
            Feet::Both => "both",
        }
    }
}

impl fmt::Display for Feet {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for Feet {
    type Err = Error;
    /// `left`, `right` or `both`, in any case; `l` and `r` for short.
    fn from_str(s: &str) -> Result<Self> {
        match s.trim().to_ascii_lowercase().as_str() {
            "left" | "l" => Ok(Feet::Left),
            "right" | "r" => Ok(Feet::Right),
            "both" => Ok(Feet::Both),
            _ => Err(Error::Invalid {
                setting: Setting::Side,
                value: s.to_string(),
                why: "expected left, right or both".into(),
            }),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_spelling_reads_and_a_wrong_one_names_the_setting() {
        for (s, f) in [
            ("left", Feet::Left),
            (" R ", Feet::Right),
            ("BOTH", Feet::Both),
        ] {
            assert_eq!(s.parse::<Feet>().ok(), Some(f), "{s}");
            assert_eq!(f.to_string().parse::<Feet>().ok(), Some(f));
        }
        assert_eq!(Feet::Both.sides(), vec![Side::Left, Side::Right]);
        let e = "up".parse::<Feet>().expect_err("no such foot");
        assert_eq!(e.to_string(), "side up: expected left, right or both");
    }
}
