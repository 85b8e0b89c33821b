//! Text exports of a trial: TRC (markers, Motion Analysis' format that OpenSim reads), MOT
//! (the plates' ground reaction as OpenSim's ExternalLoads read it), CSV and JSON; and
//! [`opensim`], the pair of files OpenSim needs on one time base in its Y-up frame.
//!
//! Every writer speaks the file's own frame numbers ([`c3d::C3d::frame_number`]) and its one
//! time base ([`c3d::C3d::frame_time`], [`c3d::C3d::analog_time`]), and by default leaves
//! model outputs (Plug-in Gait's angles, forces, moments, powers stored as points) out of
//! marker tables: they are no positions ([`crate::markers`]).

pub(crate) mod csv;
mod job;
mod json;
mod mot;
mod opensim;
mod trc;

pub use csv::{analog_csv, parameter_rows, points_csv, PARAMETERS_HEADER};
pub use job::{analog_csv_path, export, ExportDestination, ExportFormat, ExportOptions, Exported};
pub use json::json;
pub use mot::mot;
pub use opensim::{opensim, OpenSimExport, OpenSimOptions};
pub use trc::{trc, Trc};

use crate::error::Result;

/// Which points a marker table holds.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub enum Points {
    /// The markers: every point that is not a model output (the default).
    #[default]
    Markers,
    /// Every point, model outputs too.
    All,
    /// These labels, in this order (an unknown label is an error naming the file's labels).
    Named(Vec<String>),
}

impl Points {
    /// The point indices this selection picks in `c`.
    pub fn indices(&self, c: &c3d::C3d) -> Result<Vec<usize>> {
        match self {
            Points::Markers => Ok(crate::markers::marker_indices(c)),
            Points::All => Ok((0..c.point_count()).collect()),
            Points::Named(names) => crate::markers::select(c, names),
        }
    }
}

/// A label for a TRC or MOT header, where tabs separate fields and line breaks separate rows:
/// those characters become spaces. Also whether anything was replaced.
pub fn header_label(l: &str) -> (String, bool) {
    let clean: String = l
        .chars()
        .map(|ch| {
            if matches!(ch, '\t' | '\n' | '\r') {
                ' '
            } else {
                ch
            }
        })
        .collect();
    let changed = clean != l;
    (clean, changed)
}
