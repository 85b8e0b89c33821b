//! `c3dfix events`: foot strikes and foot offs of walking trials, from the force plates,
//! from the markers, or both (see `docs/events.md`).

use crate::console::{errln, outln};
use anyhow::Result;
use c3dfix::annotate::Annotate;
use c3dfix::events::{Detected, EventOptions, EventSource};
use c3dfix::{session_from, CalibrationTruth, SessionLags};
use gait::session::SessionOptions;
use gait::MarkerNames;
use std::path::PathBuf;

#[derive(clap::Args)]
pub struct Args {
    /// The trials: C3D files, or folders whose C3D files are all taken.
    #[arg(required = true)]
    pub files: Vec<PathBuf>,
    /// Trials done at once, 1 to 256 (default: one per core).
    #[arg(long, short = 'j', value_name = "N", value_parser = crate::ranges::choice::<c3dfix::Jobs>)]
    pub jobs: Option<c3dfix::Jobs>,
    /// Where events come from: `plates` (a foot alone loading a plate), `kinematics` (the
    /// heel, toe and pelvis markers: Zeni 2008 and Desailly 2009 combined; never the file's
    /// own events) or `auto` (plate events where a foot lands on a plate, kinematic ones
    /// elsewhere, shifted by their lag on this trial's plate steps).
    #[arg(long, default_value = "auto", value_parser = crate::ranges::choice::<EventSource>)]
    pub from: EventSource,
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
    /// Shift the kinematic events by the lead or lag the markers showed on OTHER trials of
    /// the same session (C3D files or folders; repeat the flag for several): the median of
    /// (truth − kinematic) per kind over their contacts, at least 1 per kind (none: that
    /// kind is left as the markers give it, with a warning). A trial never calibrates
    /// itself. In `auto`, a kind the trial's own plates calibrate keeps that calibration.
    #[arg(long, value_name = "FILE_OR_FOLDER")]
    pub calibrate_from: Vec<PathBuf>,
    /// What the --calibrate-from trials' events are learned from: `plates` (one foot alone on
    /// a plate), `events` (the files' own Foot Strike / Foot Off) or `auto` (a trial's plates
    /// where it has contacts, else its own events).
    #[arg(
        long,
        value_name = "TRUTH",
        default_value = "auto",
        requires = "calibrate_from",
        value_parser = crate::ranges::choice::<CalibrationTruth>
    )]
    pub calibrate_truth: CalibrationTruth,
}

fn one(
    path: &std::path::Path,
    opts: &EventOptions,
    session: Option<&SessionLags>,
    dest: Annotate<'_>,
    replace: bool,
) -> Result<Detected> {
    let with_session;
    let opts = match session {
        Some(s) => {
            with_session = EventOptions {
                session: Some(s.for_trial(path, &SessionOptions::default())),
                ..opts.clone()
            };
            &with_session
        }
        None => opts,
    };
    Ok(c3dfix::annotate::events_file(path, opts, replace, dest)?)
}

fn as_json(path: &std::path::Path, d: &Detected) -> serde_json::Value {
    let markers: serde_json::Map<String, serde_json::Value> = d
        .markers
        .iter()
        .map(|(role, names)| (role.clone(), serde_json::json!(names)))
        .collect();
    let mut doc = serde_json::json!({
        "file": path.display().to_string(),
        "events": d.events,
        "markers": markers,
        "warnings": d.warnings,
    });
    if let (false, Some(o)) = (d.notes.is_empty(), doc.as_object_mut()) {
        o.insert("notes".into(), serde_json::json!(d.notes));
    }
    if let (Some(s), Some(o)) = (&d.session_calibration, doc.as_object_mut()) {
        o.insert("session_calibration".into(), serde_json::json!(s));
    }
    doc
}

pub fn run(mut a: Args) -> Result<i32> {
    let from = a.from;
    let named_one_file = a.files.len() == 1 && !a.files[0].is_dir();
    a.files = crate::commands::each::trials(&a.files)?;
    let opts = EventOptions {
        from,
        markers: MarkerNames::parse(&a.markers)?,
        ..EventOptions::default()
    };
    let session = if a.calibrate_from.is_empty() {
        None
    } else {
        if from == EventSource::Plates {
            anyhow::bail!(
                "--calibrate-from shifts kinematic events: use --from kinematics or auto"
            );
        }
        let s = session_from(&a.calibrate_from, &opts, a.calibrate_truth)
            .map_err(|e| anyhow::anyhow!("{e} (--calibrate-from)"))?;
        for why in &s.skipped {
            errln!("c3dfix: calibration: skipped {why}");
        }
        Some(s)
    };
    let session = session.as_ref();
    let dest = match (&a.output, a.in_place) {
        (Some(out), _) => {
            if a.files.len() != 1 {
                anyhow::bail!("-o takes one input file; use --in-place for several");
            }
            Annotate::To {
                output: out.as_path(),
                force: a.force,
            }
        }
        (None, true) => Annotate::InPlace { backup: a.backup },
        (None, false) => {
            if a.replace || a.force {
                anyhow::bail!("--replace and --force apply to writing: add -o OUT or --in-place");
            }
            Annotate::Report
        }
    };
    if named_one_file {
        let d = one(&a.files[0], &opts, session, dest, a.replace)?;
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
    let results = crate::commands::each::each(&a.files, a.jobs, |f| {
        one(f, &opts, session, dest, a.replace)
    })?;
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
    for n in &d.notes {
        outln!("  note: {n}")?;
    }
    for w in &d.warnings {
        outln!("  warning: {w}")?;
    }
    if let Some(s) = &d.session_calibration {
        let ms = |k: &c3dfix::KindReport| match (k.left_ms, k.right_ms) {
            (Some(l), Some(r)) if l == r => format!("{l:+.1} ms"),
            (l, r) => {
                let f = |v: Option<f64>| v.map_or("none".to_string(), |v| format!("{v:+.1} ms"));
                format!("left {}, right {}", f(l), f(r))
            }
        };
        let used = |k: &c3dfix::KindReport| {
            if k.used {
                ""
            } else if k.left_ms.is_some() || k.right_ms.is_some() {
                " (not used: the trial's own plates calibrate them)"
            } else {
                " (not used: too few contacts)"
            }
        };
        outln!(
            "  session calibration (markers with the offsets of {} other trial(s)): strikes {} from {} contacts{}, offs {} from {} contacts{}",
            s.trials,
            ms(&s.strike),
            s.strike.contacts,
            used(&s.strike),
            ms(&s.off),
            s.off.contacts,
            used(&s.off)
        )?;
    }
    for e in &d.events {
        let plate = e.plate.map(|p| format!(" (plate {p})")).unwrap_or_default();
        outln!(
            "  {:>9.4} s  frame {:>6}  {:<5} {:<11} {}{plate}",
            e.time,
            e.frame,
            e.side.context(),
            e.kind.label(),
            e.source.name()
        )?;
    }
    Ok(())
}
