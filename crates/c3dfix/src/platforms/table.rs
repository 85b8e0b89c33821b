//! The plates as people take them away: the JSON report both fronts print (`forces --json`,
//! `forces -o x.json`) and the CSV table of every sample. Written here, once, so the
//! command line and the Python package cannot drift apart in what a plate's report holds.

use super::{ForcePlatforms, Platform};
use serde::Serialize;
use std::fmt::Write as _;
use std::path::Path;

/// The plates of one trial as reported: every sample of every plate (the push included),
/// with the file's time base. Fields in alphabetical order, the order of the reports before
/// this type existed, so their bytes are unchanged.
#[derive(Debug, Serialize)]
pub struct ForcesReport<'a> {
    pub file: String,
    pub platforms: &'a [Platform],
    /// Sample `i` of every plate is at `start_time + i / rate` s, on the file's time base (the
    /// EVENT group's): the contacts' times are on it too.
    pub start_time: f64,
    /// The push (N) below which COP and free moment are undefined.
    pub threshold: f64,
    /// Each plate left out or corrected, in words.
    pub warnings: Vec<String>,
}

impl ForcePlatforms {
    /// The report of these plates, read from `file`.
    pub fn report(&self, file: &Path) -> ForcesReport<'_> {
        ForcesReport {
            file: file.display().to_string(),
            platforms: &self.platforms,
            start_time: self.start_time,
            threshold: self.threshold,
            warnings: self.warnings.iter().map(|w| w.to_string()).collect(),
        }
    }

    /// Every sample as CSV: time (the file's time base, as its events), then per plate force,
    /// moment, COP and free moment, each column naming its unit; an undefined value (a COP
    /// under the threshold) is an empty field.
    pub fn csv(&self) -> String {
        let mut s = String::from("time");
        for p in &self.platforms {
            for (q, unit) in [
                ("force", &p.units.force),
                ("moment", &p.units.moment),
                ("cop", &p.units.position),
                ("free_moment", &p.units.moment),
            ] {
                for ax in ["x", "y", "z"] {
                    // Writing into a String cannot fail.
                    let _ = write!(s, ",plate{}_{q}_{ax} ({unit})", p.index);
                }
            }
        }
        s.push('\n');
        for i in 0..self.samples() {
            let _ = write!(s, "{}", self.time(i));
            for p in &self.platforms {
                for v in [&p.force, &p.moment, &p.cop, &p.free_moment] {
                    for x in v.get(i).copied().unwrap_or([f64::NAN; 3]) {
                        if x.is_finite() {
                            let _ = write!(s, ",{x}");
                        } else {
                            s.push(',');
                        }
                    }
                }
            }
            s.push('\n');
        }
        s
    }
}
