//! The compact file of gaps the shipped coefficients are fitted on: per gap only what the
//! fit reads (the fill's real mean error and the evidence the features are made of), to
//! four significant digits, grouped by lab.
//!
//! ```text
//! # comments
//! lab NAME
//! error scored spread len spread3 spread_holes bend drift refilled rescored donor_err share respread step accel speed lead
//! ```
//! An unknown value is `-`; `refilled` is 0 or 1; `lead` is the name of the method that
//! leads the fill (as `repair --method` spells it). Four digits, not three: the fit's c₁ is
//! the best of a grid on a nearly flat criterion (gaps within 2×), and three digits moved
//! it from 0.80 to 0.90 (c₀ from −0.0504 to −0.0760, two margins of about the same worth);
//! with four the fit of the file is the fit of the full records (c₀ −0.05038 against
//! −0.05041). The fit is always run on the file as read back, so the file and the
//! coefficients agree to the last digit.

use std::fmt::Write as _;

use super::Sample;
use repair::fill::{Diag, FillMethod};

/// Fields of a gap's line, in order.
pub const COLUMNS: [&str; 17] = [
    "error",
    "scored",
    "spread",
    "len",
    "spread3",
    "spread_holes",
    "bend",
    "drift",
    "refilled",
    "rescored",
    "donor_err",
    "share",
    "respread",
    "step",
    "accel",
    "speed",
    "lead",
];

/// A line of the gaps file that is not what [`read`] expects.
#[derive(Debug, thiserror::Error)]
#[error("gaps file, line {line}: {what}")]
pub struct GapsError {
    pub line: usize,
    pub what: String,
}

/// The gaps of a gaps file, each lab's name held once.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Gaps {
    pub labs: Vec<String>,
    /// (index into `labs`, evidence, real mean error).
    pub gaps: Vec<(usize, Diag, f64)>,
}

impl Gaps {
    /// The gaps as the fit takes them.
    pub fn samples(&self) -> Vec<Sample<'_>> {
        self.gaps
            .iter()
            .map(|&(lab, evidence, error)| Sample {
                lab: &self.labs[lab],
                evidence,
                error,
            })
            .collect()
    }
}

/// `v` to four significant digits, in the shorter of plain and exponent notation.
fn short(v: f64) -> String {
    if v == 0.0 || !v.is_finite() {
        return format!("{v}");
    }
    let r: f64 = format!("{v:.3e}").parse().unwrap_or(v);
    let (plain, exp) = (format!("{r}"), format!("{r:e}"));
    if exp.len() < plain.len() {
        exp
    } else {
        plain
    }
}

/// The gaps file of `gaps`, labs in the order they first appear, `header` (lines without
/// the `#`) on top. `slowed` is not kept: the fit does not read it.
pub fn write(gaps: &[Sample], header: &str) -> String {
    let mut labs: Vec<&str> = Vec::new();
    for g in gaps {
        if !labs.contains(&g.lab) {
            labs.push(g.lab);
        }
    }
    let mut out = String::new();
    for l in header.lines() {
        let _ = writeln!(out, "# {l}");
    }
    let _ = writeln!(out, "# {}", COLUMNS.join(" "));
    let opt = |v: Option<f64>| v.map_or("-".to_string(), short);
    for lab in labs {
        let _ = writeln!(out, "lab {lab}");
        for g in gaps.iter().filter(|g| g.lab == lab) {
            let d = &g.evidence;
            let fields = [
                short(g.error),
                short(d.scored),
                short(d.spread),
                d.len.to_string(),
                opt(d.spread3),
                opt(d.spread_holes),
                opt(d.bend),
                opt(d.drift),
                u8::from(d.refilled).to_string(),
                opt(d.rescored),
                opt(d.donor_err),
                opt(d.share),
                opt(d.respread),
                opt(d.step),
                opt(d.accel),
                opt(d.speed),
                d.lead.map_or("-".to_string(), |m| m.name().to_string()),
            ];
            let _ = writeln!(out, "{}", fields.join(" "));
        }
    }
    out
}

/// The gaps of a gaps file (see the module's documentation).
pub fn read(text: &str) -> Result<Gaps, GapsError> {
    let mut g = Gaps::default();
    for (i, l) in text.lines().enumerate() {
        let err = |what: String| GapsError { line: i + 1, what };
        let l = l.trim();
        if l.is_empty() || l.starts_with('#') {
            continue;
        }
        if let Some(name) = l.strip_prefix("lab ") {
            g.labs.push(name.trim().to_string());
            continue;
        }
        let Some(lab) = g.labs.len().checked_sub(1) else {
            return Err(err("a gap before any `lab NAME` line".into()));
        };
        let f: Vec<&str> = l.split_whitespace().collect();
        if f.len() != COLUMNS.len() {
            return Err(err(format!(
                "{} fields where {} were expected ({})",
                f.len(),
                COLUMNS.len(),
                COLUMNS.join(" ")
            )));
        }
        let num = |k: usize| -> Result<f64, GapsError> {
            f[k].parse()
                .map_err(|_| err(format!("{}: `{}` is not a number", COLUMNS[k], f[k])))
        };
        let opt = |k: usize| -> Result<Option<f64>, GapsError> {
            if f[k] == "-" {
                Ok(None)
            } else {
                num(k).map(Some)
            }
        };
        let len = f[3]
            .parse()
            .map_err(|_| err(format!("len: `{}` is not a frame count", f[3])))?;
        let refilled = match f[8] {
            "0" => false,
            "1" => true,
            v => return Err(err(format!("refilled: `{v}` is not 0 or 1"))),
        };
        let evidence = Diag {
            scored: num(1)?,
            spread: num(2)?,
            len,
            spread3: opt(4)?,
            spread_holes: opt(5)?,
            bend: opt(6)?,
            drift: opt(7)?,
            refilled,
            rescored: opt(9)?,
            donor_err: opt(10)?,
            share: opt(11)?,
            respread: opt(12)?,
            step: opt(13)?,
            slowed: None,
            accel: opt(14)?,
            speed: opt(15)?,
            lead: match f[16] {
                "-" => None,
                v => Some(
                    FillMethod::from_name(v)
                        .ok_or_else(|| err(format!("lead: `{v}` is not a fill method")))?,
                ),
            },
        };
        g.gaps.push((lab, evidence, num(0)?));
    }
    Ok(g)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn four_digits_in_the_shorter_notation() {
        assert_eq!(short(0.0), "0");
        assert_eq!(short(12.3456), "12.35");
        assert_eq!(short(0.000123456), "1.235e-4");
        assert_eq!(short(12345678.9), "1.235e7");
        assert_eq!(short(1234.56), "1235");
        assert_eq!(short(-0.5), "-0.5");
    }

    #[test]
    fn a_file_reads_back_as_written() {
        let d = Diag {
            scored: 1.5,
            spread: 0.25,
            len: 40,
            spread3: None,
            spread_holes: Some(2.0),
            bend: Some(0.5),
            drift: None,
            refilled: true,
            rescored: Some(0.75),
            donor_err: Some(3.0),
            share: Some(0.5),
            respread: None,
            step: Some(1.25),
            slowed: None,
            accel: Some(3.5),
            speed: Some(0.75),
            lead: Some(FillMethod::Lagrange5),
        };
        let s = [
            Sample {
                lab: "a",
                evidence: d,
                error: 2.5,
            },
            Sample {
                lab: "b",
                evidence: Diag {
                    refilled: false,
                    lead: None,
                    ..d
                },
                error: 0.125,
            },
        ];
        let text = write(&s, "two gaps");
        assert!(text.starts_with("# two gaps\n"));
        let back = read(&text).unwrap();
        assert_eq!(back.labs, ["a", "b"]);
        assert_eq!(back.samples(), s);
    }

    #[test]
    fn a_bad_line_is_named() {
        let e = read("lab a\n1 2 3\n").unwrap_err();
        assert_eq!(e.line, 2);
        assert!(e.to_string().contains("3 fields where 17"), "{e}");
        let e = read("1 2 3\n").unwrap_err();
        assert!(e.to_string().contains("before any `lab NAME`"), "{e}");
        let e = read("lab a\nx 1 1 5 - - - - 0 - - - - - - - -\n").unwrap_err();
        assert!(e.to_string().contains("error: `x` is not a number"), "{e}");
    }
}
