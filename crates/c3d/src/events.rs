//! Events: the 18 header slots and the EVENT parameter group.

use crate::parameters::Parameters;
use serde::Serialize;

/// An event from the EVENT group (EVENT:LABELS, CONTEXTS, TIMES, DESCRIPTIONS).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Event {
    pub label: String,
    /// "Left", "Right", "General" …; empty when the file gives none.
    pub context: String,
    /// Seconds from the start of the trial (EVENT:TIMES stores minutes and seconds).
    pub time: f64,
    pub description: String,
}

/// The events of the EVENT group, as many as EVENT:USED says (or as TIMES holds).
pub fn from_parameters(ps: &Parameters) -> Vec<Event> {
    let Some(times) = ps.get("EVENT", "TIMES") else {
        return Vec::new();
    };
    let t = times.as_f32s();
    let pairs = t.len() / 2;
    let used = ps
        .get_i32("EVENT", "USED")
        .map_or(pairs, |u| (u.max(0) as usize).min(pairs));
    let labels = ps.get_strings("EVENT", "LABELS").unwrap_or_default();
    let contexts = ps.get_strings("EVENT", "CONTEXTS").unwrap_or_default();
    let descriptions = ps.get_strings("EVENT", "DESCRIPTIONS").unwrap_or_default();
    let at = |v: &[String], i: usize| v.get(i).cloned().unwrap_or_default();
    (0..used)
        .map(|i| Event {
            label: at(&labels, i),
            context: at(&contexts, i),
            time: t[2 * i] as f64 * 60.0 + t[2 * i + 1] as f64,
            description: at(&descriptions, i),
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::parameters::Value;

    #[test]
    fn times_are_minutes_and_seconds() {
        let mut ps = Parameters::new();
        ps.set_i16("EVENT", "USED", 2).unwrap();
        ps.set(
            "EVENT",
            "TIMES",
            vec![2, 2],
            Value::Float(vec![0.0, 1.5, 1.0, 0.25]),
        )
        .unwrap();
        ps.set_strings(
            "EVENT",
            "LABELS",
            &["Foot Strike".into(), "Foot Off".into()],
        )
        .unwrap();
        let ev = from_parameters(&ps);
        assert_eq!(ev.len(), 2);
        assert_eq!(ev[0].label, "Foot Strike");
        assert_eq!(ev[0].time, 1.5);
        assert_eq!(ev[1].time, 60.25);
    }
}
