//! Reclaiming at less cost with the same result (issue 47 item 4): the links the swap stage
//! learned are the reclaim stage's where its markers sample the same, only the markers with a
//! piece to score have their links learned, and only the pieces near a gap's ends are
//! scored. Pinned on c3d-labs' walkway trials, whose 29–36
//! unlabelled points make some 15 000–50 000 pieces.

use c3dfix::{ReclaimMode, RepairOptions};
use repair::reclaim::{find_reclaims, find_reclaims_sharing, judge, ReclaimOptions, Verdict};
use repair::swaps::{find_swaps_learned, learn_links, LearnedLinks, LinksOnDemand, SwapOptions};

const TRIALS: [&str; 3] = [
    "RehabEngGroup__MOtoNMS__Fast_Walking.c3d",
    "RehabEngGroup__MOtoNMS__Cross_-_Overs_2.c3d",
    "RehabEngGroup__MOtoNMS__Running_1.c3d",
];

/// The labelled markers and the unlabelled points of `c` as trials (mm, as the files are).
fn split(c: &c3d::C3d) -> (repair::Trial, repair::Trial) {
    let s = c3dfix::markers::split_unlabelled(c, &repair::Unlabelled::common());
    let p = c.points();
    let trial = |points: &[usize]| {
        let xyz = points
            .iter()
            .map(|&i| p.trajectory(i).iter().map(|q| q.map(f64::from)).collect())
            .collect();
        let valid = points
            .iter()
            .map(|&i| (0..c.frames()).map(|f| p.is_valid(f, i)).collect())
            .collect();
        repair::Trial::new(c.point_rate() as f64, xyz, valid).unwrap()
    };
    (trial(&s.labelled), trial(&s.unlabelled))
}

fn labs() -> Option<Vec<(String, c3d::C3d)>> {
    let Some(dir) = testkit::c3d_labs() else {
        testkit::skipped("C3D_LABS absent");
        return None;
    };
    Some(
        TRIALS
            .iter()
            .map(|n| (n.to_string(), c3dfix::open(dir.join(n)).unwrap()))
            .collect(),
    )
}

/// `t` with the samples the swap finder leaves out in these files left out: those of
/// residual 0, which the capture software computed (the trials' own gap fills, 48–161
/// samples of each).
fn measured_only(c: &c3d::C3d, t: &repair::Trial) -> repair::Trial {
    let s = c3dfix::markers::split_unlabelled(c, &repair::Unlabelled::common());
    let mut out = t.clone();
    for (row, &i) in s.labelled.iter().enumerate() {
        for (v, r) in out.valid[row].iter_mut().zip(c.points().residuals(i)) {
            *v &= r != 0.0;
        }
    }
    out
}

/// The swap finder's links, handed to the reclaim judging, give the very result it gets
/// learning them itself: whole when the markers sample the same, and when the finder left
/// some samples out (as a repair's does), with only the pairs of the markers whose samples
/// differ learned again. Alone, the judging learns the pairs of the markers it scores a
/// piece of, not all of them.
#[test]
fn links_from_the_swap_finder_give_the_same_reclaims() {
    let Some(trials) = labs() else { return };
    let opts = ReclaimOptions::default();
    for (name, c) in &trials {
        let (m, u) = split(c);
        let pairs = m.markers() * (m.markers() - 1) / 2;
        let own = find_reclaims(&m, &u, 1.0, &opts);
        assert_eq!(own.link_pairs.pairs, pairs, "{name}");
        assert!(
            own.link_pairs.learned > 0 && own.link_pairs.learned <= pairs,
            "{name}: {:?}",
            own.link_pairs
        );
        assert!(
            !own.moves.is_empty() && own.pieces > 10_000,
            "{name}: {}",
            own.pieces
        );
        let same = |r: &repair::reclaim::Reclaims| {
            assert_eq!(
                (&r.moves, &r.unsettled, r.pieces),
                (&own.moves, &own.unsettled, own.pieces),
                "{name}"
            )
        };
        let (_, learned) = find_swaps_learned(&m, &SwapOptions::default()).unwrap();
        let learned = learned.unwrap();
        assert_eq!(learned.links, learn_links(&m, 2.5, 0.5, 8), "{name}");
        let shared = find_reclaims_sharing(&m, &u, 1.0, &opts, Some(&learned));
        assert_eq!(shared.link_pairs.learned, 0, "{name}");
        same(&shared);
        // The finder on the measured samples only: the markers with computed samples differ.
        let swap_view = measured_only(c, &m);
        let (_, learned) = find_swaps_learned(&swap_view, &SwapOptions::default()).unwrap();
        let learned = learned.unwrap();
        let part = find_reclaims_sharing(&m, &u, 1.0, &opts, Some(&learned));
        let relearned = part.link_pairs.learned;
        assert!(
            relearned > 0 && relearned < own.link_pairs.learned,
            "{name}: {relearned} of {:?}",
            own.link_pairs
        );
        same(&part);
        // Each marker's links on demand are learn_links', alone or beside what the
        // finder learned on other samples.
        let all = learn_links(&m, 2.5, 0.5, 8);
        for known in [None, Some(&learned)] {
            let demand = LinksOnDemand::new(&m, (2.5, 0.5, 8), known);
            for (k, links) in all.iter().enumerate() {
                assert_eq!(&demand.of(k), links, "{name}: marker {k}");
            }
        }
        // One sampled sample a millimetre off: the pairs of its marker are learned again.
        let mut other = m.clone();
        let step = m.frames().div_ceil(400);
        let (row, f) = (0..m.markers())
            .find_map(|r| {
                let f = (0..m.frames()).step_by(step).find(|&f| m.valid[r][f])?;
                Some((r, f))
            })
            .unwrap();
        other.xyz[row][f][0] += 1.0;
        let (links, done) = learned.learn_again(&other, 2.5, 0.5, 8);
        assert_eq!(links, learn_links(&other, 2.5, 0.5, 8), "{name}");
        let (again, _) = LearnedLinks::learn(&m, 2.5, 0.5, 8).learn_again(&other, 2.5, 0.5, 8);
        assert_eq!(again, links, "{name}");
        assert!(done.learned >= m.markers() - 1, "{name}");
        // Fewer links kept per marker: the pairs' verdicts hold, the best are kept again.
        let (fewer, done) = learned.learn_again(&m, 2.5, 0.5, 7);
        assert_eq!(fewer, learn_links(&m, 2.5, 0.5, 7), "{name}");
        assert!(done.learned >= relearned, "{name}");
        // Another clustering: everything learned again.
        let (tighter, all) = learned.learn_again(&m, 2.0, 0.5, 8);
        assert_eq!(tighter, learn_links(&m, 2.0, 0.5, 8), "{name}");
        assert_eq!(all.learned, pairs, "{name}");
    }
}

/// Only the pieces near a gap's ends are scored: every piece the full judging finds not off
/// starts or ends within the path's reach of its gap's edge, the count of pieces is the
/// full judging's, and so the settled and unsettled pieces are the full judging's.
#[test]
fn pieces_far_from_a_gap_end_are_off_so_counting_them_is_enough() {
    let Some(trials) = labs() else { return };
    let opts = ReclaimOptions::default();
    for (name, c) in &trials {
        let (m, u) = split(c);
        let all = judge(&m, &u, 1.0, &opts);
        let found = find_reclaims(&m, &u, 1.0, &opts);
        assert_eq!(found.pieces, all.len(), "{name}");
        let live: Vec<_> = all
            .iter()
            .filter(|(_, f)| f.verdict != Verdict::Off)
            .collect();
        let n = m.frames();
        for (p, _) in &live {
            let v = &m.valid[p.marker];
            let near_start = (p.first.saturating_sub(opts.path_frames)..p.first).any(|f| v[f]);
            let near_end = (p.last + 1..(p.last + 1 + opts.path_frames).min(n)).any(|f| v[f]);
            assert!(near_start || near_end, "{name}: {p:?}");
        }
        // Most pieces are far from both ends: what the cut saves.
        assert!(
            live.len() * 10 < all.len(),
            "{name}: {} of {}",
            live.len(),
            all.len()
        );
        for mv in &found.moves {
            assert!(live.iter().any(|(p, f)| *p == mv.piece && *f == mv.fit));
        }
        for un in &found.unsettled {
            assert!(live.iter().any(|(p, f)| *p == un.piece && *f == un.fit));
        }
    }
}

/// In a repair, the reclaim stage takes most of the swap stage's links (it learns again
/// only the pairs of markers with samples the finder left out), and lists what
/// `c3dfix reclaim`, which learns its own, lists.
#[test]
fn a_repair_shares_the_swap_stages_links() {
    let Some(trials) = labs() else { return };
    for (name, c) in &trials {
        let path = std::path::Path::new(name);
        let mut copy = c.clone();
        let done = c3dfix::repair(&mut copy, &RepairOptions::default(), path).unwrap();
        assert_eq!(RepairOptions::default().reclaim, ReclaimMode::Report);
        let shared = done.reclaim.link_pairs;
        let alone = c3dfix::reclaim(c, path, &repair::Unlabelled::common(), false).unwrap();
        assert!(
            shared.learned < alone.link_pairs.learned && alone.link_pairs.pairs == shared.pairs,
            "{name}: {shared:?} {:?}",
            alone.link_pairs
        );
        assert_eq!(
            (&done.reclaim.pieces, done.reclaim.unsettled.len()),
            (&alone.pieces, alone.unsettled.len()),
            "{name}"
        );
        let listed = |r: &c3dfix::Reclaim| -> Vec<_> {
            r.settled
                .iter()
                .map(|b| (b.marker.clone(), b.source.clone(), b.first_frame, b.fit))
                .collect()
        };
        assert_eq!(listed(&done.reclaim), listed(&alone), "{name}");
    }
}
