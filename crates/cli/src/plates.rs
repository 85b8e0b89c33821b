//! Force plates as the outputs other than `forces` and `export` show them (`info`,
//! `plot --forces`, the viewer): the plates computed with the default options. The lab's
//! vertical and `--axes` are the library's ([`c3dfix::axes`]).

use anyhow::Result;
use c3dfix::{ForceOptions, ForcePlatforms};

/// Every plate of `c` with the default options (10 N threshold, no baseline, no filter).
pub fn compute(c: &c3d::C3d) -> Result<ForcePlatforms> {
    Ok(c3dfix::force_platforms(c, &ForceOptions::default())?)
}

/// The analog sample shown for each point frame: the first of the frame's samples, as the
/// file interleaves them (ANALOG:RATE = samples per frame × POINT:RATE), or `None` past the
/// analog data's end.
pub fn frame_sample(fp: &ForcePlatforms, frame: usize, samples: usize) -> Option<usize> {
    let i = frame * fp.samples_per_frame.max(1);
    (i < samples).then_some(i)
}
