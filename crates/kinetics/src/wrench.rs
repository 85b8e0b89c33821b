//! The plate's wrench — force and moment about the centre of its working surface, in the
//! plate's own frame — from the analog channels of each plate type the manual defines.
//!
//! Every type is brought to the same pair (F, M_C), so the centre of pressure, the free
//! moment and the lab-frame outputs are computed once for all of them ([`crate::cop`],
//! [`crate::plate`]).
//!
//! The manual's pages (c3d.org, "FORCE_PLATFORM:TYPE", "TYPE-1" … "TYPE-4",
//! "FORCE_PLATFORM:ORIGIN", "FORCE_PLATFORM:CAL_MATRIX"):
//! - Type 1: Fx, Fy, Fz, the COP's x and y in the plate frame, and the free moment Tz.
//! - Type 2: Fx, Fy, Fz, Mx, My, Mz about the plate's origin O (the point where a force
//!   makes no moment). ORIGIN is the vector from O to the centre of the working surface C,
//!   in plate coordinates, so M_C = M_O − ORIGIN × F.
//! - Type 3 (Kistler): fx12, fx34, fy14, fy23, fz1, fz2, fz3, fz4 from four sensors at
//!   (±a, ±b) in quadrants 1–4, in the plane of O; ORIGIN holds a, b and the depth az0 of O
//!   below the surface, so C = (0, 0, az0).
//! - Type 4: the six channels of type 2 multiplied by the 6 × 6 CAL_MATRIX first
//!   (`[CAL_MATRIX] F_measured = F_corrected`).
//!
//! ORIGIN's sign: the plate's z points down and O lies below the surface, so ORIGIN's z is
//! negative (the manual, FORCE_PLATFORM:ORIGIN and TYPE-2). Several writers store the
//! opposite vector, from C to O, with z positive (most Vicon files in the corpora). Such an
//! ORIGIN is turned round — all three components for types 1, 2 and 4, whose ORIGIN is a
//! vector; only az0 for type 3, whose a and b are sensor distances — and reported, never
//! silently used.

use crate::{cross, sub, Error, Result, V3};
use serde::Serialize;

/// The plate types the manual defines and this crate computes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum PlateKind {
    /// Forces, COP and free moment as channels.
    Type1,
    /// Forces and moments about the plate's origin.
    Type2,
    /// Kistler's eight sensor channels.
    Type3,
    /// Type 2's channels through a 6 × 6 calibration matrix.
    Type4,
}

impl PlateKind {
    /// The kind of FORCE_PLATFORM:TYPE `t`; other types (5–7, 11, 12, 21, …) are refused.
    pub fn from_type(t: i32) -> Result<PlateKind> {
        match t {
            1 => Ok(PlateKind::Type1),
            2 => Ok(PlateKind::Type2),
            3 => Ok(PlateKind::Type3),
            4 => Ok(PlateKind::Type4),
            _ => Err(Error::UnsupportedType(t)),
        }
    }

    pub fn number(self) -> i32 {
        match self {
            PlateKind::Type1 => 1,
            PlateKind::Type2 => 2,
            PlateKind::Type3 => 3,
            PlateKind::Type4 => 4,
        }
    }

    /// Analog channels the type needs.
    pub fn channels(self) -> usize {
        match self {
            PlateKind::Type3 => 8,
            _ => 6,
        }
    }
}

/// FORCE_PLATFORM:ORIGIN as used: the vector from the plate's origin to the centre of the
/// working surface in plate coordinates (type 3: a, b and az0), after the sign rule.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Origin {
    pub used: V3,
    /// The stored z was positive and has been turned round.
    pub corrected: bool,
}

impl Origin {
    /// The manual's sign rule applied to a stored ORIGIN (see the module's doc).
    pub fn from_stored(kind: PlateKind, stored: V3) -> Result<Origin> {
        if stored.iter().any(|v| !v.is_finite()) {
            return Err(Error::OriginNotFinite);
        }
        if stored[2] <= 0.0 {
            return Ok(Origin {
                used: stored,
                corrected: false,
            });
        }
        let used = match kind {
            PlateKind::Type3 => [stored[0], stored[1], -stored[2]],
            _ => [-stored[0], -stored[1], -stored[2]],
        };
        Ok(Origin {
            used,
            corrected: true,
        })
    }

    /// The centre of the working surface in plate coordinates, from the plate's origin.
    fn centre(&self, kind: PlateKind) -> V3 {
        match kind {
            PlateKind::Type3 => [0.0, 0.0, self.used[2]],
            _ => self.used,
        }
    }
}

/// Turns one sample of a plate's channels into its wrench about the working surface's
/// centre, plate frame. Built once per plate, applied to every sample.
#[derive(Debug, Clone, PartialEq)]
pub struct WrenchMaker {
    pub kind: PlateKind,
    pub origin: Origin,
    /// Row-major 6 × 6 (type 4 only).
    cal: Option<[f64; 36]>,
}

/// Force (N) and moment about the working surface's centre (N × position units), plate
/// frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Wrench {
    pub force: V3,
    pub moment: V3,
}

impl WrenchMaker {
    /// `cal` is the plate's CAL_MATRIX row-major (needed by type 4, ignored by the others,
    /// as the manual says).
    pub fn new(kind: PlateKind, origin: Origin, cal: Option<&[f64]>) -> Result<WrenchMaker> {
        let cal = match kind {
            PlateKind::Type4 => {
                let m = cal.ok_or(Error::NoCalMatrix)?;
                let a: [f64; 36] = m.try_into().map_err(|_| Error::CalMatrixSize(m.len()))?;
                Some(a)
            }
            _ => None,
        };
        Ok(WrenchMaker { kind, origin, cal })
    }

    /// The wrench of one sample; `ch` holds the type's channels in the manual's order.
    pub fn wrench(&self, ch: &[f64]) -> Wrench {
        let c = self.origin.centre(self.kind);
        match self.kind {
            PlateKind::Type1 => {
                let f = [ch[0], ch[1], ch[2]];
                // The COP relative to the surface's centre: the channels give it from the
                // plate's origin, which ORIGIN's x and y place relative to the centre.
                let r = [ch[3] - c[0], ch[4] - c[1], 0.0];
                let m = cross(r, f);
                Wrench {
                    force: f,
                    moment: [m[0], m[1], m[2] + ch[5]],
                }
            }
            PlateKind::Type2 | PlateKind::Type4 => {
                let mut v = [ch[0], ch[1], ch[2], ch[3], ch[4], ch[5]];
                if let Some(m) = &self.cal {
                    let mut out = [0.0; 6];
                    for (r, o) in out.iter_mut().enumerate() {
                        *o = (0..6).map(|k| m[r * 6 + k] * v[k]).sum();
                    }
                    v = out;
                }
                let f = [v[0], v[1], v[2]];
                let mo = [v[3], v[4], v[5]];
                Wrench {
                    force: f,
                    moment: sub(mo, cross(c, f)),
                }
            }
            PlateKind::Type3 => {
                let [fx12, fx34, fy14, fy23, fz1, fz2, fz3, fz4] =
                    [ch[0], ch[1], ch[2], ch[3], ch[4], ch[5], ch[6], ch[7]];
                let (a, b) = (self.origin.used[0], self.origin.used[1]);
                let f = [fx12 + fx34, fy14 + fy23, fz1 + fz2 + fz3 + fz4];
                // Sensors 1–4 at (a, b), (−a, b), (−a, −b), (a, −b), in O's plane.
                let mo = [
                    b * (fz1 + fz2 - fz3 - fz4),
                    a * (-fz1 + fz2 + fz3 - fz4),
                    b * (-fx12 + fx34) + a * (fy14 - fy23),
                ];
                Wrench {
                    force: f,
                    moment: sub(mo, cross(c, f)),
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: V3, b: V3) -> bool {
        a.iter().zip(b).all(|(x, y)| (x - y).abs() < 1e-9)
    }

    #[test]
    fn origin_sign_rule() {
        let o = Origin::from_stored(PlateKind::Type2, [1.0, -2.0, 40.0]).expect("origin");
        assert_eq!(o.used, [-1.0, 2.0, -40.0]);
        assert!(o.corrected);
        let o = Origin::from_stored(PlateKind::Type3, [120.0, 200.0, 58.0]).expect("origin");
        assert_eq!(o.used, [120.0, 200.0, -58.0]);
        let o = Origin::from_stored(PlateKind::Type4, [0.5, 0.5, -40.0]).expect("origin");
        assert!(!o.corrected);
    }

    /// A point load at a known place on the surface gives the same wrench about the centre
    /// whichever type measured it.
    #[test]
    fn one_load_seen_by_every_type() {
        let h = -40.0; // the surface is 40 mm above O (z down)
        let load = [10.0, -20.0, 700.0];
        let at = [30.0, -50.0]; // from the surface's centre
        let tz = 2.5;
        let m_c = {
            let m = cross([at[0], at[1], 0.0], load);
            [m[0], m[1], m[2] + tz]
        };
        // Type 2: moments about O, with C at (0, 0, h) from O.
        let c = [0.0, 0.0, h];
        let mo = {
            let p = [at[0], at[1], h];
            let m = cross(p, load);
            [m[0], m[1], m[2] + tz]
        };
        let t2 = WrenchMaker::new(
            PlateKind::Type2,
            Origin::from_stored(PlateKind::Type2, c).expect("o"),
            None,
        )
        .expect("maker");
        let w = t2.wrench(&[load[0], load[1], load[2], mo[0], mo[1], mo[2]]);
        assert!(close(w.force, load) && close(w.moment, m_c), "{w:?}");

        // Type 4 with a diagonal matrix that doubles the forces of half-sized channels.
        let mut cal = [0.0; 36];
        for k in 0..6 {
            cal[k * 6 + k] = 2.0;
        }
        let t4 = WrenchMaker::new(
            PlateKind::Type4,
            Origin::from_stored(PlateKind::Type4, c).expect("o"),
            Some(&cal),
        )
        .expect("maker");
        let half: Vec<f64> = [load[0], load[1], load[2], mo[0], mo[1], mo[2]]
            .iter()
            .map(|v| v / 2.0)
            .collect();
        let w = t4.wrench(&half);
        assert!(close(w.force, load) && close(w.moment, m_c), "{w:?}");

        // Type 1: COP and Tz directly.
        let t1 = WrenchMaker::new(
            PlateKind::Type1,
            Origin::from_stored(PlateKind::Type1, [0.0; 3]).expect("o"),
            None,
        )
        .expect("maker");
        let w = t1.wrench(&[load[0], load[1], load[2], at[0], at[1], tz]);
        assert!(close(w.force, load) && close(w.moment, m_c), "{w:?}");

        // Type 3: split the load over four sensors at (±a, ±b) so that their moments about
        // O match, with the horizontal forces on the sensor pairs that share them.
        let (a, b) = (120.0, 200.0);
        // Vertical shares from the moments about O's x and y axes:
        // Mx = b (fz1 + fz2 − fz3 − fz4), My = a (−fz1 + fz2 + fz3 − fz4).
        let mx = mo[0];
        let my = mo[1];
        let s = load[2];
        let p = mx / b; // fz1 + fz2 − fz3 − fz4
        let q = my / a; // −fz1 + fz2 + fz3 − fz4
        let fz1 = (s + p - q) / 4.0;
        let fz3 = (s - p + q) / 4.0;
        let fz2 = (s + p + q) / 4.0;
        let fz4 = (s - p - q) / 4.0;
        // Horizontal forces: Mz = b(−fx12 + fx34) + a(fy14 − fy23).
        let fx12 = load[0] / 2.0 - mo[2] / (2.0 * b);
        let fx34 = load[0] / 2.0 + mo[2] / (2.0 * b);
        let (fy14, fy23) = (load[1] / 2.0, load[1] / 2.0);
        let t3 = WrenchMaker::new(
            PlateKind::Type3,
            Origin::from_stored(PlateKind::Type3, [a, b, h]).expect("o"),
            None,
        )
        .expect("maker");
        let w = t3.wrench(&[fx12, fx34, fy14, fy23, fz1, fz2, fz3, fz4]);
        assert!(close(w.force, load), "{w:?}");
        // The sensors reproduce M_O; moved to C = (0, 0, h) it is the load's moment there.
        assert!(close(w.moment, m_c), "{w:?} {m_c:?}");
    }

    #[test]
    fn type4_needs_its_matrix() {
        let o = Origin::from_stored(PlateKind::Type4, [0.0; 3]).expect("o");
        assert_eq!(
            WrenchMaker::new(PlateKind::Type4, o, None),
            Err(Error::NoCalMatrix)
        );
        assert_eq!(
            WrenchMaker::new(PlateKind::Type4, o, Some(&[1.0; 30])),
            Err(Error::CalMatrixSize(30))
        );
        assert_eq!(PlateKind::from_type(7), Err(Error::UnsupportedType(7)));
    }
}
