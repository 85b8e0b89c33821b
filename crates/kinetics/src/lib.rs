//! Force-platform maths on plain arrays, as the C3D manual defines it: the plate's frame from
//! its corners ([`frame`]), its wrench about the centre of the working surface from the
//! analog channels of plate types 1–4 ([`wrench`]), the centre of pressure and free moment
//! ([`cop`]), the lab-frame outputs of a whole plate ([`plate`]), the intervals of contact
//! ([`contact`]) and the plate's unloaded level ([`baseline`]). A plate's load is its push
//! (−Fz of its own frame, see [`PlateOutput::push`]), never |Fz|.
//!
//! Like `repair`, this crate knows nothing of C3D bytes: the format crate reads
//! FORCE_PLATFORM, the `c3dfix` library scales the analog channels and joins the two.
//!
//! Conventions, one for every output: vectors are `[x, y, z]` in the lab frame (the frame of
//! the points and of FORCE_PLATFORM:CORNERS); forces in N; positions in the points' unit;
//! moments in N × that unit. The force is the one the plate measures (the load applied to
//! it), rotated into the lab frame — as ezc3d and BTK give it.

pub mod baseline;
pub mod contact;
pub mod cop;
pub mod frame;
pub mod plate;
pub mod wrench;

pub use contact::contacts;
pub use frame::PlateFrame;
pub use plate::{compute, PlateOutput, PlateSpec};
pub use wrench::PlateKind;

/// Why a plate cannot be computed. [`Error::parameter`] names the FORCE_PLATFORM parameter
/// at fault and the message says what is wrong with its value, so that the caller, who
/// knows the plate, can say "plate 2, CORNERS: enclose no area" without taking a
/// parameter name back out of the text.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum Error {
    #[error("{0} is not supported (types 1, 2, 3 and 4 are)")]
    UnsupportedType(i32),
    #[error("lists {got} channels; type {kind} needs {need}")]
    Channels { kind: i32, need: usize, got: usize },
    #[error("enclose no area (the corners coincide or lie on a line)")]
    ZeroArea,
    #[error("describe no plate (opposite sides differ, or the corners are not in one plane, by over 5 % of a side)")]
    NotAPlate,
    #[error("are not finite")]
    CornersNotFinite,
    #[error("is missing; a type-4 plate needs its 6 x 6 matrix")]
    NoCalMatrix,
    #[error("has {0} values; 36 (6 x 6) expected")]
    CalMatrixSize(usize),
    #[error("is not finite")]
    OriginNotFinite,
    #[error("the plate's channels have different lengths")]
    Lengths,
}

impl Error {
    /// The FORCE_PLATFORM parameter (without its group) whose value is at fault.
    pub fn parameter(&self) -> &'static str {
        match self {
            Error::UnsupportedType(_) => "TYPE",
            Error::Channels { .. } | Error::Lengths => "CHANNEL",
            Error::ZeroArea | Error::NotAPlate | Error::CornersNotFinite => "CORNERS",
            Error::NoCalMatrix | Error::CalMatrixSize(_) => "CAL_MATRIX",
            Error::OriginNotFinite => "ORIGIN",
        }
    }
}

pub type Result<T> = std::result::Result<T, Error>;

pub(crate) type V3 = [f64; 3];

pub(crate) fn cross(a: V3, b: V3) -> V3 {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

pub(crate) fn sub(a: V3, b: V3) -> V3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

pub(crate) fn add(a: V3, b: V3) -> V3 {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

pub(crate) fn scale(a: V3, s: f64) -> V3 {
    [a[0] * s, a[1] * s, a[2] * s]
}

pub(crate) fn norm(a: V3) -> f64 {
    (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt()
}
