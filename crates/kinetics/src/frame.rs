//! The plate's frame in the lab, from FORCE_PLATFORM:CORNERS — the one transform every
//! output goes through.
//!
//! The manual numbers the corners by quadrant of the plate's own x-y plane: 1 at (+x, +y),
//! 2 at (−x, +y), 3 at (−x, −y), 4 at (+x, −y) (c3d.org, FORCE_PLATFORM:CORNERS). So the
//! plate's x axis runs from the mean of corners 2 and 3 to the mean of 1 and 4, its y axis
//! from the mean of 3 and 4 to the mean of 1 and 2, and z = x × y (down into the floor for
//! a plate whose z points down, as most do). The centre of the working surface is the mean
//! of the four corners.

use crate::{add, cross, norm, scale, sub, Error, Result, V3};
use serde::Serialize;

/// Where a plate is and how it is turned.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct PlateFrame {
    /// Columns are the plate's x, y and z axes in lab coordinates: `lab = rotation · plate`.
    pub rotation: [V3; 3],
    /// The centre of the working surface (mean of the corners), lab frame.
    pub centre: V3,
    /// The corners as given.
    pub corners: [V3; 4],
}

impl PlateFrame {
    /// The frame of a plate with these corners; corners that enclose no area (all on one
    /// point or line) have no frame.
    pub fn from_corners(corners: [V3; 4]) -> Result<PlateFrame> {
        if corners.iter().flatten().any(|v| !v.is_finite()) {
            return Err(Error::CornersNotFinite);
        }
        let [c1, c2, c3, c4] = corners;
        let x = sub(add(c1, c4), add(c2, c3));
        let y = sub(add(c1, c2), add(c3, c4));
        let size = norm(x).max(norm(y));
        let z = cross(x, y);
        // The diagonals' cross product is twice the area; relative to the plate's size so
        // that millimetres and metres are judged alike.
        let area2 = norm(cross(sub(c1, c3), sub(c2, c4)));
        if size == 0.0 || norm(z) <= 1e-9 * size * size || area2 <= 1e-9 * size * size {
            return Err(Error::ZeroArea);
        }
        let ex = scale(x, 1.0 / norm(x));
        let ez = scale(z, 1.0 / norm(z));
        let ey = cross(ez, ex);
        let centre = scale(add(add(c1, c2), add(c3, c4)), 0.25);
        // Four numbers that are no plate (a corrupt parameter) must not become a frame: the
        // corners must make a parallelogram (opposite sides equal) and lie in one plane,
        // within 5 % of the longer side — far looser than any surveyed plate, far tighter
        // than garbage.
        let (s12, s43) = (sub(c1, c2), sub(c4, c3));
        let (s14, s23) = (sub(c1, c4), sub(c2, c3));
        let side = norm(s12).max(norm(s14));
        let dot = |a: V3, b: V3| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
        let flat = corners
            .iter()
            .map(|&c| dot(sub(c, centre), ez).abs())
            .fold(0.0, f64::max);
        if norm(sub(s12, s43)) > 0.05 * side
            || norm(sub(s14, s23)) > 0.05 * side
            || flat > 0.05 * side
        {
            return Err(Error::NotAPlate);
        }
        Ok(PlateFrame {
            rotation: [ex, ey, ez],
            centre,
            corners,
        })
    }

    /// A plate-frame vector in lab coordinates.
    #[inline]
    pub fn to_lab(&self, v: V3) -> V3 {
        let [ex, ey, ez] = self.rotation;
        [
            ex[0] * v[0] + ey[0] * v[1] + ez[0] * v[2],
            ex[1] * v[0] + ey[1] * v[1] + ez[1] * v[2],
            ex[2] * v[0] + ey[2] * v[1] + ez[2] * v[2],
        ]
    }

    /// A point given in plate coordinates relative to the centre of the working surface,
    /// in lab coordinates.
    #[inline]
    pub fn point_to_lab(&self, from_centre: V3) -> V3 {
        add(self.centre, self.to_lab(from_centre))
    }

    /// A lab-frame vector in plate coordinates.
    #[inline]
    pub fn to_plate(&self, v: V3) -> V3 {
        let [ex, ey, ez] = self.rotation;
        let dot = |a: V3| a[0] * v[0] + a[1] * v[1] + a[2] * v[2];
        [dot(ex), dot(ey), dot(ez)]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_floor_plate_with_z_down() {
        // A 600 x 400 plate whose x runs along the lab's y and y along the lab's x: z = x × y
        // points down.
        let f = PlateFrame::from_corners([
            [200.0, 300.0, 0.0],
            [200.0, -300.0, 0.0],
            [-200.0, -300.0, 0.0],
            [-200.0, 300.0, 0.0],
        ])
        .expect("frame");
        assert_eq!(f.rotation[0], [0.0, 1.0, 0.0]);
        assert_eq!(f.rotation[1], [1.0, 0.0, 0.0]);
        assert_eq!(f.rotation[2], [0.0, 0.0, -1.0]);
        assert_eq!(f.centre, [0.0, 0.0, 0.0]);
        let v = [1.0, 2.0, 3.0];
        let back = f.to_plate(f.to_lab(v));
        assert!(back.iter().zip(v).all(|(a, b)| (a - b).abs() < 1e-12));
    }

    #[test]
    fn corners_that_are_no_plate_have_no_frame() {
        // A kite (sides unequal) and a folded quadrilateral (one corner 100 mm off the plane
        // of a 500 mm plate).
        let kite = [
            [1.0, 1.0, 0.0],
            [-1.0, 1.0, 0.0],
            [-1.0, -3.0, 0.0],
            [1.0, -1.0, 0.0],
        ];
        assert_eq!(PlateFrame::from_corners(kite), Err(Error::NotAPlate));
        let folded = [
            [250.0, 250.0, 100.0],
            [-250.0, 250.0, 0.0],
            [-250.0, -250.0, 0.0],
            [250.0, -250.0, 0.0],
        ];
        assert_eq!(PlateFrame::from_corners(folded), Err(Error::NotAPlate));
    }

    #[test]
    fn corners_on_a_line_have_no_frame() {
        let c = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [2.0, 0.0, 0.0],
            [3.0, 0.0, 0.0],
        ];
        assert_eq!(PlateFrame::from_corners(c), Err(Error::ZeroArea));
        assert_eq!(
            PlateFrame::from_corners([[0.0; 3]; 4]),
            Err(Error::ZeroArea)
        );
        let mut n = [[0.0; 3]; 4];
        n[1][0] = f64::NAN;
        assert_eq!(PlateFrame::from_corners(n), Err(Error::CornersNotFinite));
    }
}
