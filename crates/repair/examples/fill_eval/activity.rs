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
/// [`repair::fit::fit`]) to every other lab's gaps, then to every other lab's gaps of
/// other activities: how many are within 2× of their estimate and above twice it, and the
/// largest step of a fill over the marker's largest recorded step. The fit reads the
/// tuned and held-apart labs' gaps, as the shipped model's does; the gaps judged are every
/// lab's.
pub(crate) fn per_activity(recs: &[Rec]) {
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
                    let est = |m: &Option<repair::fit::Model>| GapScore {
                        expected: m.as_ref().and_then(|m| predict(&r.g, m)).or(r.g.expected),
                        ..r.g
                    };
                    (*r, est(&by_lab), est(&by_both))
                })
                .collect()
        })
        .collect();
    let judged: Vec<&(&Rec, GapScore, GapScore)> = judged.iter().flatten().collect();
    let mut names: Vec<&str> = act.values().copied().collect();
    names.sort_unstable();
    names.dedup();
    println!("\n### expected errors per activity, labs held apart\n");
    println!("Each activity's `auto` gaps, each estimated by a model fitted to the other labs (lab held apart), and by one fitted to the other labs' trials of other activities (lab and activity held apart). Trials and labs: * marks labs nothing was chosen on.\n");
    println!("| activity | trials (labs) | gaps | lab apart: Spearman | within 2x % | over 2x % | lab and activity apart: Spearman | within 2x % | over 2x % | largest step ratio |");
    println!("|---|---|---|---|---|---|---|---|---|---|");
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
        let c1 = calibration(&v.iter().map(|x| x.1).collect::<Vec<_>>(), 0.0);
        let c2 = calibration(&v.iter().map(|x| x.2).collect::<Vec<_>>(), 0.0);
        let step = v.iter().map(|x| x.0.g.step_ratio).fold(0.0, f64::max);
        println!(
            "| {name} | {} ({}) | {} | {:.3} | {:.1} | {:.1} | {:.3} | {:.1} | {:.1} | {step:.2} |",
            trials.len(),
            labs.join(", "),
            c1.gaps,
            c1.spearman,
            100.0 * c1.within_2x,
            100.0 * c1.over_confident,
            c2.spearman,
            100.0 * c2.within_2x,
            100.0 * c2.over_confident,
        );
    }
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
