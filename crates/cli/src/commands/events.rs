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
    /// The trials: C3D files, or folders whose C3D files are all taken.
    #[arg(required = true)]
    pub files: Vec<PathBuf>,
    /// Trials done at once (default: one per core).
    #[arg(long, short = 'j', value_name = "N")]
    pub jobs: Option<usize>,
    /// Where events come from: `plates` (a foot alone loading a plate), `kinematics` (the
    /// heel, toe and pelvis markers: Zeni 2008 and Desailly 2009 combined; never the file's
    /// own events) or `auto` (plate events where a foot lands on a plate, kinematic ones
    /// elsewhere, shifted by their lag on this trial's plate steps).
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
    /// Write the trial with the events added to its EVENT group (as Nexus writes it) to OUT
    /// (one input file).
    #[arg(short = 'o', long, value_name = "OUT", conflicts_with = "in_place")]
    pub output: Option<PathBuf>,
    /// Write the events into each input file itself (atomically).
    #[arg(long)]
    pub in_place: bool,
    /// With --in-place, keep each original as FILE.bak first.
    #[arg(long, requires = "in_place")]
    pub backup: bool,
    /// Remove the file's own Foot Strike and Foot Off events first (other events are kept).
    #[arg(long)]
    pub replace: bool,
    /// Replace an existing OUT.
    #[arg(long)]
    pub force: bool,
}

/// Where the events go, besides standard output.
enum Write<'a> {
    Nowhere,
    To(&'a std::path::Path),
    InPlace { backup: bool },
}

fn one(path: &std::path::Path, opts: &EventOptions, write: &Write, a: &Args) -> Result<Detected> {
    if let Write::Nowhere = write {
        let c = read_c3d(path)?;
        return Ok(detect_events(&c, opts, path)?);
    }
    // A file to be written is read into memory, not mapped: it may be the file replaced.
    let mut c = c3dfix::open(path)?;
    let d = detect_events(&c, opts, path)?;
    c3dfix::event_group::write_events(&mut c, &d.events, a.replace)
        .map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))?;
    let (dest, save) = match write {
        Write::To(out) => (
            *out,
            c3dfix::SaveOptions {
                force: a.force,
                backup: false,
            },
        ),
        _ => (
            path,
            c3dfix::SaveOptions {
                force: true,
                backup: matches!(write, Write::InPlace { backup: true }),
            },
        ),
    };
    c3dfix::save(&c, dest, &save)?;
    Ok(d)
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

pub fn run(mut a: Args) -> Result<i32> {
    let from: EventSource = a.from.parse()?;
    let named_one_file = a.files.len() == 1 && !a.files[0].is_dir();
    a.files = crate::commands::each::trials(&a.files)?;
    let opts = EventOptions {
        from,
        markers: MarkerNames::parse(&a.markers)?,
        ..EventOptions::default()
    };
    let write = match (&a.output, a.in_place) {
        (Some(out), _) => {
            if a.files.len() != 1 {
                anyhow::bail!("-o takes one input file; use --in-place for several");
            }
            Write::To(out.as_path())
        }
        (None, true) => Write::InPlace { backup: a.backup },
        (None, false) => {
            if a.replace || a.force {
                anyhow::bail!("--replace and --force apply to writing: add -o OUT or --in-place");
            }
            Write::Nowhere
        }
    };
    if named_one_file {
        let d = one(&a.files[0], &opts, &write, &a)?;
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
    let results = crate::commands::each::each(&a.files, a.jobs, |f| one(f, &opts, &write, &a))?;
    for (f, r) in a.files.iter().zip(results) {
        match r {
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
