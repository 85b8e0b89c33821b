//! The page for a C3D file as `c3dfix view` writes it, with everything the file brings
//! (its force plates, its events, the stick figure its labels give): one function, so the
//! command and the Python package write the same bytes for the same file.

use super::{page, sticks};
use crate::marks;
use crate::Result;
use c3d::C3d;
use std::path::Path;

/// The viewer page for the C3D trial `c`, read from `path` and titled `name`. `original`:
/// the file it was repaired from, drawn beside it. `pairs`: the stick figure as marker
/// indices of `c` (`None`: the Plug-in Gait segments found among its labels).
/// `detect_events`: mark the detector's events too, beside the file's own. The plates are
/// computed with the default options when FORCE_PLATFORM names some (a file without them has
/// no analog decoded). `warn` is given each of the plates' warnings (a plate left out, a
/// parameter not used: a sentence naming its plate) as soon as it is known, so a front end
/// says them beside the file's name even when the page then cannot be made.
pub fn file_page(
    c: &C3d,
    path: &Path,
    name: &str,
    original: Option<(&C3d, &str)>,
    pairs: Option<Vec<(usize, usize)>>,
    detect_events: bool,
    warn: &mut dyn FnMut(String),
) -> Result<String> {
    let pairs = pairs.unwrap_or_else(|| sticks::plug_in_gait(&c.point_labels()));
    let params = c.platform_params();
    let plates = if params.plates.is_empty() {
        for p in &params.problems {
            let w = c3dfix::PlateWarning {
                plate: p.plate,
                parameter: p.parameter.clone(),
                message: p.message.clone(),
            };
            warn(w.to_string());
        }
        None
    } else {
        let fp = c3dfix::force_platforms(c, &c3dfix::ForceOptions::default())?;
        for w in &fp.warnings {
            warn(w.to_string());
        }
        Some(fp)
    };
    let mut events = marks::from_file(c);
    if detect_events {
        events.extend(marks::detected(c, path)?);
    }
    page((c, name), original, pairs, plates.as_ref(), events)
}
