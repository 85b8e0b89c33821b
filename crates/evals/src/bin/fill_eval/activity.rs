//! `auto`'s expected errors per activity (issue 35): each trial's activity by rule from its
//! corpus's README (see `corpus::activity`), and each activity's gaps judged by models that
//! never saw their lab, and then by models that never saw their lab nor their activity.

use super::*;

/// Each record's activity, by its trial (see `corpus::activity`). A corpus not on this
/// machine gives its trials the activity its list's set names.
pub(crate) fn activities_of(recs: &[Rec]) -> HashMap<String, &'static str> {
    let roots = corpus::roots();
    let mut out = HashMap::new();
    for r in recs {
        if out.contains_key(&r.file) {
            continue;
        }
        let corpus = FILES.iter().find(|f| f.3 == r.file).map(|f| f.2);
        let readme = corpus
            .and_then(|c| roots.get(c).cloned().flatten())
            .and_then(|root| std::fs::read_to_string(root.join("README.md")).ok());
        out.insert(
            r.file.clone(),
            corpus::activity(readme.as_deref(), &r.file, r.set),
        );
    }
    out
}

/// Per activity, `auto`'s gaps each estimated by the model fitted (see
/// [`evals::fit::fit`]) to every other lab's gaps, then to every other lab's gaps of
/// other activities: how many are within 2× of their estimate and above twice it, and the
/// largest step of a fill over the marker's largest recorded step. The fit reads the
/// tuned and held-apart labs' gaps, as the shipped model's does; the gaps judged are every
/// lab's. With `gaps_out`, every judged gap is written there as a tab-separated line
/// (activity, lab, trial, marker, first frame, length, run, chosen method, real error, the
/// two estimates, the step ratio and the evidence), to read where an activity fails.
pub(crate) fn per_activity(recs: &[Rec], gaps_out: Option<&std::path::Path>) {
    use rayon::prelude::*;
    let act = activities_of(recs);
    let auto: Vec<&Rec> = recs
        .iter()
        .filter(|r| r.g.method == FillMethod::Auto)
        .collect();
    let a = |r: &Rec| act[&r.file];
    let mut folds: Vec<(&str, &str)> = auto.iter().map(|r| (r.lab, a(r))).collect();
    folds.sort_unstable();
    folds.dedup();
    // Each (lab, activity)'s gaps under the two held-apart models: lab only, lab and activity.
    let judged: Vec<Vec<(&Rec, GapScore, GapScore)>> = folds
        .par_iter()
        .map(|&(lab, activity)| {
            let train = |keep: &dyn Fn(&Rec) -> bool| {
                let v: Vec<(&str, &GapScore)> = auto
                    .iter()
                    .filter(|r| (r.held || r.tuned) && r.lab != lab && keep(r))
                    .map(|r| (r.lab, &r.g))
                    .collect();
                fit(&v)
            };
            let by_lab = train(&|_| true);
            let by_both = train(&|r| a(r) != activity);
            auto.iter()
                .filter(|r| r.lab == lab && a(r) == activity)
                .map(|r| {
                    let est = |m: &Option<evals::fit::Model>| GapScore {
                        expected: m.as_ref().and_then(|m| predict(&r.g, m)).or(r.g.expected),
                        ..r.g
                    };
                    (*r, est(&by_lab), est(&by_both))
                })
                .collect()
        })
        .collect();
    let judged: Vec<&(&Rec, GapScore, GapScore)> = judged.iter().flatten().collect();
    if let Some(p) = gaps_out {
        let mut out = String::from(
            "activity\tlab\theld\tfile\trate\tmarker\tfirst\tlen\trun\tchosen\terror\test_lab\test_both\tstep\tevidence\n",
        );
        for (r, l, b) in &judged {
            let chosen = r.g.chosen.map_or("-", |m| m.name());
            let ev = serde_json::to_string(&r.g.evidence).unwrap_or_default();
            out.push_str(&format!(
                "{}\t{}\t{}\t{}\t{}\t{}\t{}\t{}\t{}\t{chosen}\t{}\t{}\t{}\t{}\t{ev}\n",
                a(r),
                r.lab,
                r.held,
                r.file,
                r.rate,
                r.g.marker,
                r.g.first,
                r.g.gap_len,
                r.run,
                r.g.mean,
                l.expected.unwrap_or(f64::NAN),
                b.expected.unwrap_or(f64::NAN),
                r.g.step_ratio,
            ));
        }
        if let Err(e) = std::fs::write(p, out) {
            eprintln!("fill_eval: --activity-gaps {}: {e}", p.display());
        }
    }
    let mut names: Vec<&str> = act.values().copied().collect();
    names.sort_unstable();
    names.dedup();
    println!("\n### expected errors per activity, labs held apart\n");
    println!("Each activity's `auto` gaps, each estimated by a model fitted to the other labs (lab held apart), and by one fitted to the other labs' trials of other activities (lab and activity held apart). Trials and labs: * marks labs nothing was chosen on.\n");
    println!("| activity | trials (labs) | gaps | shipped model: within 2x % | over 2x % | lab apart: Spearman | within 2x % | over 2x % | lab and activity apart: Spearman | within 2x % | over 2x % | largest step ratio |");
    println!("|---|---|---|---|---|---|---|---|---|---|---|---|");
    for name in names {
        let v: Vec<&&(&Rec, GapScore, GapScore)> =
            judged.iter().filter(|x| a(x.0) == name).collect();
        if v.is_empty() {
            continue;
        }
        let mut trials: Vec<&str> = v.iter().map(|x| x.0.file.as_str()).collect();
        trials.sort_unstable();
        trials.dedup();
        let mut labs: Vec<String> = v
            .iter()
            .map(|x| format!("{}{}", x.0.lab, if x.0.held { "*" } else { "" }))
            .collect();
        labs.sort_unstable();
        labs.dedup();
        // The shipped model's own estimates, as the run's repair made them: on a lab the
        // model was not fitted on (c3d-labs' trials), the fairest figure of all.
        let c0 = calibration(&v.iter().map(|x| x.0.g).collect::<Vec<_>>(), 0.0);
        let c1 = calibration(&v.iter().map(|x| x.1).collect::<Vec<_>>(), 0.0);
        let c2 = calibration(&v.iter().map(|x| x.2).collect::<Vec<_>>(), 0.0);
        let step = v.iter().map(|x| x.0.g.step_ratio).fold(0.0, f64::max);
        println!(
            "| {name} | {} ({}) | {} | {:.1} | {:.1} | {:.3} | {:.1} | {:.1} | {:.3} | {:.1} | {:.1} | {step:.2} |",
            trials.len(),
            labs.join(", "),
            c1.gaps,
            100.0 * c0.within_2x,
            100.0 * c0.over_confident,
            c1.spearman,
            100.0 * c1.within_2x,
            100.0 * c1.over_confident,
            c2.spearman,
            100.0 * c2.within_2x,
            100.0 * c2.over_confident,
        );
    }
    per_lab(&judged, &a);
    per_trial(&judged, &a);
    println!("\nTrials per activity:\n");
    let mut by: BTreeMap<&str, Vec<&str>> = BTreeMap::new();
    for (f, n) in &act {
        by.entry(n).or_default().push(f);
    }
    for (n, mut fs) in by {
        fs.sort_unstable();
        println!("- {n}: {}", fs.join(", "));
    }
}

/// Each activity's gaps lab by lab, under the lab-apart and the lab-and-activity-apart
/// models: the goal is set on every activity with two labs or more, and a pooled figure can
/// hide one lab far off.
fn per_lab(judged: &[&(&Rec, GapScore, GapScore)], a: &dyn Fn(&Rec) -> &'static str) {
    let mut by: BTreeMap<(&str, &str), Vec<(GapScore, GapScore)>> = BTreeMap::new();
    for (r, lab, both) in judged {
        by.entry((a(r), r.lab)).or_default().push((*lab, *both));
    }
    println!("\n### expected errors per activity and lab, held apart\n");
    println!("| activity | lab | gaps | lab apart: within 2x % | over 2x % | lab and activity apart: within 2x % | over 2x % |");
    println!("|---|---|---|---|---|---|---|");
    for ((act, lab), v) in &by {
        let c1 = calibration(&v.iter().map(|x| x.0).collect::<Vec<_>>(), 0.0);
        let c2 = calibration(&v.iter().map(|x| x.1).collect::<Vec<_>>(), 0.0);
        println!(
            "| {act} | {lab} | {} | {:.1} | {:.1} | {:.1} | {:.1} |",
            c1.gaps,
            100.0 * c1.within_2x,
            100.0 * c1.over_confident,
            100.0 * c2.within_2x,
            100.0 * c2.over_confident
        );
    }
}

/// Each trial's gaps under the lab-and-activity-apart model, and per activity how many of
/// its trials alone would miss the goal (≥ 80 % within 2×, ≤ 5 % above twice): most
/// activities here are one trial, and walking's own trials say how far one trial strays
/// from its activity's pooled figures.
fn per_trial(judged: &[&(&Rec, GapScore, GapScore)], a: &dyn Fn(&Rec) -> &'static str) {
    let mut by: BTreeMap<(&str, &str), Vec<GapScore>> = BTreeMap::new();
    for (r, _, both) in judged {
        by.entry((a(r), r.file.as_str())).or_default().push(*both);
    }
    println!("\n### expected errors per trial, lab and activity apart\n");
    println!("| activity | trial | gaps | within 2x % | over 2x % |");
    println!("|---|---|---|---|---|");
    let mut tally: BTreeMap<&str, (usize, usize, f64, f64, f64, f64)> = BTreeMap::new();
    for ((act, file), v) in &by {
        let c = calibration(v, 0.0);
        println!(
            "| {act} | {file} | {} | {:.1} | {:.1} |",
            c.gaps,
            100.0 * c.within_2x,
            100.0 * c.over_confident
        );
        let t = tally
            .entry(act)
            .or_insert((0, 0, f64::INFINITY, 0.0, f64::INFINITY, 0.0));
        t.0 += 1;
        t.1 += usize::from(c.within_2x < 0.8 || c.over_confident > 0.05);
        t.2 = t.2.min(c.within_2x);
        t.3 = t.3.max(c.within_2x);
        t.4 = t.4.min(c.over_confident);
        t.5 = t.5.max(c.over_confident);
    }
    println!();
    for (act, (n, miss, w0, w1, o0, o1)) in tally {
        println!(
            "- {act}: {miss} of {n} trials alone miss the goal (within 2x {:.1}-{:.1} %, over twice {:.1}-{:.1} %)",
            100.0 * w0,
            100.0 * w1,
            100.0 * o0,
            100.0 * o1
        );
    }
}
