// Read a C3D trial, repair it as `c3dfix repair IN -o OUT --spikes hampel --lowpass
// butterworth:4:6` does, and save it atomically.
//
//     cargo run --release -p c3dfix --example repair_file -- IN.c3d OUT.c3d
//
// (Plain comments rather than a `//!` header, so the end-to-end tests can include this file
// and check that its output is byte-identical to the command's.)

use c3dfix::{RepairOptions, SaveOptions};
use std::path::Path;

/// Open, repair, save; the summary of what was done.
pub fn repair_and_save(input: &Path, output: &Path) -> c3dfix::Result<c3dfix::Summary> {
    let mut trial = c3dfix::open(input)?;
    let opts = RepairOptions {
        spikes: Some("hampel".parse()?),
        lowpass: Some("butterworth:4:6".parse()?),
        ..RepairOptions::default()
    };
    let done = c3dfix::repair(&mut trial, &opts, input)?;
    let save = SaveOptions {
        force: true,
        ..SaveOptions::default()
    };
    c3dfix::save(&trial, output, &save)?;
    Ok(done.summary)
}

#[allow(dead_code)]
fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let [input, output] = args.as_slice() else {
        eprintln!("usage: repair_file IN.c3d OUT.c3d");
        std::process::exit(2);
    };
    match repair_and_save(Path::new(input), Path::new(output)) {
        Ok(s) => println!(
            "{input} -> {output}: {} of {} gaps filled, {} spikes, {} samples changed",
            s.filled, s.gaps, s.spikes, s.samples_changed
        ),
        Err(e) => {
            eprintln!("error: {e}");
            std::process::exit(2);
        }
    }
}
