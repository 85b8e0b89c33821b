//! Where the fills' time goes: counters the fill code bumps when profiling is on, so a
//! benchmark can say which candidates, which gap lengths and which models cost what
//! (`crates/cli/benches/price.sh`, `docs/price.md`). Off by default; then every probe is one
//! relaxed atomic load and nothing is timed, so the fills cost what they did without it.
//!
//! The counters are process-wide sums over every thread: the times are thread time spent
//! inside each probe (CPU time when the threads are not starved), so they add up to more
//! than the wall clock when gaps are filled in parallel. The library only gathers; the
//! binary decides whether and where to print ([`take`] and its `Display`).

use std::fmt;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering::Relaxed};
use std::time::Instant;

static ON: AtomicBool = AtomicBool::new(false);

/// Turns the counters on or off (off at start).
pub fn enable(on: bool) {
    ON.store(on, Relaxed);
}

/// Whether the counters are on.
#[inline]
pub fn enabled() -> bool {
    ON.load(Relaxed)
}

/// Timed work: each candidate method, on the real gap and on the artificial gaps, and the
/// steps around them.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Work {
    /// Donor choice for one gap or one artificial gap on another marker ([`Plan::build`]).
    ///
    /// [`Plan::build`]: crate::fill::Plan
    Plan,
    /// Cutting `auto`'s artificial gaps.
    Holes,
    /// A candidate's fill of the real gap, by method.
    Real(Method),
    /// A candidate's fill of an artificial gap, by method.
    Scored(Method),
    /// The skeleton built and applied.
    Skeleton,
    /// The step rule slowing a fill.
    Slowing,
    /// The choice among the candidates (blends and their errors).
    Choose,
}

/// The methods the counters tell apart (`auto`'s wide PCA model apart from the plain one).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Method {
    Poly,
    Spline,
    Rigid,
    Pattern,
    Pca,
    PcaWide,
    Kalman,
    Gloersen,
    Other,
}

const METHODS: [(Method, &str); 9] = [
    (Method::Poly, "lagrange5"),
    (Method::Spline, "spline"),
    (Method::Rigid, "rigid"),
    (Method::Pattern, "pattern"),
    (Method::Pca, "pca"),
    (Method::PcaWide, "pca (wide)"),
    (Method::Kalman, "kalman"),
    (Method::Gloersen, "gloersen"),
    (Method::Other, "other"),
];

impl Method {
    pub(crate) fn of(m: crate::FillMethod) -> Method {
        use crate::FillMethod as F;
        match m {
            F::Lagrange5 | F::Lagrange2 | F::Linear => Method::Poly,
            F::Spline => Method::Spline,
            F::Rigid => Method::Rigid,
            F::Pattern => Method::Pattern,
            F::Pca => Method::Pca,
            F::Kalman => Method::Kalman,
            F::Gloersen => Method::Gloersen,
            _ => Method::Other,
        }
    }

    fn index(self) -> usize {
        METHODS.iter().position(|(m, _)| *m == self).unwrap_or(0)
    }
}

const N_METHODS: usize = METHODS.len();
/// Plan, Holes, Real × methods, Scored × methods, Skeleton, Slowing, Choose.
const N_WORK: usize = 2 + 2 * N_METHODS + 3;

impl Work {
    fn index(self) -> usize {
        match self {
            Work::Plan => 0,
            Work::Holes => 1,
            Work::Real(m) => 2 + m.index(),
            Work::Scored(m) => 2 + N_METHODS + m.index(),
            Work::Skeleton => 2 + 2 * N_METHODS,
            Work::Slowing => 3 + 2 * N_METHODS,
            Work::Choose => 4 + 2 * N_METHODS,
        }
    }

    fn name(i: usize) -> String {
        match i {
            0 => "plan (donor choice)".into(),
            1 => "artificial gaps cut".into(),
            i if i < 2 + N_METHODS => format!("{} on the real gap", METHODS[i - 2].1),
            i if i < 2 + 2 * N_METHODS => {
                format!("{} on artificial gaps", METHODS[i - 2 - N_METHODS].1)
            }
            i if i == 2 + 2 * N_METHODS => "skeleton".into(),
            i if i == 3 + 2 * N_METHODS => "step rule (slowing)".into(),
            _ => "choice and blends".into(),
        }
    }
}

/// Events counted: models built, artificial gaps cut and scored.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Count {
    /// Plans built (donor choices).
    Plan,
    /// `auto`'s wide PCA plans built.
    WidePlan,
    /// PCA training sums gathered over a window.
    PcaSums,
    /// PCA models trained (one eigen-decomposition each).
    PcaModel,
    /// Kalman smoother models trained.
    KalmanModel,
    /// Skeletons built from the recorded distances.
    Skeleton,
    /// Gløersen & Federolf fills.
    Gloersen,
    /// Gløersen & Federolf whole-trial models built (two eigen-decompositions each).
    GloersenModel,
    /// Artificial gaps cut.
    Holes,
    /// Artificial gaps on which every candidate filled (scored).
    Scored,
}

const COUNTS: [(Count, &str); 10] = [
    (Count::Plan, "plans built"),
    (Count::WidePlan, "wide PCA plans built"),
    (Count::PcaSums, "PCA training sums gathered"),
    (Count::PcaModel, "PCA models trained"),
    (Count::KalmanModel, "Kalman models trained"),
    (Count::Skeleton, "skeletons built"),
    (Count::Gloersen, "Gløersen fills"),
    (Count::GloersenModel, "Gløersen whole-trial models built"),
    (Count::Holes, "artificial gaps cut"),
    (Count::Scored, "artificial gaps scored"),
];

/// Gap-length buckets (first frame count of each), for the time per gap.
const BUCKETS: [usize; 7] = [1, 5, 10, 20, 40, 80, 200];

#[allow(clippy::declare_interior_mutable_const)]
const ZERO: AtomicU64 = AtomicU64::new(0);
static NANOS: [AtomicU64; N_WORK] = [ZERO; N_WORK];
static CALLS: [AtomicU64; N_WORK] = [ZERO; N_WORK];
static EVENTS: [AtomicU64; COUNTS.len()] = [ZERO; COUNTS.len()];
static GAP_NANOS: [AtomicU64; BUCKETS.len()] = [ZERO; BUCKETS.len()];
static GAPS: [AtomicU64; BUCKETS.len()] = [ZERO; BUCKETS.len()];

/// Times its work from creation to drop (nothing when profiling is off).
pub(crate) struct Timer(Option<(usize, Instant)>);

impl Drop for Timer {
    fn drop(&mut self) {
        if let Some((i, t0)) = self.0 {
            let ns = u64::try_from(t0.elapsed().as_nanos()).unwrap_or(u64::MAX);
            NANOS[i].fetch_add(ns, Relaxed);
            CALLS[i].fetch_add(1, Relaxed);
        }
    }
}

/// Starts timing `w`.
#[inline]
pub(crate) fn time(w: Work) -> Timer {
    Timer(enabled().then(|| (w.index(), Instant::now())))
}

/// Counts one `c`.
#[inline]
pub(crate) fn count(c: Count) {
    count_n(c, 1);
}

/// Counts `n` of `c`.
#[inline]
pub(crate) fn count_n(c: Count, n: usize) {
    if enabled() {
        let i = COUNTS.iter().position(|(k, _)| *k == c).unwrap_or(0);
        EVENTS[i].fetch_add(n as u64, Relaxed);
    }
}

/// Times one gap's whole fill (both passes add to its length's bucket).
pub(crate) struct GapTimer(Option<(usize, Instant)>);

impl Drop for GapTimer {
    fn drop(&mut self) {
        if let Some((i, t0)) = self.0 {
            let ns = u64::try_from(t0.elapsed().as_nanos()).unwrap_or(u64::MAX);
            GAP_NANOS[i].fetch_add(ns, Relaxed);
            GAPS[i].fetch_add(1, Relaxed);
        }
    }
}

/// Starts timing the fill of a gap of `len` frames.
#[inline]
pub(crate) fn gap(len: usize) -> GapTimer {
    GapTimer(enabled().then(|| {
        let i = BUCKETS.iter().rposition(|&b| len >= b).unwrap_or(0);
        (i, Instant::now())
    }))
}

/// What the counters gathered since the last [`take`].
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Profile {
    /// Per kind of work: its name, how often it ran and its seconds (summed over threads).
    pub work: Vec<(String, u64, f64)>,
    /// Per event: its name and count.
    pub counts: Vec<(&'static str, u64)>,
    /// Per gap-length bucket: its range, the gap fills (first and second pass) and seconds.
    pub gaps: Vec<(String, u64, f64)>,
}

/// The counters' values, which are reset (so each trial of a batch can be reported alone).
pub fn take() -> Profile {
    let secs = |a: &AtomicU64| a.swap(0, Relaxed) as f64 * 1e-9;
    let work = (0..N_WORK)
        .map(|i| (Work::name(i), CALLS[i].swap(0, Relaxed), secs(&NANOS[i])))
        .collect();
    let counts = COUNTS
        .iter()
        .zip(&EVENTS)
        .map(|((_, name), a)| (*name, a.swap(0, Relaxed)))
        .collect();
    let gaps = BUCKETS
        .iter()
        .enumerate()
        .map(|(i, &b)| {
            let range = match BUCKETS.get(i + 1) {
                Some(&next) => format!("{b}-{}", next - 1),
                None => format!("{b}+"),
            };
            (range, GAPS[i].swap(0, Relaxed), secs(&GAP_NANOS[i]))
        })
        .collect();
    Profile { work, counts, gaps }
}

impl fmt::Display for Profile {
    /// One line per non-zero counter, `profile <kind> <name>: ...`, for a script to sum.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for (name, calls, s) in self.work.iter().filter(|w| w.1 > 0) {
            writeln!(f, "profile\twork\t{name}\t{calls}\t{s:.6}")?;
        }
        for (name, n) in self.counts.iter().filter(|c| c.1 > 0) {
            writeln!(f, "profile\tcount\t{name}\t{n}")?;
        }
        for (range, n, s) in self.gaps.iter().filter(|g| g.1 > 0) {
            writeln!(f, "profile\tgaps\t{range}\t{n}\t{s:.6}")?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Off, nothing is gathered; on, work, events and gaps land in their own rows, and
    /// `take` resets them. (One test: the counters are process-wide.)
    #[test]
    fn counters_gather_only_when_on_and_reset_on_take() {
        enable(false);
        drop(time(Work::Real(Method::Pca)));
        count(Count::PcaModel);
        drop(gap(12));
        let p = take();
        assert!(p.work.iter().all(|w| w.1 == 0));
        enable(true);
        drop(time(Work::Scored(Method::Kalman)));
        count(Count::PcaModel);
        count(Count::PcaModel);
        drop(gap(12));
        let p = take();
        enable(false);
        let calls = |name: &str| p.work.iter().find(|w| w.0 == name).map(|w| w.1);
        // At least: other tests of this binary may fill while the counters are on.
        assert!(calls("kalman on artificial gaps") >= Some(1));
        let models = p.counts.iter().find(|c| c.0 == "PCA models trained");
        assert!(models.is_some_and(|c| c.1 >= 2));
        assert_eq!(p.gaps[2].0, "10-19");
        assert!(p.gaps[2].1 >= 1);
        assert!(take().counts.iter().all(|c| c.1 == 0));
    }
}
