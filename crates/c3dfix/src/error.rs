//! The library's one error type: each variant says what went wrong and names the file.

use std::path::PathBuf;

/// Everything opening, repairing, evaluating or saving a trial can fail with. Messages name
/// the file (and, for malformed files, the section and byte offset, from [`c3d::Error`]), so
/// they can be shown to a person as they are.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// A file could not be read as C3D, or a trial could not be encoded for writing.
    #[error("{}: {source}", path.display())]
    C3d {
        path: PathBuf,
        #[source]
        source: c3d::Error,
    },
    /// A destination cannot be written (the message names it and says why: its folder is
    /// missing, it is a device, …).
    #[error("{0}")]
    Output(String),
    /// A destination exists and replacing it was not asked for (each front end says how to
    /// ask: `--force`, `force=True`).
    #[error("{} exists and replacing it was not asked for", path.display())]
    Exists { path: PathBuf },
    /// An output would land on the run's own input, which only an in-place run replaces.
    #[error(
        "the output {} is the input file {}: replacing the input is asked for as in-place",
        output.display(),
        input.display()
    )]
    OwnInput { output: PathBuf, input: PathBuf },
    /// Settings that do not go together.
    #[error("{0}")]
    Conflict(Conflict),
    /// A setting's value outside its range: the setting, the value as given and the limits.
    #[error("{} {value}: {limits}", setting.name())]
    OutOfRange {
        setting: Setting,
        value: String,
        /// What is accepted, e.g. "from 1 to 80 frames".
        limits: String,
    },
    /// A setting's value that does not read as one (a malformed specification): the
    /// setting, the value as given and what is wrong with it.
    #[error("{} {value}: {why}", setting.name())]
    Invalid {
        setting: Setting,
        value: String,
        why: String,
    },
    /// Options that make no sense (an unknown method, a malformed filter spec, a marker the
    /// file does not have, a value out of range).
    #[error("{0}")]
    Options(String),
    /// The markers a job needs (heels, toes, pelvis) are not in the trial under any name
    /// known or given; each front end says how to name them.
    #[error("{}: {source}{}", path.display(), if *for_plates { PLATES_NEED_FEET } else { "" })]
    Markers {
        path: PathBuf,
        #[source]
        source: gait::Error,
        /// Events were asked of the plates alone, which need the feet's markers too.
        for_plates: bool,
    },
    /// The trial cannot be processed as asked (no points, too few markers).
    #[error("{}: {what}", path.display())]
    Trial { path: PathBuf, what: String },
    /// A parameter names a unit the output cannot convert (an export to metres from a
    /// POINT:UNITS no table knows).
    #[error("{}: {parameter} {source}", path.display())]
    Unit {
        path: PathBuf,
        /// The parameter that holds the unit, e.g. "POINT:UNITS".
        parameter: String,
        #[source]
        source: c3d::UnknownUnit,
    },
    /// A BVH file could not be read (the message names it).
    #[error(transparent)]
    Bvh(#[from] bvh::ReadError),
    /// A BVH motion cannot be reduced to keys as asked.
    #[error("{}: {source}", path.display())]
    Keyframes {
        path: PathBuf,
        #[source]
        source: bvh::keyframes::KeyframeError,
    },
    /// An output turned to another frame (OpenSim's, Y up) needs the lab's up, and neither
    /// the plates nor the markers tell it: the axes must be given (each front says how).
    #[error("{}: neither force plates nor markers tell which way is up: give the axes (e.g. x,z,-y)", path.display())]
    NoUp { path: PathBuf },
    /// Gait parameters were asked of the file's own events and its EVENT group holds no
    /// Foot Strike or Foot Off of either foot: they are to be detected (each front says how).
    #[error("{}: no Foot Strike or Foot Off events of the Left or Right context in the EVENT group (detect them, or write them into the file first)", path.display())]
    NoFileEvents { path: PathBuf },
    /// The repair library refused the data or configuration.
    #[error("{}: {source}", path.display())]
    Repair {
        path: PathBuf,
        #[source]
        source: repair::RepairError,
    },
}

/// Why plate events need markers, said where the markers are missing.
pub const PLATES_NEED_FEET: &str = " (events from the plates need the foot and pelvis markers as well, to tell which foot stands on a plate)";

/// A setting the command line and the Python package both expose, as an error names it:
/// each front end spells it its own way (`--gap-lengths`, `gap_lengths=`), from
/// [`Setting::name`]'s plain words.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum Setting {
    /// Where the result goes (`-o OUT`, `output`).
    Output,
    /// Replace the input itself.
    InPlace,
    /// Keep the replaced input as `FILE.bak`.
    Backup,
    /// Replace an existing output.
    Force,
    /// Evaluation: which coordinates form one gap (1, 2 or 3 markers).
    Group,
    /// Evaluation: the artificial gaps' lengths.
    GapLengths,
    /// Evaluation: artificial gaps per length.
    GapsPerLength,
    /// Force plates: the push below which the COP is undefined.
    Threshold,
    /// Events: where they are detected from.
    EventSource,
    /// Repair: what is done with label swaps and jumps.
    Swaps,
    /// Repair: what is done with unlabelled samples that are a marker's.
    Reclaim,
    /// Exports: the rotation from the lab's axes to the output's.
    Axes,
    /// Cycles: the feet whose cycles are cut.
    Side,
    /// Runs over many files: trials done at once.
    Jobs,
}

impl Setting {
    /// The setting in plain words, as the library's own messages name it.
    pub fn name(self) -> &'static str {
        match self {
            Setting::Output => "output",
            Setting::InPlace => "in-place",
            Setting::Backup => "backup",
            Setting::Force => "force",
            Setting::Group => "group",
            Setting::GapLengths => "gap lengths",
            Setting::GapsPerLength => "gaps per length",
            Setting::Threshold => "threshold",
            Setting::EventSource => "event source",
            Setting::Swaps => "swaps",
            Setting::Reclaim => "reclaim",
            Setting::Axes => "axes",
            Setting::Side => "side",
            Setting::Jobs => "jobs",
        }
    }
}

/// Destination settings that do not go together.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum Conflict {
    #[error("backup goes with in-place")]
    BackupWithoutInPlace,
    #[error("give either an output file or in-place, not both")]
    OutputAndInPlace,
    #[error("give an output file or in-place")]
    NoDestination,
    /// A run over many files given both an output folder and in-place.
    #[error("give either an output folder or in-place, not both")]
    FolderAndInPlace,
    /// A run over many files given neither an output folder nor in-place.
    #[error("give an output folder or in-place")]
    NoFolderOrInPlace,
    /// An axis rotation for an export format that has no frame to turn.
    #[error("axes apply to the trc, mot and opensim formats only")]
    AxesFormat,
    /// The OpenSim pair given no folder to go into.
    #[error("the opensim format writes its two files into a folder")]
    PairNeedsFolder,
    /// A folder given to a format that writes one file.
    #[error("an output folder is for the opensim format only (the others write one file)")]
    FolderForPair,
}

impl From<repair::ParseError> for Error {
    /// A misspelt method, mode or spec is an option error.
    fn from(e: repair::ParseError) -> Self {
        Error::Options(e.to_string())
    }
}

impl Error {
    /// Where a file breaks the C3D format, when that is what went wrong: the file, the
    /// section and the byte offset from the file's start (front ends may show or attach
    /// them; the message already says them).
    pub fn bad_file(&self) -> Option<(&std::path::Path, c3d::Section, u64)> {
        match self {
            Error::C3d {
                path,
                source:
                    c3d::Error::Malformed {
                        section, offset, ..
                    },
            } => Some((path, *section, *offset)),
            _ => None,
        }
    }

    pub(crate) fn options(what: impl Into<String>) -> Self {
        Error::Options(what.into())
    }
}

/// The library's result type.
pub type Result<T> = std::result::Result<T, Error>;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_truncated_file_is_a_bad_file_with_its_section_and_offset() {
        let path = PathBuf::from(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../../sample_c3d/walk_int.c3d"
        ));
        let Ok(bytes) = std::fs::read(&path) else {
            panic!("{} is part of the repository", path.display());
        };
        // The header and the parameter section's first block only: the parameters run on.
        let source = match c3d::read(bytes[..1024].to_vec()) {
            Err(e) => e,
            Ok(_) => panic!("a file cut inside its parameters must not read"),
        };
        let e = Error::C3d {
            path: path.clone(),
            source,
        };
        let (p, section, offset) = e.bad_file().expect("a malformed file");
        assert_eq!(p, path);
        assert!((512..=1024).contains(&offset), "offset {offset}");
        assert!(
            e.to_string()
                .contains(&format!("{section} at byte {offset}")),
            "{e}"
        );
        assert!(Error::Exists { path }.bad_file().is_none());
    }
}
