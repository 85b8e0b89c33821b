//! A whole plate: channels in, lab-frame force, moment, COP and free moment out.

use crate::cop::{cop_and_free_moment, CopCorrection};
use crate::frame::PlateFrame;
use crate::wrench::{Origin, PlateKind, WrenchMaker};
use crate::{Error, Result, V3};

/// What a plate is, as FORCE_PLATFORM describes it. Every length is in one unit, the
/// points' (the manual's rule), and moments in N × that unit.
#[derive(Debug, Clone, PartialEq)]
pub struct PlateSpec<'a> {
    /// FORCE_PLATFORM:TYPE.
    pub kind: i32,
    /// FORCE_PLATFORM:CORNERS, lab frame, position units.
    pub corners: [V3; 4],
    /// FORCE_PLATFORM:ORIGIN as stored (the sign rule is applied here).
    pub origin: V3,
    /// FORCE_PLATFORM:CAL_MATRIX, row-major 6 × 6; used by type 4 only.
    pub cal_matrix: Option<&'a [f64]>,
    /// FORCE_PLATFORM:FPCOPPOLY (Kistler's COP correction); used by type 3 only.
    pub cop_poly: Option<[f64; 12]>,
    /// Millimetres per position unit (Kistler's correction works in mm).
    pub mm_per_unit: f64,
}

/// A plate's outputs, one entry per analog sample, all in the lab frame: `force` in N,
/// `moment` about the centre of the working surface in N × position units, `cop` in
/// position units and `free_moment` (the torque about the COP, along the plate's normal)
/// in N × position units; `cop` and `free_moment` are NaN where the push is below the
/// threshold.
#[derive(Debug, Clone, PartialEq)]
pub struct PlateOutput {
    pub kind: PlateKind,
    pub frame: PlateFrame,
    pub origin: Origin,
    pub force: Vec<V3>,
    pub moment: Vec<V3>,
    pub cop: Vec<V3>,
    pub free_moment: Vec<V3>,
    /// The push: how hard a foot presses the plate into the floor, −Fz of the plate's own
    /// frame (N). What the threshold, the COP's validity and the contact intervals judge.
    ///
    /// Why −Fz, for every type: the manual's plate frame has z pointing down into the floor
    /// (FORCE_PLATFORM:ORIGIN; CORNERS numbered by the quadrants of that frame), and the
    /// channels of types 1–4 carry the force the plate exerts on the body, the reaction,
    /// which points up, out of the floor: a foot's push reads as a negative Fz. Every loaded
    /// plate of the corpora agrees (types 1–4; AMTI, Bertec, Kistler; Vicon, Qualisys,
    /// Motion Analysis, Codamotion writers): stance reads Fz from −200 to −2 800 N with the
    /// plate's z pointing away from the markers, and the COP of those samples lies under
    /// the foot markers. A positive Fz is a pull — an offset or a drift, since no foot pulls
    /// a floor plate up — and is never a contact.
    pub push: Vec<f64>,
    /// Samples where a channel was not finite (their outputs are NaN).
    pub non_finite: usize,
}

/// Compute a plate from its channels (physical units, one slice per channel in the type's
/// order, equal lengths) with a COP threshold in N.
pub fn compute(spec: &PlateSpec, channels: &[&[f64]], threshold: f64) -> Result<PlateOutput> {
    let kind = PlateKind::from_type(spec.kind)?;
    if channels.len() != kind.channels() {
        return Err(Error::Channels {
            kind: spec.kind,
            need: kind.channels(),
            got: channels.len(),
        });
    }
    let n = channels[0].len();
    if channels.iter().any(|c| c.len() != n) {
        return Err(Error::Lengths);
    }
    let frame = PlateFrame::from_corners(spec.corners)?;
    let origin = Origin::from_stored(kind, spec.origin)?;
    let maker = WrenchMaker::new(kind, origin, spec.cal_matrix)?;
    let correction = match (kind, spec.cop_poly) {
        (PlateKind::Type3, Some(poly)) => Some(CopCorrection {
            poly,
            mm_per_unit: spec.mm_per_unit,
        }),
        _ => None,
    };
    let nan = [f64::NAN; 3];
    let mut out = PlateOutput {
        kind,
        frame,
        origin,
        force: Vec::with_capacity(n),
        moment: Vec::with_capacity(n),
        cop: Vec::with_capacity(n),
        free_moment: Vec::with_capacity(n),
        push: Vec::with_capacity(n),
        non_finite: 0,
    };
    let mut ch = vec![0.0; channels.len()];
    for s in 0..n {
        for (v, c) in ch.iter_mut().zip(channels) {
            *v = c[s];
        }
        if ch.iter().any(|v| !v.is_finite()) {
            out.non_finite += 1;
            for v in [
                &mut out.force,
                &mut out.moment,
                &mut out.cop,
                &mut out.free_moment,
            ] {
                v.push(nan);
            }
            out.push.push(f64::NAN);
            continue;
        }
        let w = maker.wrench(&ch);
        out.force.push(frame.to_lab(w.force));
        out.moment.push(frame.to_lab(w.moment));
        out.push.push(-w.force[2]);
        match cop_and_free_moment(w.force, w.moment, threshold, correction.as_ref()) {
            Some((cop, tz)) => {
                out.cop.push(frame.point_to_lab(cop));
                out.free_moment.push(frame.to_lab([0.0, 0.0, tz]));
            }
            None => {
                out.cop.push(nan);
                out.free_moment.push(nan);
            }
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cross;

    /// A type-2 plate in a lab turned about z: a load at a known lab point comes back there,
    /// with the force rotated and the moment about the plate's centre.
    #[test]
    fn a_load_at_a_lab_point() {
        // Plate x along lab y, plate y along lab x, z down; centre at (1000, 500, 0).
        let corners = [
            [1200.0, 800.0, 0.0],
            [1200.0, 200.0, 0.0],
            [800.0, 200.0, 0.0],
            [800.0, 800.0, 0.0],
        ];
        let origin = [0.0, 0.0, -40.0];
        // A subject pushing down at lab (1050, 600, 0): plate coordinates from the centre
        // (100, 50, 0); the channels carry the reaction on the foot, up, which is −z in
        // plate axes.
        let f_plate = [5.0, -8.0, -700.0];
        let p_plate = [100.0, 50.0, -40.0]; // from O
        let tz = 1.5;
        let mo = {
            let m = cross(p_plate, f_plate);
            [m[0], m[1], m[2] + tz]
        };
        let ch: Vec<Vec<f64>> = [f_plate[0], f_plate[1], f_plate[2], mo[0], mo[1], mo[2]]
            .iter()
            .map(|&v| vec![v, 0.0])
            .collect();
        let refs: Vec<&[f64]> = ch.iter().map(|c| c.as_slice()).collect();
        let spec = PlateSpec {
            kind: 2,
            corners,
            origin,
            cal_matrix: None,
            cop_poly: None,
            mm_per_unit: 1.0,
        };
        let out = compute(&spec, &refs, 10.0).expect("plate");
        let close = |a: V3, b: V3| a.iter().zip(b).all(|(x, y)| (x - y).abs() < 1e-9);
        assert!(
            close(out.force[0], [-8.0, 5.0, 700.0]),
            "{:?}",
            out.force[0]
        );
        assert!(close(out.cop[0], [1050.0, 600.0, 0.0]), "{:?}", out.cop[0]);
        assert!(
            close(out.free_moment[0], [0.0, 0.0, -tz]),
            "{:?}",
            out.free_moment[0]
        );
        // Moment about the centre: (COP − centre) × F + free moment, all in the lab.
        let r = [50.0, 100.0, 0.0];
        let m = cross(r, out.force[0]);
        assert!(
            close(out.moment[0], [m[0], m[1], m[2] - tz]),
            "{:?}",
            out.moment[0]
        );
        assert_eq!(out.push[0], 700.0);
        // The unloaded sample has a force (zero) but no COP.
        assert!(out.cop[1][0].is_nan() && out.free_moment[1][2].is_nan());
        assert_eq!(out.force[1], [0.0, 0.0, 0.0]);
    }

    #[test]
    fn refusals_name_what_is_wrong() {
        let spec = PlateSpec {
            kind: 5,
            corners: [[0.0; 3]; 4],
            origin: [0.0; 3],
            cal_matrix: None,
            cop_poly: None,
            mm_per_unit: 1.0,
        };
        let z = [0.0];
        let six: Vec<&[f64]> = vec![&z; 6];
        assert_eq!(compute(&spec, &six, 10.0), Err(Error::UnsupportedType(5)));
        let spec = PlateSpec { kind: 3, ..spec };
        assert!(matches!(
            compute(&spec, &six, 10.0),
            Err(Error::Channels {
                need: 8,
                got: 6,
                ..
            })
        ));
        let spec = PlateSpec { kind: 2, ..spec };
        assert_eq!(compute(&spec, &six, 10.0), Err(Error::ZeroArea));
    }
}
