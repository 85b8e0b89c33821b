//! Which of a file's own events are gait events, as labs write them: Nexus' `Foot Strike` /
//! `Foot Off` in the `Left` / `Right` context (any case, numbered `Foot Strike1` by some
//! exports), and the codes that carry their side in the label — `LHS`/`RHS` (heel strike),
//! `LTO`/`RTO` (toe off), `LFS`/`LFO`, `LIC` (initial contact), `LON`/`LOFF` — in the
//! `General` or an empty context (Qualisys, c3d-labs' s2mLab), or in the context with an
//! empty label (Motion Analysis' Walk1). A generic `Event`, `Start` or `Take-Off` is no gait
//! event. One reading for every command (`info`, `gait`, `cycles`, the session
//! calibration); the file's events are never renamed: a rewrite keeps them as they are.

use gait::params::TimedEvent;
use gait::{Kind, Side};

/// The file's own gait events (their foot, kind and time in seconds on the EVENT group's
/// base), in the group's order: the one reading of a file's events into feet and kinds
/// (see [`gait_event`]) that every command uses; its other events are left out.
pub fn file_gait_events(c: &c3d::C3d) -> Vec<TimedEvent> {
    c.events()
        .iter()
        .filter_map(|e| {
            let (side, kind) = gait_event(&e.context, &e.label)?;
            Some(TimedEvent {
                side,
                kind,
                time: e.time,
            })
        })
        .collect()
}

/// The side and kind of one EVENT entry (`context`, `label`), if it is a gait event.
pub fn gait_event(context: &str, label: &str) -> Option<(Side, Kind)> {
    let (c, l) = (context.trim(), label.trim());
    match side_word(c) {
        Some(side) => {
            if let Some(kind) = kind_words(l) {
                return Some((side, kind));
            }
            // A sided code under a sided context must agree with it.
            coded(l).filter(|(s, _)| *s == side)
        }
        None if c.is_empty() || c.eq_ignore_ascii_case("general") => coded(l),
        None if l.is_empty() => coded(c),
        None => None,
    }
}

/// What a lab's own gait label (`LHS` in General, `Foot Strike1`) is read as, for showing
/// beside it: `None` for Nexus' own words (`Foot Strike`, `Foot Off`, any case), which say
/// it themselves, and for an entry that is no gait event.
pub fn read_as(context: &str, label: &str) -> Option<(Side, Kind)> {
    let l = label.trim();
    let nexus = [Kind::FootStrike, Kind::FootOff]
        .iter()
        .any(|k| l.eq_ignore_ascii_case(k.label()));
    if nexus {
        return None;
    }
    gait_event(context, label)
}

/// "Left" / "Right", any case.
fn side_word(s: &str) -> Option<Side> {
    match s.to_ascii_lowercase().as_str() {
        "left" => Some(Side::Left),
        "right" => Some(Side::Right),
        _ => None,
    }
}

/// Lower case, letters and digits only, trailing digits (a count) removed.
fn squeeze(s: &str) -> String {
    let n: String = s
        .chars()
        .filter(|c| c.is_ascii_alphanumeric())
        .map(|c| c.to_ascii_lowercase())
        .collect();
    n.trim_end_matches(|c: char| c.is_ascii_digit()).to_string()
}

/// `Foot Strike`, `Foot Off` (any case, numbered or not).
fn kind_words(s: &str) -> Option<Kind> {
    match squeeze(s).as_str() {
        "footstrike" => Some(Kind::FootStrike),
        "footoff" => Some(Kind::FootOff),
        _ => None,
    }
}

/// A code with its side first: `LHS`, `RTO`, `LON`, `ROFF`, `Left Foot Strike`, `LFS2`.
fn coded(s: &str) -> Option<(Side, Kind)> {
    let n = squeeze(s);
    let (side, rest) = [
        ("left", Side::Left),
        ("right", Side::Right),
        ("l", Side::Left),
        ("r", Side::Right),
    ]
    .into_iter()
    .find_map(|(p, side)| n.strip_prefix(p).map(|rest| (side, rest)))?;
    let kind = match rest {
        "hs" | "fs" | "ic" | "on" | "footstrike" | "heelstrike" | "strike" => Kind::FootStrike,
        "to" | "fo" | "off" | "footoff" | "toeoff" => Kind::FootOff,
        _ => return None,
    };
    Some((side, kind))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn labs_codes_and_nexus_labels() {
        use Kind::{FootOff as Off, FootStrike as Fs};
        use Side::{Left as L, Right as R};
        assert_eq!(gait_event("Left", "Foot Strike"), Some((L, Fs)));
        assert_eq!(gait_event("right", "FOOT OFF"), Some((R, Off)));
        assert_eq!(gait_event("Left", "Foot Strike1"), Some((L, Fs)));
        assert_eq!(gait_event("General", "LHS"), Some((L, Fs)));
        assert_eq!(gait_event("General", "RTO"), Some((R, Off)));
        assert_eq!(gait_event("", "LON"), Some((L, Fs)));
        assert_eq!(gait_event("", "LOFF"), Some((L, Off)));
        assert_eq!(gait_event("RHS", ""), Some((R, Fs)));
        assert_eq!(gait_event("Right", "RTO"), Some((R, Off)));
        // A code that contradicts its context, a generic label, a jump's phases: none.
        assert_eq!(gait_event("Left", "RHS"), None);
        assert_eq!(gait_event("Right", "Event"), None);
        assert_eq!(gait_event("General", "Event"), None);
        assert_eq!(gait_event("Take-Off", ""), None);
        assert_eq!(gait_event("General", "Seating4"), None);
        assert_eq!(gait_event("General", "Standing4"), None);
    }
}
