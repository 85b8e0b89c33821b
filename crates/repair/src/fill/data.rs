//! The trial's data as the fill methods read it ([`Data`]), the marker being filled
//! ([`Target`]) and the frames to fill ([`Span`]).

use super::outcome::SkipReason;
use crate::gaps::Gap;

/// A pass's store of whole-trial models, kept beside the data they are models of and shared
/// by the pass's gaps. Declared here and implemented by the published PCA's cache
/// (`gloersen::Cache`), so that the data, at the bottom of the fill room, names no method
/// above it.
pub(crate) trait TrialModels: Sync {
    /// `span` of `t` filled by the model trained without `holes` (which hold `t.hole`, if
    /// any), built on first use.
    fn fill(
        &self,
        t: &Target,
        span: Span,
        holes: &[(usize, usize)],
        mm_per_unit: f64,
    ) -> Result<Vec<[f64; 3]>, SkipReason>;
}

/// The trial's data as the fill methods read it.
#[derive(Clone, Copy)]
pub(crate) struct Data<'a> {
    pub xyz: &'a [Vec<[f64; 3]>],
    pub valid: &'a [Vec<bool>],
    pub frames: usize,
    /// Per marker, its largest step between consecutive valid frames
    /// ([`max_steps`](super::max_steps)):
    /// no fill may move the marker faster than its own recorded data does.
    pub max_step: &'a [f64],
    /// One marker's validity read from here instead of `valid` (see
    /// [`fill_gaps`](super::fill_gaps): the target as recorded, among neighbours whose
    /// first-pass fills count as samples).
    pub(super) own: Option<(usize, &'a [bool])>,
    /// The published PCA's whole-trial models of this data, shared by the pass's gaps.
    pub(super) gloersen: Option<&'a dyn TrialModels>,
}

/// The distance between two samples.
pub(crate) fn dist(a: [f64; 3], b: [f64; 3]) -> f64 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
}

impl<'a> Data<'a> {
    pub fn new(xyz: &'a [Vec<[f64; 3]>], valid: &'a [Vec<bool>], max_step: &'a [f64]) -> Self {
        let frames = xyz.first().map_or(0, Vec::len);
        Data {
            xyz,
            valid,
            frames,
            max_step,
            own: None,
            gloersen: None,
        }
    }

    /// The same data with the published PCA's models kept in `cache` (which must not
    /// outlive this data: the models are of it).
    pub(super) fn with_gloersen(self, cache: &'a dyn TrialModels) -> Self {
        Data {
            gloersen: Some(cache),
            ..self
        }
    }

    /// The same data with marker `m`'s validity taken from `own`.
    pub(super) fn with_own(self, m: usize, own: &'a [bool]) -> Self {
        Data {
            own: Some((m, own)),
            ..self
        }
    }

    #[inline]
    pub(super) fn row(&self, m: usize) -> &'a [bool] {
        match self.own {
            Some((o, v)) if o == m => v,
            _ => &self.valid[m],
        }
    }

    #[inline]
    pub fn ok(&self, m: usize, f: usize) -> bool {
        self.row(m)[f]
    }

    #[inline]
    pub fn at(&self, m: usize, f: usize) -> [f64; 3] {
        self.xyz[m][f]
    }

    /// Whether marker `m` is valid on every frame of `lo..=hi`.
    pub fn ok_through(&self, m: usize, lo: usize, hi: usize) -> bool {
        self.row(m)[lo..=hi].iter().all(|&v| v)
    }
}

/// The marker being filled, possibly with an extra artificial hole (frames treated as
/// invalid) used when `auto` scores methods on data whose truth is known.
#[derive(Clone, Copy)]
pub(crate) struct Target<'a> {
    pub m: usize,
    pub data: Data<'a>,
    pub hole: Option<(usize, usize)>,
}

impl Target<'_> {
    #[inline]
    pub fn ok(&self, f: usize) -> bool {
        self.data.ok(self.m, f) && !self.hole.is_some_and(|(a, b)| f >= a && f <= b)
    }

    #[inline]
    pub fn at(&self, f: usize) -> [f64; 3] {
        self.data.at(self.m, f)
    }

    /// Up to `k` valid frames before `first`, nearest first.
    pub fn before(&self, first: usize, k: usize) -> Vec<usize> {
        (0..first).rev().filter(|&f| self.ok(f)).take(k).collect()
    }

    /// Up to `k` valid frames after `last`, nearest first.
    pub fn after(&self, last: usize, k: usize) -> Vec<usize> {
        (last + 1..self.data.frames)
            .filter(|&f| self.ok(f))
            .take(k)
            .collect()
    }
}

/// The frames to fill, inclusive, and the anchors just outside (valid target samples).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Span {
    pub first: usize,
    pub last: usize,
    pub before: Option<usize>,
    pub after: Option<usize>,
}

impl Span {
    pub fn new(first: usize, last: usize, frames: usize) -> Span {
        Span {
            first,
            last,
            before: first.checked_sub(1),
            after: (last + 1 < frames).then_some(last + 1),
        }
    }

    pub fn of(gap: &Gap, frames: usize) -> Span {
        Span::new(gap.first, gap.last, frames)
    }

    pub fn len(&self) -> usize {
        self.last - self.first + 1
    }

    /// First and last frame including the anchors that exist.
    pub fn outer(&self) -> (usize, usize) {
        (
            self.before.unwrap_or(self.first),
            self.after.unwrap_or(self.last),
        )
    }
}
