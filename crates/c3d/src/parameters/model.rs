//! The parameter section's model: groups and parameters in file order, with typed access.

use crate::error::{Error, Result};
use crate::processor::Processor;
use crate::text::{latin1, to_latin1};
use serde::Serialize;

/// A parameter's data, typed as stored (type byte -1, 1, 2 or 4).
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(tag = "type", content = "values", rename_all = "lowercase")]
pub enum Value {
    Char(Vec<u8>),
    Byte(Vec<u8>),
    Int(Vec<i16>),
    Float(Vec<f32>),
}

impl Value {
    pub(super) fn type_byte(&self) -> i8 {
        match self {
            Value::Char(_) => -1,
            Value::Byte(_) => 1,
            Value::Int(_) => 2,
            Value::Float(_) => 4,
        }
    }

    /// Number of elements.
    pub fn len(&self) -> usize {
        match self {
            Value::Char(v) | Value::Byte(v) => v.len(),
            Value::Int(v) => v.len(),
            Value::Float(v) => v.len(),
        }
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    pub fn type_name(&self) -> &'static str {
        match self {
            Value::Char(_) => "char",
            Value::Byte(_) => "byte",
            Value::Int(_) => "int16",
            Value::Float(_) => "float",
        }
    }
}

/// Bytes kept from the file for a record, so an unchanged record is rewritten exactly.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct RawRecord {
    /// From the record's first byte to the next record's first byte.
    pub(super) bytes: Vec<u8>,
    /// The canonical encoding of what was parsed from `bytes` (processor of the file).
    pub(super) canonical: Vec<u8>,
    /// Position among the records read.
    pub(super) index: usize,
}

/// A parameter group.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Group {
    /// Group number (1–127); parameters refer to it.
    pub id: u8,
    pub name: String,
    pub locked: bool,
    pub description: String,
    #[serde(skip)]
    pub(super) raw: Option<RawRecord>,
}

/// A parameter.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Parameter {
    /// Number of the group it belongs to.
    pub group_id: u8,
    pub name: String,
    pub locked: bool,
    /// Dimensions (0 to 7 of them); none means a single element.
    pub dims: Vec<u8>,
    pub value: Value,
    pub description: String,
    #[serde(skip)]
    pub(super) raw: Option<RawRecord>,
}

/// A record of the parameter section.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "lowercase")]
pub enum Record {
    Group(Group),
    Parameter(Parameter),
}

impl Record {
    pub(super) fn raw(&self) -> Option<&RawRecord> {
        match self {
            Record::Group(g) => g.raw.as_ref(),
            Record::Parameter(p) => p.raw.as_ref(),
        }
    }

    pub(super) fn name(&self) -> &str {
        match self {
            Record::Group(g) => &g.name,
            Record::Parameter(p) => &p.name,
        }
    }
}

/// The whole parameter section.
#[derive(Debug, Clone, PartialEq)]
pub struct Parameters {
    /// Records in file order.
    pub records: Vec<Record>,
    /// The section's first four bytes: reserved, key (0x50), block count, processor.
    pub(crate) prelude: [u8; 4],
    /// The section as read (for rewriting it untouched), and the processor it was read with.
    pub(crate) raw: Option<(Vec<u8>, Processor)>,
    pub(crate) raw_record_count: usize,
}

impl Parameters {
    /// An empty section for a new file.
    pub fn new() -> Parameters {
        Parameters {
            records: Vec::new(),
            prelude: [1, 0x50, 0, Processor::Intel.byte()],
            raw: None,
            raw_record_count: 0,
        }
    }

    /// Block count from the section's prelude.
    pub fn declared_blocks(&self) -> u8 {
        self.prelude[2]
    }

    /// The groups, in file order.
    pub fn groups(&self) -> impl Iterator<Item = &Group> {
        self.records.iter().filter_map(|r| match r {
            Record::Group(g) => Some(g),
            Record::Parameter(_) => None,
        })
    }

    /// The parameters of group `id`, in file order.
    pub fn parameters_of(&self, id: u8) -> impl Iterator<Item = &Parameter> {
        self.records.iter().filter_map(move |r| match r {
            Record::Parameter(p) if p.group_id == id => Some(p),
            _ => None,
        })
    }

    /// The group called `name` (case-insensitive).
    pub fn group(&self, name: &str) -> Option<&Group> {
        self.groups().find(|g| g.name.eq_ignore_ascii_case(name))
    }

    /// The parameter `group:name` (case-insensitive).
    pub fn get(&self, group: &str, name: &str) -> Option<&Parameter> {
        let id = self.group(group)?.id;
        self.parameters_of(id)
            .find(|p| p.name.eq_ignore_ascii_case(name))
    }

    /// Mutable access to `group:name`.
    pub fn get_mut(&mut self, group: &str, name: &str) -> Option<&mut Parameter> {
        let id = self.group(group)?.id;
        self.records.iter_mut().find_map(|r| match r {
            Record::Parameter(p) if p.group_id == id && p.name.eq_ignore_ascii_case(name) => {
                Some(p)
            }
            _ => None,
        })
    }

    /// First element of `group:name` as a float (ints and bytes convert).
    pub fn get_f32(&self, group: &str, name: &str) -> Option<f32> {
        self.get(group, name)?.as_f32s().first().copied()
    }

    /// First element of `group:name` as a signed integer.
    pub fn get_i32(&self, group: &str, name: &str) -> Option<i32> {
        self.get(group, name)
            .and_then(|p| p.as_i32s().first().copied())
    }

    /// First element of `group:name` read as an unsigned 16-bit integer (POINT:FRAMES etc.).
    pub fn get_u16(&self, group: &str, name: &str) -> Option<u16> {
        self.get(group, name)
            .and_then(|p| p.as_u16s().first().copied())
    }

    /// `group:name` as strings (one per row of a char array).
    pub fn get_strings(&self, group: &str, name: &str) -> Option<Vec<String>> {
        self.get(group, name).map(|p| p.as_strings())
    }

    /// `group:name` and its continuations `name2`, `name3`, … concatenated (POINT:LABELS2 …),
    /// as written by files with more than 255 labels.
    pub fn get_strings_continued(&self, group: &str, name: &str) -> Vec<String> {
        let mut out = self.get_strings(group, name).unwrap_or_default();
        for k in 2.. {
            match self.get_strings(group, &format!("{name}{k}")) {
                Some(more) => out.extend(more),
                None => break,
            }
        }
        out
    }

    /// Set `group:name` to `value` with `dims`, creating the group and parameter as needed.
    pub fn set(&mut self, group: &str, name: &str, dims: Vec<u8>, value: Value) -> Result<()> {
        if dims.len() > 7 {
            return Err(Error::Misuse(format!(
                "{group}:{name}: more than 7 dimensions"
            )));
        }
        let count = element_count(&dims).unwrap_or(usize::MAX);
        if count != value.len() {
            return Err(Error::Misuse(format!(
                "{group}:{name}: dimensions {dims:?} hold {count} elements, value has {}",
                value.len()
            )));
        }
        if dims.len() > 7 {
            return Err(Error::Misuse(format!(
                "{group}:{name}: more than 7 dimensions"
            )));
        }
        if let Some(p) = self.get_mut(group, name) {
            p.dims = dims;
            p.value = value;
            return Ok(());
        }
        let id = match self.group(group) {
            Some(g) => g.id,
            None => {
                let id = (1..=127u8)
                    .find(|i| self.groups().all(|g| g.id != *i))
                    .ok_or_else(|| Error::Misuse("no free group number".into()))?;
                self.records.push(Record::Group(Group {
                    id,
                    name: group.to_ascii_uppercase(),
                    locked: false,
                    description: String::new(),
                    raw: None,
                }));
                id
            }
        };
        // New parameters go after the last record of their group, keeping groups together.
        let at = self
            .records
            .iter()
            .rposition(|r| match r {
                Record::Group(g) => g.id == id,
                Record::Parameter(p) => p.group_id == id,
            })
            .map_or(self.records.len(), |i| i + 1);
        self.records.insert(
            at,
            Record::Parameter(Parameter {
                group_id: id,
                name: name.to_ascii_uppercase(),
                locked: false,
                dims,
                value,
                description: String::new(),
                raw: None,
            }),
        );
        Ok(())
    }

    /// Set a one-dimensional list of strings (`group:name` as `char[len][n]`), padding with spaces.
    pub fn set_strings(&mut self, group: &str, name: &str, strings: &[String]) -> Result<()> {
        let width = strings
            .iter()
            .map(|s| s.chars().count())
            .max()
            .unwrap_or(0)
            .max(1);
        if width > 255 || strings.len() > 255 {
            return Err(Error::Misuse(format!(
                "{group}:{name}: {} strings of up to {width} characters exceed 255×255",
                strings.len()
            )));
        }
        let mut bytes = Vec::with_capacity(width * strings.len());
        for s in strings {
            let mut b = to_latin1(s);
            b.resize(width, b' ');
            bytes.extend(b);
        }
        self.set(
            group,
            name,
            vec![width as u8, strings.len() as u8],
            Value::Char(bytes),
        )
    }

    /// Set a single integer.
    pub fn set_i16(&mut self, group: &str, name: &str, v: i16) -> Result<()> {
        self.set(group, name, vec![], Value::Int(vec![v]))
    }

    /// Set a single float.
    pub fn set_f32(&mut self, group: &str, name: &str, v: f32) -> Result<()> {
        self.set(group, name, vec![], Value::Float(vec![v]))
    }

    /// Remove `group:name`; returns whether it existed.
    pub fn remove(&mut self, group: &str, name: &str) -> bool {
        let Some(id) = self.group(group).map(|g| g.id) else {
            return false;
        };
        let before = self.records.len();
        self.records.retain(|r| {
            !matches!(r, Record::Parameter(p) if p.group_id == id && p.name.eq_ignore_ascii_case(name))
        });
        before != self.records.len()
    }
}

impl Default for Parameters {
    fn default() -> Self {
        Parameters::new()
    }
}

impl Parameter {
    /// All elements as floats.
    pub fn as_f32s(&self) -> Vec<f32> {
        match &self.value {
            Value::Float(v) => v.clone(),
            Value::Int(v) => v.iter().map(|&x| x as f32).collect(),
            Value::Byte(v) => v.iter().map(|&x| x as f32).collect(),
            Value::Char(_) => Vec::new(),
        }
    }

    /// All elements as signed integers (floats are rounded).
    pub fn as_i32s(&self) -> Vec<i32> {
        match &self.value {
            Value::Int(v) => v.iter().map(|&x| x as i32).collect(),
            Value::Byte(v) => v.iter().map(|&x| x as i32).collect(),
            Value::Float(v) => v.iter().map(|&x| x.round() as i32).collect(),
            Value::Char(_) => Vec::new(),
        }
    }

    /// All elements as unsigned 16-bit integers: int16 data reinterpreted, as the manual asks
    /// for counts such as POINT:FRAMES that may exceed 32767.
    pub fn as_u16s(&self) -> Vec<u16> {
        match &self.value {
            Value::Int(v) => v.iter().map(|&x| x as u16).collect(),
            Value::Byte(v) => v.iter().map(|&x| x as u16).collect(),
            Value::Float(v) => v
                .iter()
                .map(|&x| x.round().clamp(0.0, 65535.0) as u16)
                .collect(),
            Value::Char(_) => Vec::new(),
        }
    }

    /// Char data as strings: one per row (the first dimension is the string length), with
    /// trailing spaces and NULs removed.
    pub fn as_strings(&self) -> Vec<String> {
        let Value::Char(bytes) = &self.value else {
            return Vec::new();
        };
        let width = self.dims.first().copied().unwrap_or(1) as usize;
        if width == 0 {
            let rows = element_count(&self.dims[1..]).unwrap_or(0);
            return vec![String::new(); rows];
        }
        bytes
            .chunks(width)
            .map(|c| latin1(c).trim_end_matches([' ', '\0']).to_string())
            .collect()
    }
}

/// Number of elements of an array with these dimensions (1 for none); None on overflow.
pub(crate) fn element_count(dims: &[u8]) -> Option<usize> {
    dims.iter()
        .try_fold(1usize, |n, &d| n.checked_mul(d as usize))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn set_checks_dimensions() {
        let mut ps = Parameters::new();
        let e = ps
            .set("A", "B", vec![2, 2], Value::Int(vec![1, 2, 3]))
            .unwrap_err();
        assert!(e.to_string().contains("hold 4 elements"), "{e}");
    }

    #[test]
    fn unsigned_frames() {
        let mut ps = Parameters::new();
        ps.set_i16("POINT", "FRAMES", -25536).unwrap(); // 40000 as u16
        assert_eq!(ps.get_u16("POINT", "FRAMES"), Some(40000));
    }

    #[test]
    fn continued_labels() {
        let mut ps = Parameters::new();
        ps.set_strings("POINT", "LABELS", &["A".into()]).unwrap();
        ps.set_strings("POINT", "LABELS2", &["B".into(), "C".into()])
            .unwrap();
        assert_eq!(ps.get_strings_continued("POINT", "LABELS"), ["A", "B", "C"]);
    }
}
