//! `c3dfix cycles`: markers, analog channels and plate forces cut into gait cycles (foot
//! strike to the next foot strike of the same foot) and time-normalised to 0–100 %, as one
//! CSV (see `docs/cycles.md`).

use crate::console::{errln, outln};
use crate::output::{refuse_input, write_atomic};
use crate::plates::PlateArgs;
use anyhow::Result;
use c3dfix::events::{EventOptions, EventSource};
use c3dfix::CycleOptions;
use gait::Side;
use std::path::PathBuf;

#[derive(clap::Args)]
pub struct Args {
    /// The trial (a C3D file).
    pub file: PathBuf,
    /// The feet whose cycles are written: left, right or both.
    #[arg(long, default_value = "both", value_parser = crate::ranges::choice::<c3dfix::Feet>)]
    pub side: c3dfix::Feet,
    /// Markers to write (x, y, z in mm each), comma-separated or repeated; every marker
    /// when no signal at all is named.
    #[arg(long, value_name = "NAME", value_delimiter = ',')]
    pub markers: Vec<String>,
    /// Analog channels to write, by label, in their physical units (at their own rate).
    #[arg(long, value_name = "LABEL", value_delimiter = ',')]
    pub analog: Vec<String>,
    /// Write each force plate's force (Fx, Fy, Fz in the lab frame, N).
    #[arg(long)]
    pub forces: bool,
    #[command(flatten)]
    pub plates: PlateArgs,
    /// Cut at detected foot strikes (as `c3dfix events --from auto` finds them) instead of
    /// the file's own EVENT group.
    #[arg(long)]
    pub detect: bool,
    /// Where detected events come from: plates, kinematics or auto (with --detect).
    #[arg(long, requires = "detect", value_name = "SOURCE", value_parser = crate::ranges::choice::<EventSource>)]
    pub from: Option<EventSource>,
    /// The CSV to write (standard output when absent).
    #[arg(short = 'o', long, value_name = "OUT")]
    pub output: Option<PathBuf>,
    /// Replace an existing OUT.
    #[arg(long)]
    pub force: bool,
}

pub fn run(a: Args) -> Result<i32> {
    let detect = if a.detect {
        let from = a.from.unwrap_or(EventSource::Auto);
        Some(EventOptions {
            from,
            ..EventOptions::default()
        })
    } else {
        None
    };
    let opts = CycleOptions {
        sides: a.side.sides(),
        markers: a.markers.clone(),
        analog: a.analog.clone(),
        forces: a.forces,
        force: a.plates.options(),
        detect,
    };
    if let Some(out) = &a.output {
        refuse_input(out, &[&a.file], "output")?;
    }
    let c = crate::commands::info::read_c3d(&a.file)?;
    let cy = c3dfix::cycles(&c, &opts, &a.file)?;
    for w in &cy.warnings {
        errln!("c3dfix: warning: {}: {w}", a.file.display());
    }
    let csv = cy.to_csv();
    match &a.output {
        Some(out) => {
            write_atomic(out, csv.as_bytes(), a.force)?;
            let per_side = |s: Side| cy.cycles.iter().filter(|c| c.side == s).count();
            outln!(
                "{}: {} cycles ({} left, {} right) from the {} events, {} columns → {}",
                a.file.display(),
                cy.cycles.len(),
                per_side(Side::Left),
                per_side(Side::Right),
                cy.events,
                cy.columns.len(),
                out.display()
            )?;
        }
        None => outln!("{}", csv.trim_end())?,
    }
    Ok(0)
}
