//! `c3dfix convert`: rewrite a file, optionally in another processor or number format.

use crate::commands::info::read_c3d;
use crate::console::errln;
use crate::output::write_atomic;
use anyhow::{Context, Result};
use std::path::PathBuf;

#[derive(Clone, Copy, clap::ValueEnum)]
pub enum ProcessorArg {
    Intel,
    Dec,
    Sgi,
}

#[derive(Clone, Copy, clap::ValueEnum)]
pub enum FormatArg {
    Int,
    Float,
}

#[derive(clap::Args)]
pub struct Args {
    /// The file to read.
    pub input: PathBuf,
    /// Where to write.
    #[arg(short, long)]
    pub output: PathBuf,
    /// Target processor format (default: the input's).
    #[arg(long, value_enum)]
    pub processor: Option<ProcessorArg>,
    /// Target number format (default: the input's).
    #[arg(long, value_enum)]
    pub format: Option<FormatArg>,
    /// POINT:SCALE for integer output (default: keep it if exact, else the finest that fits).
    /// Above 0, from the largest coordinate / 32767 (finer does not fit in 16 bits) to the
    /// largest coordinate (coarser would store every coordinate as 0).
    #[arg(long, value_parser = crate::ranges::scale)]
    pub scale: Option<f32>,
    /// Replace the output file if it exists.
    #[arg(long)]
    pub force: bool,
}

pub fn run(a: Args) -> Result<i32> {
    let c = read_c3d(&a.input)?;
    let processor = match a.processor {
        None => c.processor(),
        Some(ProcessorArg::Intel) => c3d::Processor::Intel,
        Some(ProcessorArg::Dec) => c3d::Processor::Dec,
        Some(ProcessorArg::Sgi) => c3d::Processor::Sgi,
    };
    let format = match a.format {
        None => c.format(),
        Some(FormatArg::Int) => c3d::NumberFormat::Integer,
        Some(FormatArg::Float) => c3d::NumberFormat::Float,
    };
    let bytes = c
        .convert(processor, format, a.scale)
        .with_context(|| format!("converting {}", a.input.display()))?;
    write_atomic(&a.output, &bytes, a.force)?;
    for w in c.warnings() {
        errln!("c3dfix: warning: {}: {w}", a.input.display());
    }
    errln!(
        "wrote {} ({} processor, {} data, {} bytes)",
        a.output.display(),
        processor.name(),
        format.name(),
        bytes.len()
    );
    Ok(0)
}
