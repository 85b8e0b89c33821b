//! What kind of fill a candidate is beside its method, shared by the scoring on artificial
//! holes (`holes`) and the choice (`auto`).

/// What kind of fill a candidate is, beside its method.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub(super) struct Kind {
    /// Held to the skeleton.
    pub skel: bool,
    /// A donor method's prediction tied to the samples by a spline through its residuals
    /// (see `anchor`) instead of the line.
    pub smooth: bool,
    /// PCA with the wide model.
    pub wide: bool,
    /// How far the step rule moved the fill (mean distance, data units): 0 for a fill that
    /// needed no slowing. A slowed fill is not its method's prediction, and what the
    /// artificial gaps scored does not vouch for it (see `Diag::slowed`).
    pub moved: f64,
}
