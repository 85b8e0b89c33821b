//! `info` and `view`: the report `c3dfix info --json` prints and the page `c3dfix view`
//! writes, from the same library functions (`c3dfix::info`, `show::view`), so a trial gives
//! the same JSON and the same bytes from Python as from the command.

use pyo3::prelude::*;
use std::path::{Path, PathBuf};

use crate::shared::{file_name, refuse_inputs, show_err, TrialArg};
use crate::{err, lib_err};

/// info(c3d) -> dict
///
/// What the trial holds and what is wrong with it, as `c3dfix info --json` prints it: file
/// (the path as given), bytes, processor, format, header, frames, first_frame, point_rate,
/// duration_s, points, point_units, point_scale, up and up_source (the lab's vertical and
/// what it was read from), analog channels, rate and labels, markers (label, model_output,
/// valid_frames, gaps, longest_gap), origin_samples, groups, header_events, events,
/// force_platforms (with the default options), force_platform_warnings and warnings.
/// c3d is a C3d or the path of a C3D file.
#[pyfunction]
pub fn info(py: Python<'_>, c3d: TrialArg<'_>) -> PyResult<PyObject> {
    let (c, path) = c3d.open(py)?;
    let c: &c3d::C3d = &c;
    // Through the JSON text, as the command prints it: a value tree would widen the f32
    // fields (rates, scales) to f64 and give 60.00328826904297 for the 60.00329 printed.
    let text = py
        .allow_threads(|| serde_json::to_string(&c3dfix::info::describe(c, &path)))
        .map_err(err)?;
    Ok(py.import("json")?.call_method1("loads", (text,))?.unbind())
}

/// view(c3d, path, against=None, sticks=None, detect_events=False, force=False) -> list[str]
///
/// Write the self-contained HTML page that plays the trial in 3D with its force plates and
/// events (what `c3dfix view` writes, byte for byte), atomically. c3d and against are C3d
/// objects or paths of C3D files; against is the original the trial was repaired from, drawn
/// beside it. sticks: the stick figure as [marker, marker] label pairs (default: the Plug-in
/// Gait segments found among the labels). detect_events also marks the events the detector
/// finds. Returns the force plates' warnings (what the command prints on standard error).
/// A path ending in .bvh is a skeleton: its bones come from the hierarchy, against is
/// another BVH file of the same skeleton, and there are no sticks, events or warnings.
#[pyfunction]
#[pyo3(signature = (c3d, path, against=None, sticks=None, detect_events=false, force=false))]
pub fn view(
    py: Python<'_>,
    c3d: TrialArg<'_>,
    path: PathBuf,
    against: Option<TrialArg<'_>>,
    sticks: Option<Vec<(String, String)>>,
    detect_events: bool,
    force: bool,
) -> PyResult<Vec<String>> {
    if let TrialArg::Path(p) = &c3d {
        if is_bvh(p) {
            if sticks.is_some() || detect_events {
                return Err(err(
                    "sticks and detect_events are for C3D trials: a BVH file's bones come from its hierarchy",
                ));
            }
            let original = match against {
                Some(TrialArg::Path(o)) if is_bvh(&o) => Some(o),
                None => None,
                Some(_) => return Err(err("a BVH file is compared with a BVH file (a path)")),
            };
            view_bvh(py, p, original.as_deref(), &path, force)?;
            return Ok(Vec::new());
        }
    }
    let (c, cpath) = c3d.open(py)?;
    let original = against.as_ref().map(|a| a.open(py)).transpose()?;
    refuse_inputs(&path, &cpath, original.as_ref().map(|(_, p)| p.as_path()))?;
    let (c, name): (&c3d::C3d, String) = (&c, file_name(&cpath));
    let original = original.as_ref().map(|(o, p)| (&**o, file_name(p)));
    let pairs = sticks
        .map(|pairs| {
            pairs
                .iter()
                .map(|(a, b)| {
                    let at = |m: &str| show::plot::marker_index(c, m, &name);
                    Ok((at(a)?, at(b)?))
                })
                .collect::<show::Result<Vec<_>>>()
        })
        .transpose()
        .map_err(err)?;
    let mut warnings = Vec::new();
    py.allow_threads(|| {
        let html = show::view::file_page(
            c,
            &cpath,
            &name,
            original.as_ref().map(|(o, n)| (*o, n.as_str())),
            pairs,
            detect_events,
            &mut |w| warnings.push(w),
        )
        .map_err(show_err)?;
        c3dfix::save::write_atomic(&path, html.as_bytes(), force).map_err(lib_err)
    })?;
    Ok(warnings)
}

/// True for a `.bvh` file name (any case), as the command tells skeletons from trials.
fn is_bvh(p: &Path) -> bool {
    p.extension()
        .is_some_and(|e| e.to_string_lossy().eq_ignore_ascii_case("bvh"))
}

/// The page of a BVH skeleton (`c3dfix view FILE.bvh`), with `original` drawn beside it.
fn view_bvh(
    py: Python<'_>,
    file: &Path,
    original: Option<&Path>,
    out: &Path,
    force: bool,
) -> PyResult<()> {
    refuse_inputs(out, file, original)?;
    py.allow_threads(|| {
        let b = bvh::read(file).map_err(err)?;
        let o = original
            .map(|p| bvh::read(p).map(|b| (b, file_name(p))))
            .transpose()
            .map_err(err)?;
        let html = show::view::skeleton::page(
            (&b, &file_name(file)),
            o.as_ref().map(|(b, n)| (b, n.as_str())),
        )
        .map_err(show_err)?;
        c3dfix::save::write_atomic(out, html.as_bytes(), force).map_err(lib_err)
    })
}
