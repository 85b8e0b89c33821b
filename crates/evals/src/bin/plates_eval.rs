//! The contacts of every corpus plate against the file's own Foot Strike and Foot Off
//! events, per lab: how many contacts, how many start near a Foot Strike and end near a
//! Foot Off, and the timing error in ms. The figures of `docs/plates.md`.
//!
//! `cargo run --release -p evals --bin plates_eval` (corpora in `../shared`).

use c3dfix::{force_platforms, ForceOptions};
use clap::Parser;
use std::collections::BTreeMap;

/// Every corpus plate's contacts against the file's own events, per lab (no options: the
/// corpora are found as the tests find them).
#[derive(Parser)]
#[command(name = "plates_eval")]
struct Cli {}

#[derive(Default)]
struct Tally {
    trials: usize,
    plates: usize,
    contacts: usize,
    whole: usize,
    starts: Vec<f64>,
    ends: Vec<f64>,
}

fn main() {
    Cli::parse();
    let mut files = testkit::all_c3d_files();
    if let Some(d) = testkit::c3d_more() {
        files.extend(testkit::files_with_ext(&d, "c3d"));
    }
    let mut labs: BTreeMap<String, Tally> = BTreeMap::new();
    for f in files {
        let Ok(c) = c3dfix::open(&f) else { continue };
        let Ok(fp) = force_platforms(&c, &ForceOptions::default()) else {
            continue;
        };
        if fp.platforms.is_empty() {
            continue;
        }
        let short = testkit::short(&f);
        let short = short.trim_start_matches("c3d-samples/../");
        let rate = c.point_rate() as f64;
        let events = c.events();
        let times = |word: &str| -> Vec<f64> {
            events
                .iter()
                .filter(|e| e.label.to_ascii_lowercase().contains(word))
                .map(|e| e.time)
                .collect()
        };
        let (strikes, offs) = (times("strike"), times("off"));
        let t = labs.entry(evals::labs::of_short(short)).or_default();
        t.trials += 1;
        println!("{short}");
        for p in &fp.platforms {
            t.plates += 1;
            let n = p.push.len();
            let base = p
                .baseline
                .map(|b| format!("{} {:.1} N", b.source.name(), b.level))
                .unwrap_or_else(|| "none".into());
            println!(
                "  plate {} peak {:.0} N  baseline {base}  {} contact(s)",
                p.index,
                p.peak_force,
                p.contacts.len()
            );
            for k in &p.contacts {
                t.contacts += 1;
                if k.first_sample == 0 && k.last_sample + 1 == n {
                    t.whole += 1;
                }
                let near = |list: &[f64], at: f64| {
                    list.iter()
                        .map(|e| at - e)
                        .min_by(|a, b| a.abs().total_cmp(&b.abs()))
                };
                let (s, e) = (near(&strikes, k.first_time), near(&offs, k.last_time));
                print!(
                    "    {:.3}-{:.3} s (frames {}-{}) peak {:.0} N",
                    k.first_time, k.last_time, k.first_frame, k.last_frame, k.peak
                );
                // Each end is judged only where the file marks it: an event within 10
                // frames (the rule of tests/contacts.rs).
                if let Some(s) = s.filter(|s| s.abs() * rate <= 10.0) {
                    t.starts.push(s * 1000.0);
                    print!("  strike {:+.0} ms", s * 1000.0);
                }
                if let Some(e) = e.filter(|e| e.abs() * rate <= 10.0) {
                    t.ends.push(e * 1000.0);
                    print!("  off {:+.0} ms", e * 1000.0);
                }
                println!();
            }
        }
    }
    println!("\nlab: trials, plates, contacts, whole-trial contacts; starts at a Foot Strike: n (mean |ms|, max |ms|); ends at a Foot Off: n (mean |ms|, max |ms|)");
    for (name, t) in &labs {
        let stats = |v: &[f64]| {
            let m = v.iter().map(|x| x.abs()).sum::<f64>() / v.len().max(1) as f64;
            let x = v.iter().fold(0.0f64, |a, b| a.max(b.abs()));
            format!("{m:.0}, {x:.0}")
        };
        println!(
            "{name}: {}, {}, {}, {}; {} ({}); {} ({})",
            t.trials,
            t.plates,
            t.contacts,
            t.whole,
            t.starts.len(),
            stats(&t.starts),
            t.ends.len(),
            stats(&t.ends)
        );
    }
}
