//! Which pieces are settled: a piece that fits is moved only when no rival fits as well.
//!
//! Rivals of a piece are the other pieces that fit (or fit the path with too few links to
//! tell) and share frames with it, either for the same marker (another unlabelled
//! trajectory in its gap) or from the same unlabelled trajectory (its samples in another
//! marker's gap). Costs are compared with a floor of 0.02 tolerances², so that two pieces
//! fitting within the noise are not told apart by it.

use super::finds::Verdict;
use super::finds::{Fit, Move, Piece, ReclaimOptions, Reclaims, Unsettled, Why};

/// Cost floor of the comparison (mean squared residual in tolerances).
const FLOOR: f64 = 0.02;

pub(super) fn decide(scored: &[(Piece, Fit)], opts: &ReclaimOptions) -> Reclaims {
    let live: Vec<&(Piece, Fit)> = scored
        .iter()
        .filter(|(_, f)| f.verdict != Verdict::Off)
        .collect();
    let mut out = Reclaims::default();
    for (i, &&(p, fit)) in live.iter().enumerate() {
        let rivals = live.iter().enumerate().filter(|&(j, (q, _))| {
            j != i && p.overlaps(q) && (q.marker == p.marker || q.source == p.source)
        });
        let c = fit.cost + FLOOR;
        // The rival that comes nearest (lowest cost), and whether any beats this one.
        let mut nearest: Option<(Piece, f64)> = None;
        let mut beaten = false;
        let mut close = false;
        for (_, &(q, qf)) in rivals {
            if fit.verdict == Verdict::FewLinks {
                // A piece that cannot be checked yields to any rival that can.
                beaten |= qf.verdict == Verdict::Fits;
                continue;
            }
            let qc = if qf.verdict == Verdict::Fits {
                qf.cost + FLOOR
            } else {
                // A rival the links cannot check is as good as any: it keeps this one
                // unsettled unless the path tells it apart (it does not: both fit it).
                c
            };
            beaten |= qc * opts.margin < c;
            close |= qc < opts.margin * c;
            if nearest.is_none_or(|(_, nc)| qc < nc) {
                nearest = Some((*q, qc - FLOOR));
            }
        }
        if beaten {
            continue;
        }
        match fit.verdict {
            Verdict::Fits if !close => out.moves.push(Move { piece: p, fit }),
            Verdict::Fits => {
                if let Some((rival, rival_cost)) = nearest {
                    out.unsettled.push(Unsettled {
                        piece: p,
                        why: Why::Ambiguous {
                            rival,
                            rival_cost: rival_cost.max(0.0),
                        },
                        fit,
                    });
                }
            }
            Verdict::FewLinks => out.unsettled.push(Unsettled {
                piece: p,
                why: Why::FewLinks {
                    checked_frames: fit.checked_frames,
                },
                fit,
            }),
            Verdict::Off => {}
        }
    }
    out.moves
        .sort_by_key(|m| (m.piece.marker, m.piece.first, m.piece.source));
    out.unsettled
        .sort_by_key(|u| (u.piece.marker, u.piece.first, u.piece.source));
    out
}
