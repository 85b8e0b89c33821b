//! A gap's plan: the donors chosen for it ([`Donors`]) and the models PCA and the Kalman
//! smoother train on them, each trained on first use. A plan is made once per gap and
//! reused when `auto` scores methods on artificial gaps nearby, so scores describe the fill
//! that will actually be used.

use std::ops::Deref;

use super::data::{Span, Target};
use super::donors::Donors;
use super::options::FillOptions;
use super::{kalman, pca, subspace};

/// Donors chosen for one gap, with the models trained on them.
#[derive(Debug, Clone)]
pub(crate) struct Plan {
    pub donors: Donors,
    /// The training rows PCA and the Kalman smoother share.
    pub subspace: subspace::Shared,
    pub pca_models: pca::Cache,
    pub kalman_models: kalman::Cache,
}

impl Plan {
    /// A plan with no donors (for methods that use none).
    pub fn empty(span: Span) -> Plan {
        Plan::of(Donors::empty(span))
    }

    /// The donors for `span` (see [`Donors::build`]), no model trained yet.
    pub fn build(t: &Target, span: Span, opts: &FillOptions) -> Plan {
        Plan::of(Donors::build(t, span, opts))
    }

    fn of(donors: Donors) -> Plan {
        Plan {
            donors,
            subspace: subspace::Shared::default(),
            pca_models: pca::Cache::default(),
            kalman_models: kalman::Cache::default(),
        }
    }
}

/// A plan reads as its donors (`plan.pca`, `plan.rigid`, …): the methods that only need the
/// donors take [`Donors`], and a plan is passed to them as is.
impl Deref for Plan {
    type Target = Donors;

    fn deref(&self) -> &Donors {
        &self.donors
    }
}
