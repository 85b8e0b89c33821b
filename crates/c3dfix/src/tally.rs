//! Counts per kind (gaps filled per method, left per reason), kept and listed in the order
//! of the kinds' names: the order the reports have always listed them in, whatever order
//! the kinds are declared in.

use serde::ser::{Serialize, SerializeMap, Serializer};
use std::fmt::Display;

/// How many of each kind, in the order of the kinds' names ([`Display`]); serialized as a
/// map from name to count, as a map keyed by the names would be.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Tally<K>(Vec<(K, usize)>);

impl<K> Default for Tally<K> {
    fn default() -> Self {
        Tally(Vec::new())
    }
}

impl<K: Copy + PartialEq + Display> Tally<K> {
    /// `n` more of `kind`.
    pub fn add(&mut self, kind: K, n: usize) {
        if let Some((_, count)) = self.0.iter_mut().find(|(k, _)| *k == kind) {
            *count += n;
            return;
        }
        let name = kind.to_string();
        let at = self.0.partition_point(|(k, _)| k.to_string() < name);
        self.0.insert(at, (kind, n));
    }

    /// Every count of `other` added to these.
    pub fn add_all(&mut self, other: &Tally<K>) {
        for (k, n) in other.iter() {
            self.add(k, n);
        }
    }

    /// How many of `kind` (0 when none was counted).
    pub fn get(&self, kind: K) -> usize {
        self.0
            .iter()
            .find(|(k, _)| *k == kind)
            .map_or(0, |&(_, n)| n)
    }

    /// Each kind counted with its count, in the order of their names.
    pub fn iter(&self) -> impl Iterator<Item = (K, usize)> + '_ {
        self.0.iter().copied()
    }

    /// All counts together.
    pub fn total(&self) -> usize {
        self.0.iter().map(|&(_, n)| n).sum()
    }

    /// No kind counted.
    pub fn is_empty(&self) -> bool {
        self.0.is_empty()
    }
}

impl<K: Display> Serialize for Tally<K> {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let mut map = s.serialize_map(Some(self.0.len()))?;
        for (k, n) in &self.0 {
            map.serialize_entry(&k.to_string(), n)?;
        }
        map.end()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use repair::{FillMethod, SkipKind};

    #[test]
    fn kinds_are_listed_and_serialized_by_name_as_a_string_keyed_map_was() {
        let mut t = Tally::default();
        for m in [
            FillMethod::Spline,
            FillMethod::Linear,
            FillMethod::Pca,
            FillMethod::Kalman,
            FillMethod::Linear,
            FillMethod::Lagrange5,
            FillMethod::Hold,
        ] {
            t.add(m, 1);
        }
        let names: Vec<String> = t.iter().map(|(m, _)| m.to_string()).collect();
        let mut sorted = names.clone();
        sorted.sort();
        assert_eq!(names, sorted);
        assert_eq!(t.get(FillMethod::Linear), 2);
        assert_eq!(t.total(), 7);
        let by_name: std::collections::BTreeMap<String, usize> =
            t.iter().map(|(m, n)| (m.to_string(), n)).collect();
        assert_eq!(
            serde_json::to_string(&t).unwrap(),
            serde_json::to_string(&by_name).unwrap()
        );
        let mut left = Tally::default();
        left.add(SkipKind::Uncertain, 2);
        left.add(SkipKind::TooLong, 1);
        left.add(SkipKind::NoDonors, 3);
        assert_eq!(
            serde_json::to_string(&left).unwrap(),
            r#"{"no_donors":3,"too_long":1,"uncertain":2}"#
        );
    }
}
