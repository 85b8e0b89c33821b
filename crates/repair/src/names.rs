//! The names people write for what a repair does: fill methods, the spike detector and its
//! mode, the low-pass filters. Each is read by `FromStr` and written by `Display` from one
//! table or one grammar here, so the command line, the Python package, the reports and the
//! C3DFIX record spell them alike, and a refusal lists exactly what is accepted.
//!
//! Parsing checks the spelling and the numbers' syntax; the ranges (a half window from 1 to
//! [`MAX_HALF_WINDOW`], a filter order from 1 to [`MAX_ORDER`], …) are checked once, where
//! the configuration is built ([`crate::RepairConfig::new`]), since a cutoff can only be
//! judged against a trial's rate anyway.

use std::fmt;
use std::str::FromStr;

use crate::fill::FillMethod;
use crate::filter::FilterSpec;
use crate::spikes::{SpikeMode, SpikeOptions};
#[cfg(doc)]
use crate::{filter::MAX_ORDER, spikes::MAX_HALF_WINDOW};

/// Why a name or a specification was refused: what was being read, what was given and
/// what is accepted, in words that name no front end's flag or keyword.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum ParseError {
    /// A name outside the table.
    #[error("unknown {what} {given:?} (expected {expected})")]
    Unknown {
        what: &'static str,
        given: String,
        expected: String,
    },
    /// A specification that does not follow its grammar.
    #[error("{what} {given:?}: expected {expected}")]
    Malformed {
        what: &'static str,
        given: String,
        expected: &'static str,
    },
    /// A field of a specification that is not a number of its kind.
    #[error("{what} {field}: {given:?} is not a valid number")]
    Number {
        what: &'static str,
        field: &'static str,
        given: String,
    },
}

/// `a, b, c or d`, as refusals list the accepted names.
fn listed(names: &[&str]) -> String {
    match names {
        [] => String::new(),
        [one] => (*one).to_string(),
        [init @ .., last] => format!("{} or {last}", init.join(", ")),
    }
}

impl FillMethod {
    /// Every method a repair can be asked for, with its name, in the order help texts list
    /// them: the one list of names (the reports' serde names are the same, checked by a
    /// test). `hold` is `auto`'s last resort at a trial's edge, accepted on its own too.
    pub const NAMED: [(FillMethod, &'static str); 12] = [
        (FillMethod::Auto, "auto"),
        (FillMethod::Linear, "linear"),
        (FillMethod::Lagrange2, "lagrange2"),
        (FillMethod::Lagrange5, "lagrange5"),
        (FillMethod::Spline, "spline"),
        (FillMethod::Rigid, "rigid"),
        (FillMethod::Pattern, "pattern"),
        (FillMethod::Pca, "pca"),
        (FillMethod::Kalman, "kalman"),
        (FillMethod::Gloersen, "gloersen"),
        (FillMethod::Hold, "hold"),
        (FillMethod::None, "none"),
    ];

    /// The method's name, as reports and the C3DFIX record write it.
    pub fn name(self) -> &'static str {
        FillMethod::NAMED
            .iter()
            .find(|(m, _)| *m == self)
            .map_or("none", |(_, n)| n)
    }

    /// The accepted names, listed for a help text or a refusal.
    pub fn names_listed() -> String {
        listed(&FillMethod::NAMED.map(|(_, n)| n))
    }
}

impl fmt::Display for FillMethod {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for FillMethod {
    type Err = ParseError;

    /// A method by name, in any case.
    fn from_str(s: &str) -> Result<Self, ParseError> {
        FillMethod::NAMED
            .iter()
            .find(|(_, n)| n.eq_ignore_ascii_case(s))
            .map(|&(m, _)| m)
            .ok_or_else(|| ParseError::Unknown {
                what: "fill method",
                given: s.to_string(),
                expected: FillMethod::names_listed(),
            })
    }
}

impl SpikeMode {
    /// Both modes with their names.
    pub const NAMED: [(SpikeMode, &'static str); 2] =
        [(SpikeMode::Gap, "gap"), (SpikeMode::Median, "median")];

    /// The mode's name.
    pub fn name(self) -> &'static str {
        match self {
            SpikeMode::Gap => "gap",
            SpikeMode::Median => "median",
        }
    }
}

impl fmt::Display for SpikeMode {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for SpikeMode {
    type Err = ParseError;

    fn from_str(s: &str) -> Result<Self, ParseError> {
        SpikeMode::NAMED
            .iter()
            .find(|(_, n)| n.eq_ignore_ascii_case(s))
            .map(|&(m, _)| m)
            .ok_or_else(|| ParseError::Unknown {
                what: "spike mode",
                given: s.to_string(),
                expected: listed(&SpikeMode::NAMED.map(|(_, n)| n)),
            })
    }
}

/// The spike detector as people write it, `hampel[:K[:NSIGMA]]`: the Hampel identifier with
/// a half window of K samples and a threshold of NSIGMA scaled MADs, each defaulting to
/// [`SpikeOptions::default`]'s. A field left out stays left out when written back, so the
/// C3DFIX record says what was asked.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct SpikeSpec {
    /// K, samples on each side of the centre.
    pub half_window: Option<usize>,
    /// NSIGMA, scaled MADs.
    pub nsigma: Option<f64>,
}

impl SpikeSpec {
    /// The grammar, for refusals and help texts.
    pub const GRAMMAR: &'static str = "hampel[:K[:NSIGMA]]";

    /// The Hampel settings this spec asks for, with the mode, the smallest deviation that can
    /// be a spike (data units) and whether residuals from a local prediction are judged.
    /// Not yet checked: [`crate::RepairConfig::new`] checks them.
    pub fn options(&self, mode: SpikeMode, min_deviation: f64, detrend: bool) -> SpikeOptions {
        let d = SpikeOptions::default();
        SpikeOptions {
            half_window: self.half_window.unwrap_or(d.half_window),
            nsigma: self.nsigma.unwrap_or(d.nsigma),
            min_deviation,
            mode,
            detrend,
        }
    }
}

impl fmt::Display for SpikeSpec {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("hampel")?;
        if let Some(k) = self.half_window {
            write!(f, ":{k}")?;
            if let Some(n) = self.nsigma {
                write!(f, ":{n}")?;
            }
        }
        Ok(())
    }
}

/// One numeric field of a spec.
fn number<T: FromStr>(what: &'static str, field: &'static str, s: &str) -> Result<T, ParseError> {
    s.trim().parse().map_err(|_| ParseError::Number {
        what,
        field,
        given: s.to_string(),
    })
}

impl FromStr for SpikeSpec {
    type Err = ParseError;

    fn from_str(s: &str) -> Result<Self, ParseError> {
        const WHAT: &str = "spike detector";
        let malformed = || ParseError::Malformed {
            what: WHAT,
            given: s.to_string(),
            expected: SpikeSpec::GRAMMAR,
        };
        let p: Vec<&str> = s.split(':').collect();
        if !p[0].eq_ignore_ascii_case("hampel") || p.len() > 3 {
            return Err(malformed());
        }
        Ok(SpikeSpec {
            half_window: p.get(1).map(|k| number(WHAT, "K", k)).transpose()?,
            nsigma: p.get(2).map(|n| number(WHAT, "NSIGMA", n)).transpose()?,
        })
    }
}

impl FilterSpec {
    /// The grammar, for refusals and help texts.
    pub const GRAMMAR: &'static str =
        "butterworth:ORDER:CUTOFF_HZ or cheby2:ORDER:CUTOFF_HZ:ATTEN_DB";
}

impl fmt::Display for FilterSpec {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            FilterSpec::Butterworth { order, cutoff_hz } => {
                write!(f, "butterworth:{order}:{cutoff_hz}")
            }
            FilterSpec::Cheby2 {
                order,
                cutoff_hz,
                atten_db,
            } => write!(f, "cheby2:{order}:{cutoff_hz}:{atten_db}"),
        }
    }
}

impl FromStr for FilterSpec {
    type Err = ParseError;

    /// `butterworth` (or `butter`) and `cheby2`, in any case.
    fn from_str(s: &str) -> Result<Self, ParseError> {
        const WHAT: &str = "low-pass filter";
        let p: Vec<&str> = s.split(':').collect();
        match p.as_slice() {
            [k, o, c]
                if k.eq_ignore_ascii_case("butterworth") || k.eq_ignore_ascii_case("butter") =>
            {
                Ok(FilterSpec::Butterworth {
                    order: number(WHAT, "ORDER", o)?,
                    cutoff_hz: number(WHAT, "CUTOFF_HZ", c)?,
                })
            }
            [k, o, c, a] if k.eq_ignore_ascii_case("cheby2") => Ok(FilterSpec::Cheby2 {
                order: number(WHAT, "ORDER", o)?,
                cutoff_hz: number(WHAT, "CUTOFF_HZ", c)?,
                atten_db: number(WHAT, "ATTEN_DB", a)?,
            }),
            _ => Err(ParseError::Malformed {
                what: WHAT,
                given: s.to_string(),
                expected: FilterSpec::GRAMMAR,
            }),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_fill_method_name_reads_back_and_is_the_reports_name() {
        for (m, n) in FillMethod::NAMED {
            assert_eq!(m.to_string(), n);
            assert_eq!(n.parse::<FillMethod>(), Ok(m));
            assert_eq!(n.to_ascii_uppercase().parse::<FillMethod>(), Ok(m));
            assert_eq!(serde_json::to_value(m).unwrap(), n, "serde name of {m:?}");
            assert_eq!(FillMethod::from_name(n), Some(m));
        }
        let e = "magic".parse::<FillMethod>().unwrap_err().to_string();
        assert_eq!(
            e,
            "unknown fill method \"magic\" (expected auto, linear, lagrange2, lagrange5, spline, \
             rigid, pattern, pca, kalman, gloersen, hold or none)"
        );
    }

    #[test]
    fn spike_modes_read_back() {
        for (m, n) in SpikeMode::NAMED {
            assert_eq!(m.to_string(), n);
            assert_eq!(n.parse::<SpikeMode>(), Ok(m));
            assert_eq!(serde_json::to_value(m).unwrap(), n);
        }
        assert_eq!("MEDIAN".parse::<SpikeMode>(), Ok(SpikeMode::Median));
        assert_eq!(
            "mean".parse::<SpikeMode>().unwrap_err().to_string(),
            "unknown spike mode \"mean\" (expected gap or median)"
        );
    }

    #[test]
    fn spike_specs_say_what_was_asked() {
        for s in ["hampel", "hampel:7", "hampel:7:2.5"] {
            assert_eq!(s.parse::<SpikeSpec>().unwrap().to_string(), s);
        }
        let s: SpikeSpec = "Hampel:7:2.5".parse().unwrap();
        let o = s.options(SpikeMode::Median, 4.0, true);
        assert_eq!(
            (o.half_window, o.nsigma, o.mode, o.min_deviation, o.detrend),
            (7, 2.5, SpikeMode::Median, 4.0, true)
        );
        let d = SpikeSpec::default().options(SpikeMode::Gap, 0.0, false);
        assert_eq!(d, SpikeOptions::default());
        assert!("median:3".parse::<SpikeSpec>().is_err());
        assert!("hampel:1:2:3".parse::<SpikeSpec>().is_err());
        assert_eq!(
            "hampel:x".parse::<SpikeSpec>().unwrap_err().to_string(),
            "spike detector K: \"x\" is not a valid number"
        );
        // Ranges are the configuration's to check, and it does.
        let huge: SpikeSpec = "hampel:1000000000".parse().unwrap();
        assert!(huge.options(SpikeMode::Gap, 0.0, false).validate().is_err());
    }

    #[test]
    fn filter_specs_read_back() {
        let b = FilterSpec::Butterworth {
            order: 4,
            cutoff_hz: 6.0,
        };
        let c = FilterSpec::Cheby2 {
            order: 4,
            cutoff_hz: 10.5,
            atten_db: 40.0,
        };
        assert_eq!("butterworth:4:6".parse::<FilterSpec>(), Ok(b));
        assert_eq!("BUTTER:4:6.0".parse::<FilterSpec>(), Ok(b));
        assert_eq!(b.to_string(), "butterworth:4:6");
        assert_eq!("cheby2:4:10.5:40".parse::<FilterSpec>(), Ok(c));
        assert_eq!(c.to_string(), "cheby2:4:10.5:40");
        assert_eq!(
            "bessel:4:6".parse::<FilterSpec>().unwrap_err().to_string(),
            "low-pass filter \"bessel:4:6\": expected butterworth:ORDER:CUTOFF_HZ or \
             cheby2:ORDER:CUTOFF_HZ:ATTEN_DB"
        );
        assert!("butterworth:4".parse::<FilterSpec>().is_err());
        assert!("butterworth:-4:6".parse::<FilterSpec>().is_err());
    }
}
