//! The C3D file format: bytes ⇄ model, losslessly.
//!
//! Read with [`read_file`] or [`read`]; the result keeps the bytes it came from, and
//! [`C3d::to_bytes`] gives them back unchanged until something is edited — then only the
//! edited parameter records, header words and data samples get new bytes. Conversion to
//! another processor or number format is [`C3d::convert`].

mod analog;
mod checks;
mod data;
pub mod diff;
mod error;
mod events;
mod file;
mod force_platform;
mod header;
mod memory;
mod model_outputs;
mod parameters;
mod points;
mod processor;
mod read;
mod text;
pub mod units;
mod write;

pub use analog::{Analog, Calibration};
pub use data::{Layout, PointsView};
pub use error::{Error, Result, Section, Warning};
pub use events::Event;
pub use file::{C3d, NumberFormat};
pub use force_platform::{platform_params, PlateParams, PlateProblem, PlatformParams};
pub use header::{Header, HeaderEvent, BLOCK};
pub use model_outputs::{segment_axes, MODEL_OUTPUT_TYPES};
pub use parameters::{Group, Parameter, Parameters, Record, Value};
pub use points::{is_missing, Mark, Points};
pub use processor::Processor;
pub use read::{read, read_file, read_file_mapped};
pub use units::{length_mm, mm_per_unit, UnknownUnit};
