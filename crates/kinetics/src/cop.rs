//! The centre of pressure and the free moment, from the wrench about the working surface's
//! centre C (plate frame), and Kistler's correction of the COP.
//!
//! On the surface (z = 0 from C) a load F at the COP (x, y, 0) with a free moment Tz about
//! the plate's normal has, about C, the moment M_C = (x, y, 0) × F + (0, 0, Tz):
//!   M_Cx = y·Fz,  M_Cy = −x·Fz,  M_Cz = x·Fy − y·Fx + Tz,
//! so x = −M_Cy / Fz, y = M_Cx / Fz and Tz = M_Cz − (x·Fy − y·Fx). Where the push (−Fz, see
//! [`crate::plate::PlateOutput::push`]) is small the COP is noise divided by nearly nothing:
//! below the threshold it is undefined (NaN), and so is the free moment about it. A pull is
//! below any threshold: no foot pulls a floor plate up, so the "COP" of a pull is that of an
//! offset or a drift, not of a load.

use crate::V3;

/// Kistler's COP correction (the plate manuals' "COP correction algorithm", carried in C3D
/// files as FORCE_PLATFORM:FPCOPPOLY): with ax, ay the measured COP in mm from the centre,
///   Δax = (P1x·ay⁴ + P2x·ay² + P3x)·ax³ + (P4x·ay⁴ + P5x·ay² + P6x)·ax,
///   Δay = (P1y·ax⁴ + P2y·ax² + P3y)·ay³ + (P4y·ax⁴ + P5y·ax² + P6y)·ay,
/// and the corrected COP is (ax − Δax, ay − Δay). The coefficients are for millimetres.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CopCorrection {
    /// P1x..P6x, then P1y..P6y.
    pub poly: [f64; 12],
    /// Millimetres per position unit (the polynomial works in mm).
    pub mm_per_unit: f64,
}

impl CopCorrection {
    pub fn apply(&self, x: f64, y: f64) -> (f64, f64) {
        let k = self.mm_per_unit;
        let (ax, ay) = (x * k, y * k);
        let p = &self.poly;
        let dx = (p[0] * ay.powi(4) + p[1] * ay * ay + p[2]) * ax.powi(3)
            + (p[3] * ay.powi(4) + p[4] * ay * ay + p[5]) * ax;
        let dy = (p[6] * ax.powi(4) + p[7] * ax * ax + p[8]) * ay.powi(3)
            + (p[9] * ax.powi(4) + p[10] * ax * ax + p[11]) * ay;
        ((ax - dx) / k, (ay - dy) / k)
    }
}

/// The COP (plate frame, from C, z = 0) and the free moment Tz of one sample, or `None`
/// where the push −Fz is below `threshold` or the wrench is not finite.
pub fn cop_and_free_moment(
    force: V3,
    moment_c: V3,
    threshold: f64,
    correction: Option<&CopCorrection>,
) -> Option<(V3, f64)> {
    let fz = force[2];
    let push = -fz;
    if push.is_nan() || push < threshold || force.iter().chain(&moment_c).any(|v| !v.is_finite()) {
        return None;
    }
    let mut x = -moment_c[1] / fz;
    let mut y = moment_c[0] / fz;
    if let Some(c) = correction {
        (x, y) = c.apply(x, y);
    }
    let tz = moment_c[2] - (x * force[1] - y * force[0]);
    Some(([x, y, 0.0], tz))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cross;

    #[test]
    fn cop_of_a_point_load() {
        let f = [15.0, -30.0, -650.0];
        let at = [42.0, -17.0, 0.0];
        let m = cross(at, f);
        let (cop, tz) =
            cop_and_free_moment(f, [m[0], m[1], m[2] + 3.0], 10.0, None).expect("loaded");
        assert!((cop[0] - 42.0).abs() < 1e-12 && (cop[1] + 17.0).abs() < 1e-12);
        assert!((tz - 3.0).abs() < 1e-9);
        assert!(cop_and_free_moment([0.0, 0.0, -9.9], [1.0; 3], 10.0, None).is_none());
        assert!(cop_and_free_moment([0.0, 0.0, f64::NAN], [1.0; 3], 10.0, None).is_none());
        // A pull (Fz positive along the plate's downward z) is no load.
        assert!(cop_and_free_moment([0.0, 0.0, 50.0], [1.0; 3], 10.0, None).is_none());
    }

    #[test]
    fn kistler_correction_in_mm_whatever_the_unit() {
        let mut poly = [0.0; 12];
        poly[5] = -0.0414; // P6x: a pure scale of x
        poly[11] = 0.0516; // P6y
        let mm = CopCorrection {
            poly,
            mm_per_unit: 1.0,
        };
        let (x, y) = mm.apply(100.0, 50.0);
        assert!((x - 104.14).abs() < 1e-9 && (y - (50.0 - 2.58)).abs() < 1e-9);
        let m = CopCorrection {
            poly,
            mm_per_unit: 1000.0,
        };
        let (xm, ym) = m.apply(0.1, 0.05);
        assert!((xm - 0.10414).abs() < 1e-12 && (ym - 0.04742).abs() < 1e-12);
    }
}
