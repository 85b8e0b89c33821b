//! `c3dfix export`: point data (and analog) as CSV, TRC or JSON; the force plates' ground
//! reaction as an OpenSim motion file (MOT); or both files OpenSim needs (`opensim`). The
//! writers are the library's ([`c3dfix::export`]); this module parses and prints.

use crate::commands::info::read_c3d;
use crate::console::{errln, out, outln};
use crate::plates::PlateArgs;
use anyhow::Result;
use c3dfix::export::{self, ExportDestination, ExportOptions, Points};
use c3dfix::Axes;
use std::path::PathBuf;

/// The formats as the command lists them (the library's [`export::ExportFormat`]).
#[derive(Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum ExportFormat {
    Csv,
    Trc,
    Json,
    /// OpenSim's ground reaction motion file: per plate force (N), point (m) and free torque
    /// (N·m), one row per analog sample on the file's time base; unloaded rows are 0 at the
    /// plate centre.
    Mot,
    /// NAME.trc and NAME.mot into --out-dir, on one time base, turned to OpenSim's frame:
    /// the lab's up as Y, the direction of travel (when there is one) as X.
    Opensim,
}

impl From<ExportFormat> for export::ExportFormat {
    fn from(f: ExportFormat) -> Self {
        match f {
            ExportFormat::Csv => export::ExportFormat::Csv,
            ExportFormat::Trc => export::ExportFormat::Trc,
            ExportFormat::Json => export::ExportFormat::Json,
            ExportFormat::Mot => export::ExportFormat::Mot,
            ExportFormat::Opensim => export::ExportFormat::Opensim,
        }
    }
}

#[derive(clap::Args)]
pub struct Args {
    pub file: PathBuf,
    #[arg(long, value_enum)]
    pub format: ExportFormat,
    /// Output file (default: standard output). For CSV with analog data, the analog samples
    /// go to a second file beside it, `<name>.analog.csv`.
    #[arg(short, long, conflicts_with = "out_dir")]
    pub output: Option<PathBuf>,
    /// Folder for `--format opensim`'s two files (NAME.trc, NAME.mot).
    #[arg(long)]
    pub out_dir: Option<PathBuf>,
    /// Replace existing output files.
    #[arg(long)]
    pub force: bool,
    /// The lab axes as the output's X,Y,Z (TRC, MOT and opensim), a rotation: e.g. `x,z,-y`
    /// for OpenSim's Y-up frame from a Z-up lab (X = lab x, Y = lab z, Z = −lab y). Default:
    /// the lab's axes as they are (TRC, MOT), the lab's up as Y (opensim).
    #[arg(long)]
    pub axes: Option<String>,
    /// The points to export, comma-separated labels (default: every marker; model outputs
    /// such as Plug-in Gait's angles and moments are left out of TRC and CSV).
    #[arg(long, value_delimiter = ',', conflicts_with = "all_points")]
    pub markers: Option<Vec<String>>,
    /// Export every point, model outputs too (JSON's default).
    #[arg(long)]
    pub all_points: bool,
    #[command(flatten)]
    pub plates: PlateArgs,
}

pub fn run(a: Args) -> Result<i32> {
    let format = a.format.into();
    let dest = match (&a.output, &a.out_dir) {
        (Some(out), _) => ExportDestination::File(out.clone()),
        (None, Some(dir)) => ExportDestination::Folder(dir.clone()),
        (None, None) => ExportDestination::Text,
    };
    let opts = ExportOptions {
        format,
        points: match (&a.markers, a.all_points) {
            (Some(names), _) => Some(Points::Named(names.clone())),
            (None, true) => Some(Points::All),
            (None, false) => None,
        },
        // Axes given to a format without a frame are refused by the library's check; they
        // are read only where they apply, so that refusal comes first.
        axes: match &a.axes {
            Some(spec) if format.takes_axes() => Some(Axes::parse(spec)?),
            Some(_) => Some(Axes::default()),
            None => None,
        },
        forces: a.plates.options(),
        force: a.force,
    };
    opts.check(&a.file, &dest)?;
    let c = read_c3d(&a.file)?;
    let file = a.file.display().to_string();
    let done = export::export(&c, &a.file, &dest, &opts, &mut |w| {
        errln!("c3dfix: warning: {file}: {w}")
    })?;
    warn_labels(&a.file, &done.changed_labels)?;
    if let Some(text) = &done.text {
        out!("{text}")?;
    }
    if let Some(pair) = &done.opensim {
        let up = match pair.up {
            Some(u) if a.axes.is_none() => format!(", up {} from {}", u.up, u.source),
            _ => String::new(),
        };
        let forward = pair
            .forward
            .map_or_else(String::new, |f| format!(", travel {f} as X"));
        outln!(
            "{}: wrote {}{} (lab axes {} as OpenSim's X,Y,Z{up}{forward})",
            a.file.display(),
            pair.trc.display(),
            pair.mot.as_ref().map_or_else(
                || " (no force plates: no MOT)".to_string(),
                |m| format!(" and {}", m.display())
            ),
            pair.axes
        )?;
    }
    Ok(0)
}

fn warn_labels(file: &std::path::Path, changed: &[String]) -> Result<()> {
    for l in changed {
        errln!(
            "c3dfix: warning: {}: label {l:?} is empty or holds a tab or line break, which TRC cannot; written as a point number or with spaces",
            file.display()
        );
    }
    Ok(())
}
