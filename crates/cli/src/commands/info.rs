use std::path::PathBuf;

#[derive(clap::Args)]
pub struct Args {
    /// The file to describe.
    pub file: PathBuf,
    /// Print a JSON report instead of text.
    #[arg(long)]
    pub json: bool,
}

pub fn run(_a: Args) -> anyhow::Result<i32> {
    anyhow::bail!("info is not implemented yet")
}
