//! Where each fragment of a labelled trial goes (a [`Plan`]) and the writing of it: points
//! renamed to the template's markers, fragments moved between points as recorded, and the
//! record a rerun reads (docs/label.md).

use crate::error::{Error, Result};
use repair::label::FragmentLabel;
use std::collections::BTreeMap;
use std::path::Path;

/// The points fragments end in.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct Plan {
    /// The point each fragment is in after writing.
    pub final_point: Vec<usize>,
    /// Whether a fragment's label is written (it ends in the point of that name).
    pub written: Vec<bool>,
    /// Unlabelled points that take a template marker's name: `(point, marker)`.
    pub renamed: Vec<(usize, usize)>,
}

impl Plan {
    /// Samples that change point.
    pub fn moved_samples(
        &self,
        frags: &[FragmentLabel],
        rows: &[usize],
        trial: &repair::Trial,
    ) -> usize {
        frags
            .iter()
            .enumerate()
            .filter(|(i, a)| self.final_point[*i] != rows[a.fragment.row])
            .map(|(_, a)| {
                let g = &a.fragment;
                trial.valid[g.row][g.first..=g.last]
                    .iter()
                    .filter(|&&v| v)
                    .count()
            })
            .sum()
    }
}

/// The state of the points while planning: which fragments each holds.
struct Places<'a> {
    frags: &'a [FragmentLabel],
    holds: BTreeMap<usize, Vec<usize>>,
    at: Vec<usize>,
    /// Points that carry a template marker's name (given or taken).
    named: Vec<bool>,
    unlabelled: &'a [usize],
}

impl Places<'_> {
    fn free(&self, point: usize, i: usize) -> bool {
        let g = &self.frags[i].fragment;
        self.holds.get(&point).is_none_or(|h| {
            h.iter()
                .all(|&j| j == i || !self.frags[j].fragment.overlaps(g))
        })
    }

    fn put(&mut self, i: usize, point: usize) {
        let from = self.at[i];
        if let Some(h) = self.holds.get_mut(&from) {
            h.retain(|&j| j != i);
        }
        self.holds.entry(point).or_default().push(i);
        self.at[i] = point;
    }

    /// Move fragment `i` into an unlabelled point without a name that is free over its
    /// frames (its own first), unless `except`.
    fn relocate(&mut self, i: usize, except: usize, home: usize) -> bool {
        let choice = std::iter::once(home)
            .chain(self.unlabelled.iter().copied())
            .find(|&p| {
                p != except && !self.named[p] && self.unlabelled.contains(&p) && self.free(p, i)
            });
        match choice {
            Some(p) => {
                self.put(i, p);
                true
            }
            None => false,
        }
    }
}

/// Where each fragment goes. `rows[row]` is the point of a trial row; `common` the trial's
/// points that carry a template marker's name, `(point, marker)`; `unlabelled` its
/// unlabelled points; `points` how many points the file has.
pub(crate) fn plan(
    frags: &[FragmentLabel],
    rows: &[usize],
    common: &[(usize, usize)],
    unlabelled: &[usize],
    points: usize,
) -> Plan {
    let mut named = vec![false; points.max(rows.iter().max().map_or(0, |m| m + 1))];
    let mut target: BTreeMap<usize, usize> = BTreeMap::new();
    for &(p, m) in common {
        named[p] = true;
        target.insert(m, p);
    }
    let mut places = Places {
        frags,
        holds: BTreeMap::new(),
        at: frags.iter().map(|a| rows[a.fragment.row]).collect(),
        named,
        unlabelled,
    };
    for (i, &p) in places.at.clone().iter().enumerate() {
        places.holds.entry(p).or_default().push(i);
    }
    let mut markers: Vec<usize> = frags.iter().filter_map(|a| a.label).collect();
    markers.sort_unstable();
    markers.dedup();
    let mut renamed = Vec::new();
    let mut written = vec![false; frags.len()];
    for m in markers {
        let mine: Vec<usize> = (0..frags.len())
            .filter(|&i| frags[i].label == Some(m))
            .collect();
        let t = match target.get(&m) {
            Some(&t) => t,
            None => match take_point(&mut places, &mine, m) {
                Some(t) => {
                    renamed.push((t, m));
                    target.insert(m, t);
                    t
                }
                None => continue,
            },
        };
        for &i in &mine {
            if places.at[i] == t {
                written[i] = true;
                continue;
            }
            // Another marker's (or no marker's) fragment in the way goes elsewhere first.
            let g = frags[i].fragment;
            let blocking: Vec<usize> = places.holds.get(&t).map_or(Vec::new(), |h| {
                h.iter()
                    .copied()
                    .filter(|&j| frags[j].label != Some(m) && frags[j].fragment.overlaps(&g))
                    .collect()
            });
            let home = |j: usize| rows[frags[j].fragment.row];
            if blocking.iter().all(|&j| places.relocate(j, t, home(j))) && places.free(t, i) {
                places.put(i, t);
                written[i] = true;
            }
        }
    }
    Plan {
        final_point: places.at,
        written,
        renamed,
    }
}

/// The unlabelled point that takes marker `m`'s name: among those holding its fragments
/// (most of its samples first), then the empty ones, the first whose other fragments can
/// all go to other unlabelled points.
fn take_point(places: &mut Places<'_>, mine: &[usize], m: usize) -> Option<usize> {
    let frags = places.frags;
    let mut cands: Vec<(usize, usize)> = places
        .unlabelled
        .iter()
        .filter(|&&p| !places.named[p])
        .map(|&p| {
            let n: usize = mine
                .iter()
                .filter(|&&i| places.at[i] == p)
                .map(|&i| frags[i].fragment.len())
                .sum();
            (p, n)
        })
        .filter(|&(p, n)| n > 0 || places.holds.get(&p).is_none_or(Vec::is_empty))
        .collect();
    cands.sort_by(|a, b| b.1.cmp(&a.1).then(a.0.cmp(&b.0)));
    for (q, _) in cands {
        let others: Vec<usize> = places.holds.get(&q).map_or(Vec::new(), |h| {
            h.iter()
                .copied()
                .filter(|&j| frags[j].label != Some(m))
                .collect()
        });
        let before = (places.holds.clone(), places.at.clone());
        places.named[q] = true;
        if others.iter().all(|&j| places.relocate(j, q, q)) {
            return Some(q);
        }
        places.named[q] = false;
        (places.holds, places.at) = before;
    }
    None
}

/// Write `plan` into `c`: renames, moves (each sample as recorded; the point it leaves is
/// marked missing there) and the record. Nothing is written when nothing changes.
pub(crate) fn apply(
    c: &mut c3d::C3d,
    path: &Path,
    plan: &Plan,
    frags: &[FragmentLabel],
    rows: &[usize],
    name: &dyn Fn(usize) -> String,
    template_path: &Path,
) -> Result<()> {
    let moves: Vec<(usize, usize, usize, usize)> = frags
        .iter()
        .enumerate()
        .filter(|(i, a)| plan.final_point[*i] != rows[a.fragment.row])
        .map(|(i, a)| {
            (
                rows[a.fragment.row],
                plan.final_point[i],
                a.fragment.first,
                a.fragment.last,
            )
        })
        .collect();
    if moves.is_empty() && plan.renamed.is_empty() {
        return Ok(());
    }
    let c3d_err = |source| Error::C3d {
        path: path.to_path_buf(),
        source,
    };
    rename(c, &plan.renamed, name).map_err(c3d_err)?;
    move_fragments(c, &moves).map_err(c3d_err)?;
    // The record: every fragment that changed point or whose point changed name.
    let renamed: Vec<usize> = plan.renamed.iter().map(|r| r.0).collect();
    let first_frame = c.first_frame() as f32;
    let rows_out: Vec<f32> = frags
        .iter()
        .enumerate()
        .filter(|(i, a)| {
            plan.final_point[*i] != rows[a.fragment.row] || renamed.contains(&plan.final_point[*i])
        })
        .flat_map(|(i, a)| {
            [
                (plan.final_point[i] + 1) as f32,
                (rows[a.fragment.row] + 1) as f32,
                a.fragment.first as f32 + first_frame,
                a.fragment.last as f32 + first_frame,
            ]
        })
        .collect();
    let ps = &mut c.parameters;
    let file = template_path.file_name().map_or_else(
        || template_path.display().to_string(),
        |f| f.to_string_lossy().into_owned(),
    );
    let what = format!("--template {file}");
    ps.set_strings(
        crate::rerun::GROUP,
        "LABEL",
        &[what.chars().take(255).collect()],
    )
    .map_err(c3d_err)?;
    crate::rerun::set_rows(
        ps,
        "LABELLED",
        &rows_out,
        4,
        "fragments c3dfix label wrote: point number now, point number before, first frame, last frame",
    )
    .map_err(c3d_err)?;
    if let Some(p) = ps.get_mut(crate::rerun::GROUP, "LABEL") {
        if p.description.is_empty() {
            p.description = "template c3dfix label labelled from".into();
        }
    }
    Ok(())
}

/// Give each `(point, marker)` the marker's name in POINT:LABELS (or the LABELS2, … that
/// holds it).
fn rename(
    c: &mut c3d::C3d,
    renamed: &[(usize, usize)],
    name: &dyn Fn(usize) -> String,
) -> c3d::Result<()> {
    for &(p, m) in renamed {
        let mut offset = 0;
        for k in 1.. {
            let pname = if k == 1 {
                "LABELS".to_string()
            } else {
                format!("LABELS{k}")
            };
            let Some(mut list) = c.parameters.get_strings("POINT", &pname) else {
                break;
            };
            if p < offset + list.len() {
                list[p - offset] = name(m);
                c.parameters.set_strings("POINT", &pname, &list)?;
                break;
            }
            offset += list.len();
        }
    }
    Ok(())
}

/// Move each `(from, to, first, last)` fragment: every source sample is read as recorded,
/// then all sources are marked missing, then the targets written.
fn move_fragments(c: &mut c3d::C3d, moves: &[(usize, usize, usize, usize)]) -> c3d::Result<()> {
    if moves.is_empty() {
        return Ok(());
    }
    type Sample = (usize, usize, [f32; 3], f32, u8);
    let states = vec![(); c.point_chunks()];
    let read: Vec<(Vec<Sample>, Vec<Sample>)> = c.map_point_chunks(states, |(), view| {
        let (mut miss, mut write) = (Vec::new(), Vec::new());
        for f in 0..view.frames {
            let frame = view.first_frame + f;
            for &(from, to, a, b) in moves {
                if (a..=b).contains(&frame) && from < view.count && to < view.count {
                    let (p, r, k) = view.sample(f, from);
                    write.push((frame, to, p, r, k));
                    let (xyz, r, k) = c3d::Mark::Missing.stored();
                    miss.push((frame, from, xyz, r, k));
                }
            }
        }
        (miss, write)
    });
    let (miss, write): (Vec<_>, Vec<_>) = read.into_iter().unzip();
    c.patch_points(
        miss.into_iter()
            .flatten()
            .chain(write.into_iter().flatten()),
    )?;
    Ok(())
}
