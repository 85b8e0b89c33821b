//! Where a command that rewrites one trial (`repair`, `label`) writes it: the same four flags
//! everywhere, read into the library's [`Destination`], which checks that they go together.

use c3dfix::files::Destination;
use std::path::PathBuf;

#[derive(clap::Args)]
pub struct DestinationArgs {
    /// Where to write the result.
    #[arg(short, long)]
    pub output: Option<PathBuf>,
    /// Replace the input file (atomically).
    #[arg(long)]
    pub in_place: bool,
    /// With --in-place: keep the original as FILE.bak (an existing backup is kept as is).
    #[arg(long)]
    pub backup: bool,
    /// Replace an existing output file (and report, where one is asked for).
    #[arg(long)]
    pub force: bool,
}

impl DestinationArgs {
    /// The flags as the library's destination (its kinds of conflict are said with these
    /// flags by `crate::flags`).
    pub fn destination(&self) -> Destination {
        Destination {
            output: self.output.clone(),
            in_place: self.in_place,
            backup: self.backup,
            force: self.force,
        }
    }
}
