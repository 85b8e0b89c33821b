//! The donors `auto`'s fills would choose for a gap, open to the evaluation: what the
//! donors do around and during a gap is evidence the expected-error model may read, and it
//! is measured on the records' gaps before any of it is computed inside `auto`.

use super::super::super::donors::Donors;
use super::super::super::{Data, FillOptions, Span, Target};
use crate::Trial;

/// The donors chosen for one gap, as the fills choose them (`fill::donors`: rigid, pattern
/// and PCA donors, from the markers valid through the gap and its anchors).
#[derive(Debug, Clone, PartialEq)]
pub struct GapDonors {
    /// Rigid donors, the smallest spread of distance to the target first.
    pub rigid: Vec<usize>,
    /// The best-correlated donor (the pattern fill's).
    pub pattern: Option<usize>,
    /// The PCA fill's neighbours, nearest first, with their weights.
    pub pca: Vec<(usize, f64)>,
}

/// The donors of marker `marker`'s gap over frames `first..=last` of `trial`, whose
/// validity masks already hold the gap (and any other gap filled with it): the same choice
/// the fills make with `opts`.
pub fn gap_donors(
    trial: &Trial,
    marker: usize,
    first: usize,
    last: usize,
    opts: &FillOptions,
) -> GapDonors {
    // The choice reads positions and validity only, not the markers' largest steps.
    let steps = vec![0.0; trial.markers()];
    let data = Data::new(&trial.xyz, &trial.valid, &steps);
    let t = Target {
        m: marker,
        data,
        hole: None,
    };
    let d = Donors::build(&t, Span::new(first, last, data.frames), opts);
    GapDonors {
        rigid: d.rigid,
        pattern: d.pattern,
        pca: d.pca,
    }
}
