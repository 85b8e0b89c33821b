//! `c3dfix forces`: ground reaction force, moment, centre of pressure and free moment of
//! every force plate, with the contact intervals a gait lab reads as foot-strike and
//! foot-off.

use crate::commands::info::read_c3d;
use crate::console::{errln, outln};
use crate::output::{refuse_input, write_atomic};
use anyhow::{bail, Result};
use c3dfix::ForcePlatforms;
use std::path::{Path, PathBuf};

#[derive(clap::Args)]
pub struct Args {
    pub file: PathBuf,
    /// Print JSON (every sample of every plate) instead of a summary.
    #[arg(long)]
    pub json: bool,
    #[command(flatten)]
    pub plates: crate::plates::PlateArgs,
    /// Write every sample to a file: JSON (`.json`) or CSV (`.csv`).
    #[arg(short, long)]
    pub output: Option<PathBuf>,
    /// Replace an existing output file.
    #[arg(long)]
    pub force: bool,
}

pub fn run(a: Args) -> Result<i32> {
    let table = match &a.output {
        Some(out) => {
            refuse_input(out, &[&a.file], "output")?;
            match out.extension().and_then(|e| e.to_str()) {
                Some(e) if e.eq_ignore_ascii_case("json") => Some(false),
                Some(e) if e.eq_ignore_ascii_case("csv") => Some(true),
                _ => bail!(
                    "{}: the output's extension must be .json or .csv",
                    out.display()
                ),
            }
        }
        None => None,
    };
    let c = read_c3d(&a.file)?;
    let fp = c3dfix::force_platforms(&c, &a.plates.options())?;
    for w in &fp.warnings {
        errln!("c3dfix: warning: {}: {w}", a.file.display());
    }
    if let (Some(out), Some(csv)) = (&a.output, table) {
        let text = if csv { fp.csv() } else { json(&a.file, &fp)? };
        write_atomic(out, text.as_bytes(), a.force)?;
    }
    if a.json {
        outln!("{}", json(&a.file, &fp)?)?;
    } else {
        summary(&a.file, &fp)?;
    }
    Ok(0)
}

fn json(file: &Path, fp: &ForcePlatforms) -> Result<String> {
    Ok(serde_json::to_string(&fp.report(file))?)
}

fn summary(file: &Path, fp: &ForcePlatforms) -> Result<()> {
    if fp.platforms.is_empty() {
        outln!(
            "{}: no force platforms{}",
            file.display(),
            if fp.warnings.is_empty() {
                ""
            } else {
                " could be computed (see the warnings)"
            }
        )?;
        return Ok(());
    }
    outln!(
        "{}: {} force platform{} (COP where the push >= {} N)",
        file.display(),
        fp.platforms.len(),
        if fp.platforms.len() == 1 { "" } else { "s" },
        fp.threshold
    )?;
    for p in &fp.platforms {
        let channels: Vec<String> = p.channels.iter().map(|c| c.to_string()).collect();
        outln!(
            "  plate {}  type {}  channels {}  {} Hz  peak push {:.1} {}{}{}",
            p.index,
            p.kind,
            channels.join(","),
            p.rate,
            p.peak_force,
            p.units.force,
            match p.baseline {
                Some(b) => format!(
                    "  unloaded level {:.1} N subtracted (frames {}-{}, {})",
                    b.level,
                    b.first_frame,
                    b.last_frame,
                    b.source.name()
                ),
                None => String::new(),
            },
            match &p.filtered {
                Some(f) => format!("  filtered {f}"),
                None => String::new(),
            }
        )?;
        if p.contacts.is_empty() {
            outln!("    no contact")?;
        }
        for k in &p.contacts {
            outln!(
                "    contact frames {}-{} (samples {}-{}, {:.3}-{:.3} s), peak {:.1} N",
                k.first_frame,
                k.last_frame,
                k.first_sample,
                k.last_sample,
                k.first_time,
                k.last_time,
                k.peak
            )?;
        }
    }
    Ok(())
}
