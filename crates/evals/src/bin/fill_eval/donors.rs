//! The donors' evidence (issue 35, item 3), measured after the fact on replayed records
//! (`--replay FILE --donors`): each record's trial is read again, the record's gap (and the
//! gaps filled with it in its group) knocked out, the donors chosen with the fills' own
//! choice ([`repair::fill::gap_donors`]), and what they do around the gap measured. Each
//! measure is then added to the expected-error model in turn and judged as the shipped
//! features were: the tuned labs left out in turn, the held-apart labs by a fit on the
//! tuned ones, and per activity with the lab and the activity held apart.
//!
//! The records do not keep the donors, and refilling every lab's gaps to keep them is a
//! records run of 40 minutes or more; the donors' choice reads only the trial and the gap,
//! so it is made again here as the fill's first pass made it, on the trial as the records'
//! run read it (see [`load_as_recorded`]). A measure is read over the PCA fill's donors,
//! weighted as the fill weighs them, or over the rigid fill's.

use super::activity::activities_of;
use super::*;
use evals::fit::{fit_rows, ln_real_over_scored, Model};
use rayon::prelude::*;
use repair::fill::{features, gap_donors, FEATURES};
use repair::Trial;

/// The measures tried, each one feature (ln of the measure; see [`measure`]).
const MEASURES: [&str; 6] = [
    "PCA donors' distance spread beside the gap (weighted mean of sd / mean)",
    "most rigid donor's distance spread beside the gap (least sd / mean of the rigid donors)",
    "donors' speed in the gap over beside it (PCA-weighted)",
    "donors' acceleration in the gap over beside it (PCA-weighted)",
    "donors' roughness around the gap (mean second difference over mean step, PCA-weighted)",
    "donors' largest acceleration in the gap over the largest beside it (PCA-weighted)",
];
const NM: usize = MEASURES.len();

/// Frames either side of a gap the measures read: as many as the gap, at least 10 (the
/// window the target's own speed and acceleration were read over in the last round).
fn side(len: usize) -> usize {
    len.max(10)
}

/// The activities whose rows fail the goal, and walking, as the docs' table names them.
const ROWS: [&str; 6] = [
    "jumping",
    "stairs",
    "landing",
    "dance",
    "rolling on the floor",
    "walking",
];

/// One record with its measures (`None` where a measure has nothing to read: no donor,
/// no frame beside the gap).
type Measured<'a> = (&'a Rec, [Option<f64>; NM]);

/// The study: the measures for every record whose trial can be matched, then the table of
/// each measure added to the model.
pub(crate) fn donor_study(recs: &[Rec]) {
    let (measured, selected, selected_trials): (Vec<Measured>, _, _) = measure_by_trial(
        recs,
        |r| r.g.method == FillMethod::Auto && r.g.evidence.is_some(),
        measure_trial,
        "the donors' study",
    );
    let trials: HashSet<&str> = measured.iter().map(|m| m.0.file.as_str()).collect();
    println!(
        "\n### the donors' evidence as expected-error features\n\n{} records of {} trials matched (of {} records of {} trials).\n",
        measured.len(),
        trials.len(),
        selected,
        selected_trials
    );
    for (k, name) in MEASURES.iter().enumerate() {
        let name = format!("{}. {name}", k + 1);
        let known: Vec<f64> = measured.iter().filter_map(|m| m.1[k]).collect();
        let mut s = known.clone();
        s.sort_by(f64::total_cmp);
        let q = |p: f64| s.get(((s.len() as f64 - 1.0) * p) as usize).copied();
        println!(
            "- {name}: known on {} records, quartiles {:.4} / {:.4} / {:.4}",
            known.len(),
            q(0.25).unwrap_or(f64::NAN),
            q(0.5).unwrap_or(f64::NAN),
            q(0.75).unwrap_or(f64::NAN)
        );
    }
    let act = activities_of(recs);
    // Whether a measure sets the failing activities apart from walking at all.
    println!("\nMedians per activity (of the records that have the measure):\n");
    table_head("records");
    for name in ROWS {
        let of: Vec<&Measured> = measured
            .iter()
            .filter(|m| act.get(&m.0.file).copied() == Some(name))
            .collect();
        let med = |k: usize| median_cell(of.iter().filter_map(|m| m.1[k]).collect(), 4);
        println!(
            "| {name} | {} | {} |",
            of.len(),
            (0..NM).map(med).collect::<Vec<_>>().join(" | ")
        );
    }
    println!("\n| feature added | tuned labs, left out in turn: within 2x / over twice % | held-apart labs (fitted on the tuned) | {} (lab and activity apart) |", ROWS.join(", "));
    println!("|---|---|---|---|");
    let (row, base) = judge(&measured, &act, None);
    println!("| none (the shipped 16) | {row} |");
    for (k, name) in MEASURES.iter().enumerate() {
        let x = column(&measured, k);
        let (row, _) = judge(&measured, &act, Some(&x));
        println!("| {name} | {row} |");
    }
    where_they_fail(&measured, &act, &base);
}

/// The head of a table with one row per activity, a count column named `counted` and a
/// column per measure.
fn table_head(counted: &str) {
    println!(
        "| activity | {counted} | {} |",
        (1..=NM)
            .map(|k| format!("measure {k}"))
            .collect::<Vec<_>>()
            .join(" | ")
    );
    println!("|---|---|{}", "---|".repeat(NM));
}

/// The upper median of `v` with `digits` decimals, "–" for none.
fn median_cell(v: Vec<f64>, digits: usize) -> String {
    evals::stats::median(v).map_or("–".to_string(), |x| format!("{x:.digits$}"))
}

/// Whether the measures set apart the gaps the shipped features misjudge: per activity of
/// [`ROWS`], each measure's median over the gaps above twice their estimate (lab and
/// activity apart), within 2x of it, and below half of it.
fn where_they_fail(
    measured: &[Measured],
    act: &HashMap<String, &'static str>,
    base: &[(usize, GapScore)],
) {
    println!("\nMedians of each measure by how the shipped features' estimate (lab and activity apart) fared: above twice / within 2x / below half:\n");
    table_head("gaps above / within / below");
    for name in ROWS {
        let of: Vec<&(usize, GapScore)> = base
            .iter()
            .filter(|(i, _)| act.get(&measured[*i].0.file).copied() == Some(name))
            .collect();
        // 1 above twice the estimate, 0 within 2x, -1 below half.
        let side = |g: &GapScore| {
            let e = g.expected.unwrap_or(f64::NAN);
            if g.mean > 2.0 * e {
                1
            } else if g.mean < 0.5 * e {
                -1
            } else {
                0
            }
        };
        let parts = [1, 0, -1].map(|s| {
            of.iter()
                .filter(|(_, g)| side(g) == s)
                .map(|(i, _)| *i)
                .collect::<Vec<usize>>()
        });
        let med = |k: usize, v: &[usize]| {
            median_cell(v.iter().filter_map(|&i| measured[i].1[k]).collect(), 3)
        };
        println!(
            "| {name} | {} | {} |",
            parts
                .iter()
                .map(|p| p.len().to_string())
                .collect::<Vec<_>>()
                .join(" / "),
            (0..NM)
                .map(|k| parts
                    .iter()
                    .map(|p| med(k, p))
                    .collect::<Vec<_>>()
                    .join(" / "))
                .collect::<Vec<_>>()
                .join(" | ")
        );
    }
}

/// A table row's cells, and the gaps of [`ROWS`] each with its estimate (lab and activity
/// apart), by index into the measured records.
type Judged = (String, Vec<(usize, GapScore)>);

/// Measure `k` of every record as a feature: ln of the measure, less its median over the
/// records that have it (so a record without it reads as a typical one).
fn column(measured: &[Measured], k: usize) -> Vec<f64> {
    let med = evals::stats::median(
        measured
            .iter()
            .filter_map(|m| m.1[k])
            .map(|v| v.clamp(1e-4, 1e2).ln()),
    )
    .unwrap_or(0.0);
    measured
        .iter()
        .map(|m| m.1[k].map_or(0.0, |v| v.clamp(1e-4, 1e2).ln() - med))
        .collect()
}

/// The model with the shipped features, and `extra[i]` for record `i` if given, judged
/// three ways: the tuned labs each by a fit to the other tuned labs, the held-apart labs by
/// a fit to the tuned ones, and the activities of [`ROWS`] each lab by a fit to the other
/// labs' gaps of other activities. One table row's cells.
fn judge(
    measured: &[Measured],
    act: &HashMap<String, &'static str>,
    extra: Option<&[f64]>,
) -> Judged {
    let shipped = |i: usize| {
        measured[i]
            .0
            .g
            .evidence
            .as_ref()
            .map_or([0.0; FEATURES], features)
    };
    match extra {
        None => judge_n(measured, act, &shipped),
        Some(e) => judge_n(measured, act, &|i| -> [f64; FEATURES + 1] {
            let mut x = [e[i]; FEATURES + 1];
            x[..FEATURES].copy_from_slice(&shipped(i));
            x
        }),
    }
}

fn judge_n<const N: usize>(
    measured: &[Measured],
    act: &HashMap<String, &'static str>,
    x: &(dyn Fn(usize) -> [f64; N] + Sync),
) -> Judged {
    let rows: Vec<(&str, [f64; N], f64)> = measured
        .iter()
        .enumerate()
        .map(|(i, (r, _))| {
            let scored = r.g.evidence.map_or(0.0, |d| d.scored);
            (r.lab, x(i), ln_real_over_scored(r.g.mean, scored))
        })
        .collect();
    let a = |i: usize| act.get(&measured[i].0.file).copied().unwrap_or("");
    // Each fold's gaps estimated by the model fitted on `train` (indices into `rows`).
    let judged = |folds: Vec<(Vec<usize>, Vec<usize>)>| -> Vec<(usize, GapScore)> {
        folds
            .par_iter()
            .flat_map_iter(|(train, test)| {
                let t: Vec<(&str, [f64; N], f64)> = train.iter().map(|&i| rows[i]).collect();
                let m: Option<Model<N>> = fit_rows(&t);
                test.iter()
                    .filter_map(|&i| {
                        let m = m.as_ref()?;
                        let g = &measured[i].0.g;
                        let scored = g.evidence?.scored.max(1e-12);
                        let e = scored * m.log_ratio(&rows[i].1).exp();
                        Some((
                            i,
                            GapScore {
                                expected: Some(e),
                                ..*g
                            },
                        ))
                    })
                    .collect::<Vec<_>>()
            })
            .collect()
    };
    let idx = |keep: &dyn Fn(usize) -> bool| -> Vec<usize> {
        (0..rows.len()).filter(|&i| keep(i)).collect()
    };
    let tuned = |i: usize| measured[i].0.tuned;
    let held = |i: usize| measured[i].0.held;
    let mut tuned_labs: Vec<&str> = idx(&tuned).iter().map(|&i| rows[i].0).collect();
    tuned_labs.sort_unstable();
    tuned_labs.dedup();
    let lolo = judged(
        tuned_labs
            .iter()
            .map(|lab| {
                (
                    idx(&|i| tuned(i) && rows[i].0 != *lab),
                    idx(&|i| tuned(i) && rows[i].0 == *lab),
                )
            })
            .collect(),
    );
    let apart = judged(vec![(idx(&tuned), idx(&held))]);
    let mut folds: Vec<(&str, &str)> = idx(&|i| ROWS.contains(&a(i)))
        .iter()
        .map(|&i| (rows[i].0, a(i)))
        .collect();
    folds.sort_unstable();
    folds.dedup();
    let per = judged(
        folds
            .iter()
            .map(|&(lab, activity)| {
                (
                    idx(&|i| (tuned(i) || held(i)) && rows[i].0 != lab && a(i) != activity),
                    idx(&|i| rows[i].0 == lab && a(i) == activity),
                )
            })
            .collect(),
    );
    let cell = |v: Vec<GapScore>| {
        if v.is_empty() {
            return "–".to_string();
        }
        let c = calibration(&v, 0.0);
        format!(
            "{:.1} / {:.1}",
            100.0 * c.within_2x,
            100.0 * c.over_confident
        )
    };
    let mut out = vec![
        cell(lolo.iter().map(|x| x.1).collect()),
        cell(apart.iter().map(|x| x.1).collect()),
    ];
    out.push(
        ROWS.iter()
            .map(|name| {
                cell(
                    per.iter()
                        .filter(|x| a(x.0) == *name)
                        .map(|x| x.1)
                        .collect(),
                )
            })
            .collect::<Vec<_>>()
            .join(", "),
    );
    (out.join(" | "), per)
}

/// The measures of every record of one trial, or why the trial cannot be matched to its
/// records.
fn measure_trial<'a>(
    file: &str,
    rs: &[(usize, &'a Rec)],
) -> Result<Vec<(usize, Measured<'a>)>, String> {
    let corpus = FILES
        .iter()
        .find(|f| f.3 == file)
        .map(|f| f.2)
        .ok_or("not in the corpus list")?;
    let root = corpus::roots()
        .get(corpus)
        .cloned()
        .flatten()
        .ok_or("corpus not on this machine")?;
    let path = root.join(file);
    let mut trial = load_as_recorded(&path, corpus::holds_fills(corpus))?;
    // A gap's frames held the truth it was scored on: they must be recorded now.
    for (_, r) in rs {
        let (m, a, len) = (r.g.marker, r.g.first, r.g.gap_len);
        if m >= trial.markers()
            || a + len > trial.frames()
            || !trial.valid[m][a..a + len].iter().all(|&v| v)
        {
            return Err(format!(
                "marker {m}'s gap at frame {a} is not recorded in the trial as read for the records"
            ));
        }
    }
    let opts = repair::FillOptions::default();
    Ok(rs
        .iter()
        .map(|&(i, r)| {
            let len = r.g.gap_len;
            // The gap and those filled with it: in a run of 2 or 3 markers, the run's gaps
            // of the same length starting within a gap's length of it (a group's shift is
            // at most half); a run of one fills each gap alone.
            let group: Vec<(usize, usize)> = rs
                .iter()
                .filter(|(j, o)| {
                    *j == i
                        || (r.run > 1
                            && o.run == r.run
                            && o.g.gap_len == len
                            && o.g.first.abs_diff(r.g.first) <= len)
                })
                .map(|(_, o)| (o.g.marker, o.g.first))
                .collect();
            for &(m, a) in &group {
                trial.valid[m][a..a + len]
                    .iter_mut()
                    .for_each(|v| *v = false);
            }
            let v = measure(&trial, r.g.marker, r.g.first, len, &opts);
            for &(m, a) in &group {
                trial.valid[m][a..a + len]
                    .iter_mut()
                    .for_each(|v| *v = true);
            }
            (i, (r, v))
        })
        .collect())
}

/// The measures of marker `m`'s gap over frames `a..a + len` (knocked out of `t`'s masks).
fn measure(
    t: &Trial,
    m: usize,
    a: usize,
    len: usize,
    opts: &repair::FillOptions,
) -> [Option<f64>; NM] {
    let d = gap_donors(t, m, a, a + len - 1, opts);
    let n = t.frames();
    let w = side(len);
    let beside: Vec<usize> = (a.saturating_sub(w)..a)
        .chain(a + len..(a + len + w).min(n))
        .collect();
    let ok = |j: usize, f: usize| t.valid[j][f];
    let p = |j: usize, f: usize| t.xyz[j][f];
    // How far a donor's distance to the target spreads beside the gap, over its mean.
    let spread = |j: usize| {
        let v: Vec<f64> = beside
            .iter()
            .filter(|&&f| ok(j, f) && ok(m, f))
            .map(|&f| dist(p(j, f), p(m, f)))
            .collect();
        if v.len() < 3 {
            return None;
        }
        let mean = v.iter().sum::<f64>() / v.len() as f64;
        let var = v.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / v.len() as f64;
        (mean > 0.0).then(|| var.sqrt() / mean)
    };
    // A donor's mean step and mean second difference over frames `fs` (each read where the
    // frames it needs are recorded).
    let step = |j: usize, fs: &mut dyn Iterator<Item = usize>| {
        mean(
            fs.filter(|&f| f >= 1 && ok(j, f) && ok(j, f - 1))
                .map(|f| dist(p(j, f), p(j, f - 1))),
        )
    };
    let accels = |j: usize, fs: &mut dyn Iterator<Item = usize>| -> Vec<f64> {
        fs.filter(|&f| f >= 1 && f + 1 < n && ok(j, f - 1) && ok(j, f) && ok(j, f + 1))
            .map(|f| {
                let (q0, q1, q2) = (p(j, f - 1), p(j, f), p(j, f + 1));
                dist(
                    [q2[0] - q1[0], q2[1] - q1[1], q2[2] - q1[2]],
                    [q1[0] - q0[0], q1[1] - q0[1], q1[2] - q0[2]],
                )
            })
            .collect()
    };
    let peak = |v: Vec<f64>| v.into_iter().reduce(f64::max);
    let accel = |j: usize, fs: &mut dyn Iterator<Item = usize>| mean(accels(j, fs).into_iter());
    let inside = a..a + len;
    let around = a.saturating_sub(w)..(a + len + w).min(n);
    // A PCA-weighted mean of `f` over the donors that have it.
    let weighted = |f: &dyn Fn(usize) -> Option<f64>| {
        let (mut s, mut ws) = (0.0, 0.0);
        for &(j, wj) in &d.pca {
            if let Some(v) = f(j) {
                s += wj * v;
                ws += wj;
            }
        }
        (ws > 0.0).then(|| s / ws)
    };
    let ratio = |a: Option<f64>, b: Option<f64>| match (a, b) {
        (Some(a), Some(b)) if b > 0.0 => Some(a / b),
        _ => None,
    };
    [
        weighted(&spread),
        d.rigid
            .iter()
            .filter_map(|&j| spread(j))
            .min_by(f64::total_cmp),
        ratio(
            weighted(&|j| step(j, &mut (a..a + len + 1))),
            weighted(&|j| step(j, &mut beside.iter().copied())),
        ),
        ratio(
            weighted(&|j| accel(j, &mut inside.clone())),
            weighted(&|j| accel(j, &mut beside.iter().copied())),
        ),
        ratio(
            weighted(&|j| accel(j, &mut around.clone())),
            weighted(&|j| step(j, &mut around.clone())),
        ),
        ratio(
            weighted(&|j| peak(accels(j, &mut inside.clone()))),
            weighted(&|j| peak(accels(j, &mut beside.iter().copied()))),
        ),
    ]
}

/// The trial as the records' run read it (`corpus::load` and `load_recorded` then): the
/// points whose labels the POINT output lists name (ANGLES, FORCES, …) dropped, every other
/// point kept. The rules that drop the points after the first listed output and a segment's
/// axes came after the records, whose marker numbers count those points and whose fills
/// could choose them as donors; so the donors chosen here are those the records' fills
/// chose.
fn load_as_recorded(path: &std::path::Path, recorded: bool) -> Result<Trial, String> {
    let c = c3d::read_file(path).map_err(|e| e.to_string())?;
    let listed: Vec<String> = c3d::MODEL_OUTPUT_TYPES
        .iter()
        .flat_map(|p| c.parameters.get_strings("POINT", p).unwrap_or_default())
        .filter(|s| !s.is_empty())
        .collect();
    let labels = c.point_labels();
    let points: Vec<usize> = (0..labels.len())
        .filter(|&i| !listed.contains(&labels[i]))
        .collect();
    evals::corpus::trial_of(&c, &points, recorded)
}

fn mean(v: impl Iterator<Item = f64>) -> Option<f64> {
    let (s, n) = v.fold((0.0, 0usize), |(s, n), x| (s + x, n + 1));
    (n > 0).then(|| s / n as f64)
}

fn dist(a: [f64; 3], b: [f64; 3]) -> f64 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
}
