//! `c3dfix plot`: marker coordinates against time, optionally over the original they were
//! repaired from, or the force plates (`--forces`), as SVG or PNG.

use crate::commands::info::read_c3d;
use crate::output::write_atomic;
use anyhow::Result;
use show::plot::{forces_picture, markers_picture, Format};
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
    let fname = crate::output::file_name(&a.file);
    if a.forces {
        let bytes = forces_picture(
            (&c, &a.file, &fname),
            &a.plates.options(),
            a.detect_events,
            format,
            &mut |w| crate::console::errln!("c3dfix: warning: {}: {w}", a.file.display()),
        )?;
        write_atomic(&a.output, &bytes, a.force)?;
        return Ok(0);
    }
    let orig = a.against.as_deref().map(read_c3d).transpose()?;
    let oname = a.against.as_deref().map(crate::output::file_name);
    if a.marker.is_empty() {
        anyhow::bail!("no marker given (--marker NAME[,NAME…])");
    }
    let bytes = markers_picture(
        (&c, &a.file, &fname),
        orig.as_ref().zip(oname.as_deref()),
        &a.marker,
        a.analog.as_deref(),
        a.detect_events,
        format,
    )?;
    write_atomic(&a.output, &bytes, a.force)?;
    Ok(0)
}
