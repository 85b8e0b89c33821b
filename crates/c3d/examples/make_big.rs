//! Generates the large trial the memory and speed measurements of long recordings use:
//! 100 000 frames × 100 markers of float data with 4 analog channels (about 162 MB; see
//! `common/big_trial.rs`).
//!
//! ```sh
//! cargo run --release -p c3d --example make_big -- target/big_100k_x_100.c3d
//! ```

#[path = "common/big_trial.rs"]
mod big_trial;

fn main() {
    let Some(out) = std::env::args().nth(1) else {
        eprintln!("usage: make_big OUT.c3d");
        std::process::exit(2);
    };
    match big_trial::big_trial().map(|b| std::fs::write(&out, &b).map(|_| b.len())) {
        Ok(Ok(n)) => println!("wrote {out} ({n} bytes)"),
        Ok(Err(e)) => {
            eprintln!("{out}: {e}");
            std::process::exit(1);
        }
        Err(e) => {
            eprintln!("cannot build the trial: {e}");
            std::process::exit(1);
        }
    }
}
