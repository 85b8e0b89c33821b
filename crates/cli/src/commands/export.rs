//! `c3dfix export`: point data (and analog) as CSV, TRC or JSON; the force plates' ground
//! reaction as an OpenSim motion file (MOT); or both files OpenSim needs (`opensim`). The
//! writers are the library's ([`c3dfix::export`]); this module parses and prints.

use crate::commands::info::read_c3d;
use crate::console::{errln, out, outln};
use crate::output::{refuse_input, write_all, write_atomic, Content, Output};
use crate::plates::PlateArgs;
use anyhow::{bail, Result};
use c3dfix::export::{self, OpenSimOptions, Points};
use c3dfix::Axes;
use std::path::PathBuf;

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
    if let Some(out) = &a.output {
        refuse_input(out, &[&a.file], "output")?;
    }
    let axes = match (&a.axes, a.format) {
        (None, _) => None,
        (Some(spec), ExportFormat::Trc | ExportFormat::Mot | ExportFormat::Opensim) => {
            Some(Axes::parse(spec)?)
        }
        (Some(_), _) => bail!("--axes applies to --format trc, mot and opensim only"),
    };
    match (a.format, &a.out_dir) {
        (ExportFormat::Opensim, None) => bail!("--format opensim needs --out-dir DIR"),
        (ExportFormat::Opensim, Some(_)) => {}
        (_, Some(_)) => bail!("--out-dir applies to --format opensim only (use -o)"),
        _ => {}
    }
    let points = match (&a.markers, a.all_points, a.format) {
        (Some(names), _, _) => Points::Named(names.clone()),
        (None, true, _) | (None, false, ExportFormat::Json) => Points::All,
        (None, false, _) => Points::Markers,
    };
    let c = read_c3d(&a.file)?;
    let name = crate::output::file_name(&a.file);
    match a.format {
        ExportFormat::Csv => {
            let pts = export::points_csv(&c, &points.indices(&c)?);
            let ana = (c.analog().channels() > 0).then(|| export::analog_csv(&c));
            match &a.output {
                Some(out) => {
                    let ana_path = out.with_extension("analog.csv");
                    let mut outs = vec![Output {
                        path: out,
                        bytes: Content::Bytes(pts.as_bytes()),
                        replace: a.force,
                    }];
                    if let Some(text) = &ana {
                        refuse_input(&ana_path, &[&a.file], "analog output")?;
                        outs.push(Output {
                            path: &ana_path,
                            bytes: Content::Bytes(text.as_bytes()),
                            replace: a.force,
                        });
                    }
                    write_all(&outs)?;
                }
                None => {
                    out!("{pts}")?;
                    if let Some(text) = ana {
                        outln!()?;
                        out!("{text}")?;
                    }
                }
            }
        }
        ExportFormat::Trc => {
            let t = export::trc(&c, &name, &points.indices(&c)?, &axes.unwrap_or_default())?;
            emit(&a.output, t.text, a.force)?;
            warn_labels(&a.file, &t.changed_labels)?;
        }
        ExportFormat::Json => emit(&a.output, export::json(&c, &points.indices(&c)?)?, a.force)?,
        ExportFormat::Mot => {
            let fp = c3dfix::force_platforms(&c, &a.plates.options())?;
            for w in &fp.warnings {
                errln!("c3dfix: warning: {}: {w}", a.file.display());
            }
            let text = export::mot(&c, &fp, &a.file, &axes.unwrap_or_default())?;
            emit(&a.output, text, a.force)?;
        }
        ExportFormat::Opensim => {
            let Some(dir) = &a.out_dir else {
                bail!("--format opensim needs --out-dir DIR");
            };
            let opts = OpenSimOptions {
                points,
                axes,
                forces: a.plates.options(),
                force: a.force,
            };
            let done = export::opensim(&c, &a.file, dir, &opts)?;
            for w in &done.warnings {
                errln!("c3dfix: warning: {}: {w}", a.file.display());
            }
            warn_labels(&a.file, &done.changed_labels)?;
            let up = match done.up {
                Some(u) if a.axes.is_none() => format!(", up {} from {}", u.up, u.source),
                _ => String::new(),
            };
            let forward = done
                .forward
                .map_or_else(String::new, |f| format!(", travel {f} as X"));
            outln!(
                "{}: wrote {}{} (lab axes {} as OpenSim's X,Y,Z{up}{forward})",
                a.file.display(),
                done.trc.display(),
                done.mot.as_ref().map_or_else(
                    || " (no force plates: no MOT)".to_string(),
                    |m| format!(" and {}", m.display())
                ),
                done.axes
            )?;
        }
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

fn emit(out: &Option<PathBuf>, text: String, force: bool) -> Result<()> {
    match out {
        Some(p) => write_atomic(p, text.as_bytes(), force),
        None => {
            out!("{text}")?;
            Ok(())
        }
    }
}
