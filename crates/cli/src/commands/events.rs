//! `c3dfix events`: foot strikes and foot offs of walking trials, from the force plates,
//! from the markers, or both (see `docs/events.md`).

use crate::commands::info::read_c3d;
use crate::console::{errln, outln};
use anyhow::Result;
use c3dfix::events::{detect_events, Detected, EventOptions, EventSource};
use c3dfix::gait::MarkerNames;
use std::path::PathBuf;

#[derive(clap::Args)]
pub struct Args {
    /// The trials (C3D files).
    #[arg(required = true)]
    pub files: Vec<PathBuf>,
    /// Where events come from: `plates` (a foot alone loading a plate), `kinematics` (the
    /// heel and toe markers against the pelvis, Zeni 2008; never the file's own events) or
    /// `auto` (plate events where a foot lands on a plate, kinematic ones elsewhere).
    #[arg(long, default_value = "auto")]
    pub from: String,
    /// Print JSON instead of text.
    #[arg(long)]
    pub json: bool,
    /// Name markers the search does not find: ROLE=NAME with ROLE one of lheel, rheel,
    /// ltoe, rtoe, pelvis; NAME+NAME for a mean (`pelvis=LPSI+RPSI`); comma-separated or
    /// repeated.
    #[arg(long, value_name = "ROLE=NAME")]
    pub markers: Vec<String>,
}

fn one(path: &std::path::Path, opts: &EventOptions) -> Result<Detected> {
    let c = read_c3d(path)?;
    Ok(detect_events(&c, opts, path)?)
}

fn as_json(path: &std::path::Path, d: &Detected) -> serde_json::Value {
    let markers: serde_json::Map<String, serde_json::Value> = d
        .markers
        .iter()
        .map(|(role, names)| (role.clone(), serde_json::json!(names)))
        .collect();
    serde_json::json!({
        "file": path.display().to_string(),
        "events": d.events,
        "markers": markers,
        "warnings": d.warnings,
    })
}

pub fn run(a: Args) -> Result<i32> {
    let from: EventSource = a.from.parse()?;
    let opts = EventOptions {
        from,
        markers: MarkerNames::parse(&a.markers)?,
        ..EventOptions::default()
    };
    if a.files.len() == 1 {
        let d = one(&a.files[0], &opts)?;
        if a.json {
            outln!(
                "{}",
                serde_json::to_string_pretty(&as_json(&a.files[0], &d))?
            )?;
        } else {
            print_text(&a.files[0], &d)?;
        }
        return Ok(0);
    }
    // Several files: each is reported; one that fails is named on standard error and the
    // others go on; the exit code says whether any failed.
    let mut failed = 0;
    let mut docs = Vec::new();
    for f in &a.files {
        match one(f, &opts) {
            Ok(d) if a.json => docs.push(as_json(f, &d)),
            Ok(d) => print_text(f, &d)?,
            Err(e) => {
                failed += 1;
                errln!("c3dfix: error: {}", crate::console::describe(&e));
            }
        }
    }
    if a.json {
        outln!(
            "{}",
            serde_json::to_string_pretty(&serde_json::json!({ "files": docs }))?
        )?;
    }
    Ok(if failed > 0 { 2 } else { 0 })
}

fn print_text(path: &std::path::Path, d: &Detected) -> Result<()> {
    outln!("{}: {} events", path.display(), d.events.len())?;
    for w in &d.warnings {
        outln!("  warning: {w}")?;
    }
    for e in &d.events {
        let plate = e.plate.map(|p| format!(" (plate {p})")).unwrap_or_default();
        outln!(
            "  {:>9.4} s  frame {:>6}  {:<5} {:<11} {}{plate}",
            e.time,
            e.frame,
            e.context,
            e.label,
            e.source
        )?;
    }
    Ok(())
}
