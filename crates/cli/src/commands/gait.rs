//! `c3dfix gait`: the gait-cycle parameters of walking trials per side, as Vicon Nexus'
//! "Generate Gait Cycle Parameters" defines them (see `docs/gait-parameters.md`).

use crate::console::{errln, outln};
use anyhow::Result;
use c3dfix::annotate::Annotate;
use c3dfix::events::{EventOptions, EventSource};
use c3dfix::{GaitOptions, GaitReport};
use gait::MarkerNames;
use std::path::{Path, PathBuf};

#[derive(clap::Args)]
pub struct Args {
    /// The trials: C3D files, or folders whose C3D files are all taken.
    #[arg(required = true)]
    pub files: Vec<PathBuf>,
    /// Trials done at once, 1 to 256 (default: one per core).
    #[arg(long, short = 'j', value_name = "N", value_parser = crate::ranges::choice::<c3dfix::Jobs>)]
    pub jobs: Option<c3dfix::Jobs>,
    /// Print JSON instead of text (also with --write: what was written).
    #[arg(long)]
    pub json: bool,
    /// Without --write: write the parameters of every file as CSV (file, context, name,
    /// value, unit) to this path. With --write: the trial with its ANALYSIS group written
    /// (one input file).
    #[arg(short = 'o', long, value_name = "PATH")]
    pub output: Option<PathBuf>,
    /// Detect the events (as `c3dfix events` does) instead of reading the file's own.
    #[arg(long)]
    pub detect: bool,
    /// With --detect: where events come from (plates, kinematics or auto).
    #[arg(long, requires = "detect", default_value = "auto", value_parser = crate::ranges::choice::<EventSource>)]
    pub from: EventSource,
    /// Name markers the search does not find: ROLE=NAME with ROLE one of lheel, rheel,
    /// ltoe, rtoe, pelvis (the toes measure the lengths).
    #[arg(long, value_name = "ROLE=NAME")]
    pub markers: Vec<String>,
    /// A treadmill's belt speed (m/s): on a treadmill trial, lengths and walking speed are
    /// measured over the belt (left out without it; the files do not store it).
    #[arg(long, value_name = "M_S")]
    pub belt_speed: Option<f64>,
    /// Write the parameters into the ANALYSIS group as Nexus writes it: to -o OUT, or
    /// with --in-place into each file.
    #[arg(long)]
    pub write: bool,
    /// With --write: write into each input file itself (atomically).
    #[arg(long, requires = "write", conflicts_with = "output")]
    pub in_place: bool,
    /// With --in-place, keep each original as FILE.bak first.
    #[arg(long, requires = "in_place")]
    pub backup: bool,
    /// Replace an existing output file.
    #[arg(long)]
    pub force: bool,
}

fn as_json(path: &Path, r: &GaitReport) -> serde_json::Value {
    serde_json::json!({
        "file": path.display().to_string(),
        "parameters": r.parameters,
        "events": r.events,
        "toes": r.toes,
        "warnings": r.warnings,
    })
}

fn print_text(path: &Path, r: &GaitReport) -> Result<()> {
    outln!(
        "{}: gait-cycle parameters (events: {})",
        path.display(),
        r.events
    )?;
    for w in &r.warnings {
        outln!("  warning: {w}")?;
    }
    for p in &r.parameters {
        outln!(
            "  {:<5} {:<22} {:>10.4} {}",
            p.context,
            p.name,
            p.value,
            p.unit
        )?;
    }
    Ok(())
}

pub fn run(mut a: Args) -> Result<i32> {
    let markers = MarkerNames::parse(&a.markers)?;
    let named_one_file = a.files.len() == 1 && !a.files[0].is_dir();
    a.files = crate::commands::each::trials(&a.files)?;
    let detect = if a.detect {
        Some(EventOptions {
            from: a.from,
            markers: markers.clone(),
            ..EventOptions::default()
        })
    } else {
        None
    };
    let opts = GaitOptions {
        detect,
        markers,
        belt_speed_m_s: a.belt_speed,
    };
    if a.write && a.output.is_none() && !a.in_place {
        anyhow::bail!("--write needs -o OUT (one input file) or --in-place");
    }
    if a.write && a.output.is_some() && a.files.len() != 1 {
        anyhow::bail!("--write -o takes one input file; use --write --in-place for several");
    }
    if !a.write && a.force && a.output.is_none() {
        anyhow::bail!("--force applies to an output: add -o PATH");
    }
    let csv_out = if a.write { None } else { a.output.clone() };
    if let Some(out) = &csv_out {
        let inputs: Vec<&Path> = a.files.iter().map(|p| p.as_path()).collect();
        c3dfix::save::refuse_input(out, &inputs, "the CSV")?;
    }
    let mut failed = 0;
    let mut docs = Vec::new();
    let mut csv = String::from(c3dfix::export::PARAMETERS_HEADER);
    let several = !named_one_file;
    let dest = match (&a.output, a.in_place) {
        _ if !a.write => Annotate::Report,
        (Some(out), _) => Annotate::To {
            output: out.as_path(),
            force: a.force,
        },
        (None, _) => Annotate::InPlace { backup: a.backup },
    };
    let results = crate::commands::each::each(&a.files, a.jobs, |f| {
        Ok(c3dfix::annotate::gait_file(f, &opts, dest)?)
    })?;
    for (f, r) in a.files.iter().zip(results) {
        let r = match r {
            Ok(r) => r,
            Err(e) if several => {
                failed += 1;
                errln!("c3dfix: error: {}", crate::console::describe(&e));
                continue;
            }
            Err(e) => return Err(e),
        };
        if csv_out.is_some() {
            csv.push_str(&c3dfix::export::parameter_rows(
                &f.display().to_string(),
                &r.parameters,
            ));
            for w in &r.warnings {
                errln!("c3dfix: warning: {}: {w}", f.display());
            }
        } else if a.json {
            docs.push(as_json(f, &r));
        } else {
            print_text(f, &r)?;
        }
    }
    if let Some(out) = &csv_out {
        c3dfix::save::write_atomic(out, csv.as_bytes(), a.force)?;
    } else if a.json {
        let doc = if several {
            serde_json::json!({ "files": docs })
        } else {
            docs.pop().unwrap_or(serde_json::Value::Null)
        };
        outln!("{}", serde_json::to_string_pretty(&doc)?)?;
    }
    Ok(if failed > 0 { 2 } else { 0 })
}
