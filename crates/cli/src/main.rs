//! `c3dfix`: a thin command-line layer over the `c3d`, `repair` and `bvh` crates.
//!
//! Exit codes: 0 success, 1 "differences found" (diff), 2 error.

mod commands;
mod output;

use clap::{Parser, Subcommand};

#[derive(Parser)]
#[command(
    name = "c3dfix",
    version,
    about = "Read, write, repair and inspect C3D motion-capture files"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Header, formats, counts, rates, gaps per marker, parameter groups, warnings.
    Info(commands::info::Args),
    /// Reduce a BVH motion to key frames; rebuild it by interpolation and report the error.
    Keyframes(commands::keyframes::Args),
}

fn main() {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Info(a) => commands::info::run(a),
        Command::Keyframes(a) => commands::keyframes::run(a),
    };
    match result {
        Ok(code) => std::process::exit(code),
        Err(e) => {
            eprintln!("c3dfix: error: {e:#}");
            std::process::exit(2);
        }
    }
}
