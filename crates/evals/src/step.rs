//! The step-plausibility rule checked as a user meets it: through the file. Gaps of 5–80
//! frames are knocked into fully recorded stretches of every marker (samples with a
//! residual above 0, so no software fill stands in for the truth), the file is written and
//! read back, repaired with `c3dfix repair`'s defaults, written and read back again, and
//! every filled gap's steps (joins to its anchors included) are measured against the
//! marker's largest step between consecutive valid samples of the file handed to the
//! repair, by the C3D manual's rule for a missing sample (`c3d::is_missing`), as any reader
//! would.
//!
//! The `step_check` binary runs it on a corpus; `tests/step_rule.rs` on the files where a
//! fill once ended above the limit.

const LENGTHS: [usize; 5] = [5, 10, 20, 40, 80];
/// Recorded frames kept on each side of a knocked gap.
const MARGIN: usize = 10;

/// Per point, `(xyz, valid)` over every frame.
type Rows = Vec<(Vec<[f64; 3]>, Vec<bool>)>;

fn rows(c: &c3d::C3d, points: &[usize]) -> Rows {
    let p = c.points();
    points
        .iter()
        .map(|&i| {
            let xyz = p
                .trajectory(i)
                .iter()
                .map(|q| [f64::from(q[0]), f64::from(q[1]), f64::from(q[2])])
                .collect();
            (xyz, p.validity(i))
        })
        .collect()
}

fn dist(a: [f64; 3], b: [f64; 3]) -> f64 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
}

fn max_step(xyz: &[[f64; 3]], valid: &[bool]) -> f64 {
    (1..xyz.len())
        .filter(|&f| valid[f] && valid[f - 1])
        .map(|f| dist(xyz[f], xyz[f - 1]))
        .fold(0.0, f64::max)
}

/// A hole of `len` frames in a run of samples recorded with a residual above 0 (any valid
/// samples where the marker has no such run: files whose residuals are all 0), placed by
/// the marker's index so that markers lose different frames.
fn place(c: &c3d::C3d, point: usize, row: usize, len: usize) -> Option<usize> {
    let p = c.points();
    let res = p.residuals(point);
    let recorded = |strict: bool| -> Vec<bool> {
        (0..p.frames())
            .map(|f| p.is_valid(f, point) && (res[f] > 0.0 || !strict))
            .collect()
    };
    place_in(&recorded(true), row, len).or_else(|| place_in(&recorded(false), row, len))
}

fn place_in(ok: &[bool], row: usize, len: usize) -> Option<usize> {
    let need = len + 2 * MARGIN;
    let mut runs = Vec::new();
    let mut f = 0;
    while f < ok.len() {
        if !ok[f] {
            f += 1;
            continue;
        }
        let a = f;
        while f < ok.len() && ok[f] {
            f += 1;
        }
        if f - a >= need {
            runs.push((a, f - a));
        }
    }
    let &(a, n) = runs.get(row % runs.len().max(1))?;
    Some(a + MARGIN + (row * 7919 + len * 31) % (n - need + 1))
}

/// The filled gaps of `path` checked, the number above 1.5× (each printed) and the largest
/// ratio.
pub fn check(path: &std::path::Path) -> Result<(usize, usize, f64), String> {
    let original = c3d::read_file(path).map_err(|e| e.to_string())?;
    let points = c3dfix::markers::marker_indices(&original);
    let (mut n, mut over, mut worst) = (0, 0, 0.0f64);
    for len in LENGTHS {
        let mut c = original.clone();
        let holes: Vec<(usize, usize)> = points
            .iter()
            .enumerate()
            .filter_map(|(row, &i)| place(&original, i, row, len).map(|a| (row, a)))
            .collect();
        let samples = holes.iter().flat_map(|&(row, a)| {
            let i = points[row];
            (a..a + len).map(move |f| (f, i, [0.0f32; 3], -1.0f32, 0u8))
        });
        c.patch_points(samples).map_err(|e| e.to_string())?;
        let given =
            c3d::read(c.to_bytes().map_err(|e| e.to_string())?).map_err(|e| e.to_string())?;
        let before = rows(&given, &points);
        let mut repaired = given.clone();
        c3dfix::repair(&mut repaired, &c3dfix::RepairOptions::default(), path)
            .map_err(|e| e.to_string())?;
        let out = c3d::read(repaired.to_bytes().map_err(|e| e.to_string())?)
            .map_err(|e| e.to_string())?;
        let after = rows(&out, &points);
        for &(row, a) in &holes {
            let (xyz, valid) = &after[row];
            if !valid[a..a + len].iter().all(|&v| v) {
                continue;
            }
            let limit = max_step(&before[row].0, &before[row].1);
            if limit <= 0.0 {
                continue;
            }
            let step = (a..=a + len)
                .map(|f| dist(xyz[f], xyz[f - 1]))
                .fold(0.0, f64::max);
            let r = step / limit;
            n += 1;
            if r > 1.5 {
                over += 1;
                println!(
                    "  {}: point {} frames {}..{}: step {step:.4} against {limit:.4} ({r:.2}x)",
                    path.file_name().unwrap_or_default().to_string_lossy(),
                    points[row],
                    a,
                    a + len - 1
                );
            }
            worst = worst.max(r);
        }
    }
    Ok((n, over, worst))
}
