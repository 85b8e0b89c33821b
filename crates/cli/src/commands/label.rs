//! `c3dfix label TRIAL --template LABELLED`: label a trial's unlabelled trajectories from a
//! labelled trial of the same marker set (issue 47, docs/label.md), through the library
//! ([`c3dfix::label_stage::label_file`]).

use crate::commands::destination::DestinationArgs;
use crate::console::outln;
use anyhow::Result;
use c3dfix::label_stage::{FragmentOutcome, LabelSettings, LabelStatus};
use std::path::PathBuf;

#[derive(clap::Args)]
pub struct Args {
    /// The trial to label.
    pub input: PathBuf,
    /// A labelled trial of the same marker set (ideally the same subject: its static
    /// calibration or any labelled trial of the session).
    #[arg(long, value_name = "LABELLED")]
    pub template: PathBuf,
    #[command(flatten)]
    pub dest: DestinationArgs,
    /// Labels (a glob: `*` any text, `?` one character, case-insensitive) that also mark a
    /// point as unlabelled, beside the common placeholders (`*51`, `Unlabeled 3`, an empty
    /// label).
    #[arg(long, value_name = "PATTERN")]
    pub unlabelled: Option<repair::Glob>,
    /// Also treat samples whose coordinates are all exactly 0 as missing.
    #[arg(long)]
    pub zero_invalid: bool,
    /// Print JSON instead of text.
    #[arg(long)]
    pub json: bool,
}

pub fn run(a: Args) -> Result<i32> {
    let dest = a.dest.destination();
    let settings = LabelSettings {
        unlabelled: a
            .unlabelled
            .clone()
            .map_or_else(repair::Unlabelled::common, repair::Unlabelled::with_pattern),
        zero_invalid: a.zero_invalid,
        ..LabelSettings::default()
    };
    let r = c3dfix::label_stage::label_file(&a.input, &a.template, &dest, &settings)?;
    if a.json {
        let mut v = serde_json::to_value(&r)?;
        v["file"] = a.input.display().to_string().into();
        v["template"] = a.template.display().to_string().into();
        outln!("{}", serde_json::to_string_pretty(&v)?)?;
        return Ok(0);
    }
    let out = r.output.as_deref().unwrap_or("");
    match r.status {
        LabelStatus::AlreadyLabelled => {
            outln!(
                "{}: labelled before (C3DFIX:LABEL), nothing changed -> {out}",
                a.input.display()
            )?;
            return Ok(0);
        }
        LabelStatus::NothingUnlabelled => {
            outln!(
                "{}: no unlabelled point, nothing changed -> {out}",
                a.input.display()
            )?;
            return Ok(0);
        }
        LabelStatus::Labelled => {}
    }
    outln!(
        "labelled {} -> {out} from {} ({} template markers, {} labelled in the trial already{})",
        a.input.display(),
        a.template.display(),
        r.template_markers,
        r.in_common,
        if r.seeded {
            ", matched from nothing"
        } else {
            ""
        }
    )?;
    let total = r.labelled_samples + r.left_samples;
    let pct = |n: usize| {
        if total > 0 {
            100.0 * n as f64 / total as f64
        } else {
            0.0
        }
    };
    outln!(
        "  {} unlabelled points: {} samples labelled ({:.1} %), {} left unlabelled; {} samples moved, {} points renamed, {} labels changed",
        r.unlabelled_points,
        r.labelled_samples,
        pct(r.labelled_samples),
        r.left_samples,
        r.moved_samples,
        r.renamed.len(),
        r.relabelled
    )?;
    if !r.not_in_template.is_empty() {
        outln!(
            "  not in the template, left as they are: {}",
            r.not_in_template.join(", ")
        )?;
    }
    for f in &r.fragments {
        let what = match &f.outcome {
            FragmentOutcome::Kept { .. } => continue,
            FragmentOutcome::Labelled { label } => format!("-> {label}"),
            FragmentOutcome::Relabelled { label, from } => format!("-> {label} (was {from})"),
            FragmentOutcome::Unlabelled { why } => {
                let v = serde_json::to_value(why)?;
                format!("left: {}", v["why"].as_str().unwrap_or(""))
            }
        };
        outln!(
            "  {:<10} frames {:>6}–{:<6} {:>5} samples {what}",
            f.point,
            f.first_frame,
            f.last_frame,
            f.samples
        )?;
    }
    Ok(0)
}
