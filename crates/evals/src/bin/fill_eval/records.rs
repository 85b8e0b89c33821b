//! Every artificial gap's errors as records ([`Rec`]): written as JSON lines with
//! `--records`, read back with `--replay`, so a report or a fit runs again without filling.

use super::*;

/// One gap record with where it came from.
#[derive(Clone)]
pub(crate) struct Rec {
    /// The trial, relative to its corpus.
    pub(crate) file: String,
    /// From a lab nothing was chosen on (see [`TUNED`]).
    pub(crate) held: bool,
    /// From the corpora everything was chosen on.
    pub(crate) tuned: bool,
    pub(crate) set: &'static str,
    pub(crate) lab: &'static str,
    pub(crate) rate: u32,
    pub(crate) group: usize,
    /// The run the gap came from: 1, 2 or 3 markers (`group` puts 2 and 3 together); 0 in
    /// records written before it was kept.
    pub(crate) run: usize,
    pub(crate) g: GapScore,
}

/// Every gap's record as one JSON line (`--records`).
pub(crate) fn write_records(p: &std::path::Path, recs: &[Rec]) {
    let mut f = std::io::BufWriter::new(std::fs::File::create(p).expect("records file"));
    for r in recs {
        let v = serde_json::json!({"file": r.file, "held": r.held, "tuned": r.tuned, "set": r.set, "lab": r.lab, "rate": r.rate, "group": r.group, "run": r.run, "gap": r.g});
        writeln!(f, "{v}").expect("write records");
    }
}

/// The records of an earlier run (`--records`), to report again without filling: the
/// expected-error model's fit and its held-apart check read only what the records hold.
pub(crate) fn replay(path: &std::path::Path) -> Result<Vec<Rec>, String> {
    #[derive(serde::Deserialize)]
    struct Line {
        file: String,
        held: bool,
        tuned: bool,
        set: String,
        lab: String,
        rate: u32,
        group: usize,
        #[serde(default)]
        run: usize,
        gap: GapScore,
    }
    // Set and lab names as the corpus list spells them (records of labs it no longer
    // lists keep theirs).
    let name = |s: &str| -> &'static str {
        FILES
            .iter()
            .flat_map(|f| [f.0, f.1])
            .find(|n| *n == s)
            .unwrap_or_else(|| Box::leak(s.to_string().into_boxed_str()))
    };
    let text = std::fs::read_to_string(path).map_err(|e| e.to_string())?;
    let mut recs = text
        .lines()
        .enumerate()
        .map(|(i, l)| {
            let mut v: Line =
                serde_json::from_str(l).map_err(|e| format!("line {}: {e}", i + 1))?;
            if let (FillMethod::Auto, Some(mut d)) = (v.gap.method, v.gap.evidence) {
                // Records made before the fill's step was evidence hold it beside.
                d.step = d.step.or(Some(v.gap.step_ratio));
                // And the method leading the fill, which they record as `chosen`.
                d.lead = d.lead.or(v.gap.chosen);
                v.gap.evidence = Some(d);
            }
            Ok(Rec {
                file: v.file,
                held: v.held,
                tuned: v.tuned,
                set: name(&v.set),
                lab: name(&v.lab),
                rate: v.rate,
                group: v.group,
                run: v.run,
                g: v.gap,
            })
        })
        .collect::<Result<Vec<Rec>, String>>()?;
    // Records made before the marker's acceleration was evidence get it from their trials.
    motion::fill_in_accel(&mut recs);
    // `auto`'s expected error as the model now in the code makes it.
    for r in &mut recs {
        if let (FillMethod::Auto, Some(d)) = (r.g.method, r.g.evidence) {
            r.g.expected = Some(repair::fill::calibrated(&d));
        }
    }
    Ok(recs)
}

/// The records `keep` selects, grouped by trial and measured a trial at a time in parallel
/// (`measure` reads the trial once for all its records), back in the records' own order:
/// the studies' fits read sums whose rounding follows that order. A trial that cannot be
/// measured is said and left out of `study`. Also: how many records and trials were
/// selected.
pub(crate) fn measure_by_trial<'a, T: Send>(
    recs: &'a [Rec],
    keep: impl Fn(&Rec) -> bool,
    measure: impl Fn(&str, &[(usize, &'a Rec)]) -> Result<Vec<(usize, T)>, String> + Sync,
    study: &str,
) -> (Vec<T>, usize, usize) {
    use rayon::prelude::*;
    let mut by_file: BTreeMap<&str, Vec<(usize, &Rec)>> = BTreeMap::new();
    for (i, r) in recs.iter().enumerate() {
        if keep(r) {
            by_file.entry(r.file.as_str()).or_default().push((i, r));
        }
    }
    let mut measured: Vec<(usize, T)> = by_file
        .par_iter()
        .flat_map_iter(|(file, rs)| match measure(file, rs) {
            Ok(v) => v,
            Err(e) => {
                eprintln!("{file}: {e}: left out of {study}");
                Vec::new()
            }
        })
        .collect();
    measured.sort_by_key(|m| m.0);
    let selected = by_file.values().map(Vec::len).sum();
    let measured = measured.into_iter().map(|m| m.1).collect();
    (measured, selected, by_file.len())
}
