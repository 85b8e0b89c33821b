//! `c3dfix plot`: marker coordinates against time, optionally over the original they were
//! repaired from, or the force plates (`--forces`), as SVG or PNG.

use crate::commands::info::read_c3d;
use crate::output::write_atomic;
use anyhow::Result;
use show::plot::{render, Format, Plot};
use std::path::PathBuf;

#[derive(clap::Args)]
pub struct Args {
    /// The C3D file to plot (the repaired one when comparing).
    pub file: PathBuf,
    /// Marker label(s), comma-separated; a "Subject:" prefix and case are ignored.
    #[arg(long, value_delimiter = ',', required_unless_present = "forces")]
    pub marker: Vec<String>,
    /// Draw the force plates instead: each plate's vertical ground reaction against time, and
    /// the centres of pressure over the plates' outlines seen from above.
    #[arg(long, conflicts_with_all = ["marker", "against", "analog"])]
    pub forces: bool,
    /// The original file: drawn beside FILE, with its gaps shaded and the repairs marked.
    #[arg(long)]
    pub against: Option<PathBuf>,
    /// An analog channel (label or 1-based number) drawn in physical units below.
    #[arg(long)]
    pub analog: Option<String>,
    /// With --forces: the plates' options, as for `forces`.
    #[command(flatten)]
    pub plates: crate::plates::PlateArgs,
    /// Draw the events the detector finds (as `c3dfix events --from auto`) besides the
    /// file's own, in another colour, labels at the bottom.
    #[arg(long)]
    pub detect_events: bool,
    /// Output picture: .svg or .png.
    #[arg(short, long)]
    pub output: PathBuf,
    /// Replace an existing output file.
    #[arg(long)]
    pub force: bool,
}

pub fn run(a: Args) -> Result<i32> {
    let format = Format::from_path(&a.output)?;
    let inputs: Vec<&std::path::Path> = [Some(a.file.as_path()), a.against.as_deref()]
        .into_iter()
        .flatten()
        .collect();
    crate::output::refuse_input(&a.output, &inputs, "output")?;
    if !a.forces && a.plates.given() {
        anyhow::bail!("--threshold, --no-zero-baseline and --lowpass apply to --forces only");
    }
    let c = read_c3d(&a.file)?;
    if a.forces {
        let fp = crate::plates::compute_with(&c, &a.plates.options())?;
        for w in &fp.warnings {
            crate::console::errln!("c3dfix: warning: {}: {w}", a.file.display());
        }
        let events = event_marks(&c, &a)?;
        let bytes =
            show::plot::render_forces(&fp, &crate::output::file_name(&a.file), &events, format)?;
        write_atomic(&a.output, &bytes, a.force)?;
        return Ok(0);
    }
    let orig = a.against.as_deref().map(read_c3d).transpose()?;
    let (fname, oname) = (
        crate::output::file_name(&a.file),
        a.against.as_deref().map(crate::output::file_name),
    );
    if a.marker.is_empty() {
        anyhow::bail!("no marker given (--marker NAME[,NAME…])");
    }
    let mut plot = Plot::gather(
        (&c, &fname),
        orig.as_ref().zip(oname.as_deref()),
        &a.marker,
        a.analog.as_deref(),
    )?;
    plot.events = event_marks(&c, &a)?;
    let bytes = render(&plot, format)?;
    write_atomic(&a.output, &bytes, a.force)?;
    Ok(0)
}

/// The events drawn: the file's own, and the detector's with `--detect-events`; none where
/// the file states no rate (the axis is then in frames or samples).
fn event_marks(c: &c3d::C3d, a: &Args) -> Result<Vec<show::marks::Mark>> {
    let rate = c.point_rate();
    if rate.is_nan() || rate <= 0.0 {
        return Ok(Vec::new());
    }
    let mut events = show::marks::from_file(c);
    if a.detect_events {
        events.extend(show::marks::detected(c, &a.file)?);
    }
    Ok(events)
}
