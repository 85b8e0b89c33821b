//! The library's errors in the command line's words: the kinds that name a setting
//! ([`c3dfix::Setting`]) or say how to ask for something are said here with this tool's
//! flags, so the library never has to know them (the Python package says its keywords).

use c3dfix::{Conflict, Error, Setting};

/// The flag that gives a setting.
pub fn flag(s: Setting) -> &'static str {
    match s {
        Setting::Output => "-o OUT",
        Setting::InPlace => "--in-place",
        Setting::Backup => "--backup",
        Setting::Force => "--force",
        Setting::Group => "--group",
        Setting::GapLengths => "--gap-lengths",
        Setting::GapsPerLength => "--gaps-per-length",
        Setting::Threshold => "--threshold",
        Setting::EventSource => "--from",
        Setting::Swaps => "--swaps",
        Setting::Reclaim => "--reclaim",
        Setting::Axes => "--axes",
        Setting::Side => "--side",
        Setting::Jobs => "--jobs",
        // A setting added to the library before it is given a flag here: its plain name.
        other => other.name(),
    }
}

/// A marker name the person gave (`--markers`) that the trial or the grammar refuses, said
/// with the flag; any other error of the detector as it says it.
pub fn markers_phrase(e: &gait::Error) -> String {
    match e {
        gait::Error::UnknownMarker { role, name } => {
            format!("--markers {role}={name}: the trial has no marker of that name")
        }
        gait::Error::BadMarkerSpec(item) => format!(
            "--markers {item}: expected ROLE=NAME with ROLE one of lheel, rheel, ltoe, rtoe, pelvis (NAME+NAME… for a mean)"
        ),
        other => other.to_string(),
    }
}

/// `e` as the command line says it.
pub fn phrase(e: &Error) -> String {
    match e {
        Error::Exists { path } => format!("{} exists (use --force to overwrite)", path.display()),
        Error::OwnInput { output, input } => format!(
            "the output {} is the input file {}: use --in-place (with --backup to keep the original) to replace it",
            output.display(),
            input.display()
        ),
        Error::Conflict(Conflict::BackupWithoutInPlace) => "--backup goes with --in-place".into(),
        Error::Conflict(Conflict::OutputAndInPlace) => {
            "give either -o OUT or --in-place, not both".into()
        }
        Error::Conflict(Conflict::NoDestination) => "give -o OUT or --in-place".into(),
        Error::Conflict(Conflict::FolderAndInPlace) => {
            "give either --out-dir DIR or --in-place, not both".into()
        }
        Error::Conflict(Conflict::NoFolderOrInPlace) => "give --out-dir DIR or --in-place".into(),
        Error::Conflict(Conflict::AxesFormat) => {
            "--axes applies to --format trc, mot and opensim only".into()
        }
        Error::Conflict(Conflict::PairNeedsFolder) => "--format opensim needs --out-dir DIR".into(),
        Error::Conflict(Conflict::FolderForPair) => {
            "--out-dir applies to --format opensim only (use -o)".into()
        }
        Error::NoUp { path } => format!(
            "{}: neither force plates nor markers tell which way is up: give the axes (e.g. --axes x,z,-y)",
            path.display()
        ),
        Error::OutOfRange {
            setting,
            value,
            limits,
        } => format!("{} {value}: {limits}", flag(*setting)),
        Error::Invalid {
            setting,
            value,
            why,
        } => format!("{} {value}: {why}", flag(*setting)),
        Error::NoFileEvents { path } => format!(
            "{}: no Foot Strike or Foot Off events of the Left or Right context in the EVENT group (add them with `c3dfix events -o`, or use --detect)",
            path.display()
        ),
        Error::Markers {
            path,
            source: source @ (gait::Error::UnknownMarker { .. } | gait::Error::BadMarkerSpec(_)),
            for_plates,
        } => format!(
            "{}: {}{}",
            path.display(),
            markers_phrase(source),
            if *for_plates {
                c3dfix::PLATES_NEED_FEET
            } else {
                ""
            }
        ),
        Error::Markers {
            source: gait::Error::NoMarker { .. },
            ..
        } => format!("{e} (name it with --markers)"),
        Error::Markers {
            source: gait::Error::NoFootMarkers { markers },
            ..
        } if *markers > 0 => format!("{e}; feet marked under other names are named with --markers"),
        other => other.to_string(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::PathBuf;

    #[test]
    fn kinds_are_said_with_flags() {
        let e = Error::Exists {
            path: PathBuf::from("out.c3d"),
        };
        assert_eq!(phrase(&e), "out.c3d exists (use --force to overwrite)");
        assert!(!e.to_string().contains("--"), "{e}");
        let e = Error::OutOfRange {
            setting: Setting::Group,
            value: "4".into(),
            limits: "must be 1, 2 or 3".into(),
        };
        assert_eq!(phrase(&e), "--group 4: must be 1, 2 or 3");
        assert_eq!(e.to_string(), "group 4: must be 1, 2 or 3");
        let e = Error::Invalid {
            setting: Setting::Axes,
            value: "x,y".into(),
            why: "expected three lab axes".into(),
        };
        assert_eq!(phrase(&e), "--axes x,y: expected three lab axes");
        assert_eq!(e.to_string(), "axes x,y: expected three lab axes");
        assert_eq!(
            phrase(&Error::Conflict(Conflict::NoDestination)),
            "give -o OUT or --in-place"
        );
    }

    #[test]
    fn marker_names_and_missing_events_are_said_with_the_flags_the_library_leaves_out() {
        let e = gait::Error::UnknownMarker {
            role: "lheel".into(),
            name: "NOPE".into(),
        };
        assert_eq!(
            e.to_string(),
            "markers lheel=NOPE: the trial has no marker of that name"
        );
        assert_eq!(
            markers_phrase(&e),
            "--markers lheel=NOPE: the trial has no marker of that name"
        );
        let e = Error::NoFileEvents {
            path: PathBuf::from("walk.c3d"),
        };
        assert!(!e.to_string().contains("--"), "{e}");
        assert_eq!(
            phrase(&e),
            "walk.c3d: no Foot Strike or Foot Off events of the Left or Right context in the EVENT group (add them with `c3dfix events -o`, or use --detect)"
        );
    }
}
