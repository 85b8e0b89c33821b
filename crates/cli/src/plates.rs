//! Force plates as the outputs other than `forces` show them (`info`, the OpenSim MOT export,
//! `plot --forces`, the viewer): the plates computed with the default options, the lab's
//! vertical axis read from the plates themselves, and `--axes`, the proper rotation that
//! turns the lab's axes into another program's.

use anyhow::{bail, Result};
use c3dfix::{ForceOptions, ForcePlatforms, Platform};

/// Every plate of `c` with the default options (10 N push threshold, unloaded level
/// removed, no filter).
pub fn compute(c: &c3d::C3d) -> Result<ForcePlatforms> {
    compute_with(c, &ForceOptions::default())
}

/// Every plate of `c` with the options a person gave ([`PlateArgs::options`]).
pub fn compute_with(c: &c3d::C3d, opts: &ForceOptions) -> Result<ForcePlatforms> {
    Ok(c3dfix::force_platforms(c, opts)?)
}

/// The force-plate options, one struct for every command that computes plates (`forces`,
/// `plot --forces`; flattened into each command's arguments), mapping onto
/// [`c3dfix::ForceOptions`].
#[derive(clap::Args, Debug, Clone, Default, PartialEq)]
pub struct PlateArgs {
    /// The push in N (how hard a foot presses the plate down; a pull is never a load) below
    /// which the COP and free moment are undefined, and which bounds the contact intervals
    /// [default: 10].
    #[arg(long, value_name = "N")]
    pub threshold: Option<f64>,
    /// Keep each plate's raw values: do not remove its unloaded level (by default each
    /// channel's mean over FORCE_PLATFORM:ZERO's frames, or over the plate's quietest low
    /// stretch, is subtracted).
    #[arg(long)]
    pub no_zero_baseline: bool,
    /// Remove each plate's unloaded level: the default, accepted for old command lines.
    #[arg(long, hide = true, conflicts_with = "no_zero_baseline")]
    pub zero_baseline: bool,
    /// Zero-phase low-pass filter of the plates' channels: butterworth:ORDER:CUTOFF_HZ or
    /// cheby2:ORDER:CUTOFF_HZ:ATTEN_DB (as for markers).
    #[arg(long, value_name = "SPEC")]
    pub lowpass: Option<String>,
}

impl PlateArgs {
    pub fn options(&self) -> ForceOptions {
        ForceOptions {
            threshold: self
                .threshold
                .unwrap_or(c3dfix::platforms::DEFAULT_THRESHOLD_N),
            zero_baseline: !self.no_zero_baseline,
            lowpass: self.lowpass.clone(),
        }
    }

    /// Whether any option was given (for commands where they apply to one mode only).
    pub fn given(&self) -> bool {
        *self != PlateArgs::default()
    }
}

/// The lab axis (0 x, 1 y, 2 z) the plate's working surface faces: the largest component of
/// the normal of its corners' plane. A plate lies in the floor, so this is the lab's
/// vertical whichever convention the lab used, with no guess from the markers.
pub fn vertical_axis(p: &Platform) -> usize {
    let c = &p.corners;
    let d1 = [c[0][0] - c[2][0], c[0][1] - c[2][1], c[0][2] - c[2][2]];
    let d2 = [c[1][0] - c[3][0], c[1][1] - c[3][1], c[1][2] - c[3][2]];
    let n = [
        (d1[1] * d2[2] - d1[2] * d2[1]).abs(),
        (d1[2] * d2[0] - d1[0] * d2[2]).abs(),
        (d1[0] * d2[1] - d1[1] * d2[0]).abs(),
    ];
    if n[2] >= n[0] && n[2] >= n[1] {
        2
    } else if n[1] >= n[0] {
        1
    } else {
        0
    }
}

/// The two horizontal lab axes for a vertical one, in the cyclic order that keeps a top view
/// right-handed (x, y under z; z, x under y; y, z under x).
pub fn horizontal_axes(up: usize) -> [usize; 2] {
    [(up + 1) % 3, (up + 2) % 3]
}

/// Metres per unit of a length unit's name ("mm", "m", "cm", "dm", "in"), or `None`.
pub fn metres_per(unit: &str) -> Option<f64> {
    match unit.trim().to_ascii_lowercase().as_str() {
        "mm" => Some(1e-3),
        "m" => Some(1.0),
        "cm" => Some(1e-2),
        "dm" => Some(1e-1),
        "in" => Some(0.0254),
        _ => None,
    }
}

/// The analog sample shown for each point frame: the first of the frame's samples, as the
/// file interleaves them (ANALOG:RATE = samples per frame × POINT:RATE), or `None` past the
/// analog data's end.
pub fn frame_sample(fp: &ForcePlatforms, frame: usize, samples: usize) -> Option<usize> {
    let i = frame * fp.samples_per_frame.max(1);
    (i < samples).then_some(i)
}

/// A proper rotation of the lab's axes: output axis `k` is `sign × lab[axis]`. Parsed from
/// `--axes`, e.g. `x,z,-y` for OpenSim's Y-up frame from a Z-up lab.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Axes {
    rows: [(usize, f64); 3],
}

impl Default for Axes {
    fn default() -> Self {
        Axes {
            rows: [(0, 1.0), (1, 1.0), (2, 1.0)],
        }
    }
}

impl Axes {
    /// Parse `a,b,c` where each is `x`, `y` or `z` with an optional sign. Only a permutation
    /// with signs and determinant +1 is taken: anything else would mirror the data (a left
    /// foot becomes a right one, moments change sign), which no export should do silently.
    pub fn parse(spec: &str) -> Result<Axes> {
        let hint = "expected three lab axes with signs, a rotation such as x,z,-y (OpenSim's Y-up from a Z-up lab)";
        let parts: Vec<&str> = spec.split(',').map(str::trim).collect();
        if parts.len() != 3 {
            bail!("--axes {spec}: {hint}");
        }
        let mut rows = [(0usize, 1.0f64); 3];
        let mut seen = [false; 3];
        for (k, part) in parts.iter().enumerate() {
            let (sign, name) = match part.strip_prefix('-') {
                Some(rest) => (-1.0, rest),
                None => (1.0, part.strip_prefix('+').unwrap_or(part)),
            };
            let axis = match name.to_ascii_lowercase().as_str() {
                "x" => 0,
                "y" => 1,
                "z" => 2,
                _ => bail!("--axes {spec}: {part:?} is no lab axis; {hint}"),
            };
            if seen[axis] {
                bail!("--axes {spec}: lab axis {name} is used twice; {hint}");
            }
            seen[axis] = true;
            rows[k] = (axis, sign);
        }
        let a = Axes { rows };
        if a.determinant() < 0.0 {
            bail!(
                "--axes {spec}: not a rotation (determinant -1: it mirrors the data, turning left into right); {hint}"
            );
        }
        Ok(a)
    }

    /// +1 for a rotation, −1 for a reflection: the permutation's parity times the signs.
    fn determinant(&self) -> f64 {
        let p = self.rows.map(|r| r.0);
        let inversions = (0..3)
            .flat_map(|i| (i + 1..3).map(move |j| (i, j)))
            .filter(|&(i, j)| p[i] > p[j])
            .count();
        let parity = if inversions % 2 == 0 { 1.0 } else { -1.0 };
        parity * self.rows.iter().map(|r| r.1).product::<f64>()
    }

    pub fn apply(&self, v: [f64; 3]) -> [f64; 3] {
        self.rows.map(|(axis, sign)| sign * v[axis])
    }

    pub fn apply_f32(&self, v: [f32; 3]) -> [f32; 3] {
        self.rows.map(|(axis, sign)| sign as f32 * v[axis])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn axes_take_rotations_and_refuse_reflections() {
        let a = Axes::parse("x,z,-y").unwrap();
        assert_eq!(a.apply([1.0, 2.0, 3.0]), [1.0, 3.0, -2.0]);
        assert_eq!(Axes::parse(" X , Y , +Z ").unwrap(), Axes::default());
        assert_eq!(
            Axes::parse("y,z,x").unwrap().apply([1.0, 2.0, 3.0]),
            [2.0, 3.0, 1.0]
        );
        assert_eq!(
            Axes::parse("-x,-y,z").unwrap().apply([1.0, 2.0, 3.0]),
            [-1.0, -2.0, 3.0]
        );
        for bad in [
            "x,z,y", "x,y,-z", "-x,y,z", "y,x,z", "x,x,z", "x,y", "x,y,w", "",
        ] {
            assert!(Axes::parse(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn horizontal_axes_keep_the_top_view_right_handed() {
        assert_eq!(horizontal_axes(2), [0, 1]);
        assert_eq!(horizontal_axes(1), [2, 0]);
        assert_eq!(horizontal_axes(0), [1, 2]);
    }
}
