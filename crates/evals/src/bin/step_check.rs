//! The step-plausibility rule checked through the file on every trial given (see
//! [`evals::step`]): per trial the fills checked, those stepping above 1.5× the marker's
//! largest recorded step, and the largest ratio.
//!
//! ```sh
//! cargo run --release -p evals --bin step_check              # ../shared/c3d-more
//! cargo run --release -p evals --bin step_check -- FILE...   # these files
//! ```

use clap::Parser;
use evals::step::check;
use std::path::PathBuf;

/// The step rule checked through the file.
#[derive(Parser)]
#[command(name = "step_check")]
struct Args {
    /// C3D files to check (default: every trial of `../shared/c3d-more`).
    files: Vec<PathBuf>,
}

fn main() {
    let mut files = Args::parse().files;
    if files.is_empty() {
        let Some(dir) = testkit::c3d_more() else {
            return;
        };
        files = testkit::files_with_ext(&dir, "c3d");
    }
    let (mut n, mut over, mut worst) = (0, 0, 0.0f64);
    for f in &files {
        match check(f) {
            Ok((a, b, w)) => {
                let c = c3d::read_file(f).ok();
                let format = c.as_ref().map_or(String::new(), |c| {
                    format!("{:?}, scale {}", c.format(), c.layout().point_scale)
                });
                println!(
                    "{}: {a} fills, {b} above 1.5x, largest {w:.2}x ({format})",
                    f.display()
                );
                n += a;
                over += b;
                worst = worst.max(w);
            }
            Err(e) => println!("{}: {e}", f.display()),
        }
    }
    println!("all: {n} fills, {over} step above 1.5x the marker's largest recorded step (largest {worst:.2}x)");
}
