//! The parameter section: groups and parameters in file order.
//!
//! Every record keeps the bytes it was read from, plus the canonical encoding of what was
//! parsed. When writing, a record whose canonical encoding has not changed is written from its
//! original bytes, and an untouched section is written back whole — so vendor padding, odd
//! offsets and lossy-to-decode values survive a rewrite. Parsing is lenient: damaged records
//! are read as far as they make sense and reported as [`Warning`]s.

use crate::error::{Error, Result, Section, Warning};
use crate::header::BLOCK;
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
    fn type_byte(&self) -> i8 {
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
struct RawRecord {
    /// From the record's first byte to the next record's first byte.
    bytes: Vec<u8>,
    /// The canonical encoding of what was parsed from `bytes` (processor of the file).
    canonical: Vec<u8>,
    /// Position among the records read.
    index: usize,
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
    raw: Option<RawRecord>,
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
    raw: Option<RawRecord>,
}

/// A record of the parameter section.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "lowercase")]
pub enum Record {
    Group(Group),
    Parameter(Parameter),
}

impl Record {
    fn raw(&self) -> Option<&RawRecord> {
        match self {
            Record::Group(g) => g.raw.as_ref(),
            Record::Parameter(p) => p.raw.as_ref(),
        }
    }

    fn name(&self) -> &str {
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

/// Where to look for records, computed from the header and the section's prelude.
pub(crate) struct SectionBounds {
    /// Offset of the section's first byte.
    pub start: usize,
    /// End declared by the prelude's block count (or by the data start when the count is 0).
    pub end: usize,
}

/// Parse the section at `bounds` from the whole file.
pub(crate) fn parse(
    file: &[u8],
    bounds: SectionBounds,
    p: Processor,
    warnings: &mut Vec<Warning>,
) -> Result<(Parameters, usize)> {
    let SectionBounds { start, end } = bounds;
    let sec = Section::Parameters;
    if start + 4 > file.len() {
        return Err(Error::malformed(
            sec,
            start,
            format!(
                "the parameter section should start here but the file is only {} bytes",
                file.len()
            ),
        ));
    }
    let prelude = [
        file[start],
        file[start + 1],
        file[start + 2],
        file[start + 3],
    ];
    let end = end.min(file.len());
    let mut records = Vec::new();
    let mut pos = start + 4;
    // The furthest byte any record used: the section's extent when records overflow `end`.
    let mut extent = end;
    let mut terminated = false;
    while pos + 2 <= end {
        let name_len = file[pos] as i8;
        if name_len == 0 {
            terminated = true;
            break;
        }
        let id = file[pos + 1] as i8;
        match parse_record(file, pos, end, p, records.len(), warnings)? {
            Some((record, next, used_to)) => {
                extent = extent.max(used_to);
                if id == 0 {
                    warnings.push(Warning::new(sec, Some(pos), "record with group number 0"));
                }
                records.push(record);
                match next {
                    Some(n) => pos = n,
                    None => {
                        terminated = true;
                        break;
                    }
                }
            }
            None => break,
        }
    }
    if !terminated && pos + 2 > end && pos < end {
        warnings.push(Warning::new(
            sec,
            Some(pos),
            "parameter list ends without a terminating record",
        ));
    }
    let raw_end = extent.min(file.len());
    let params = Parameters {
        raw_record_count: records.len(),
        records,
        prelude,
        raw: Some((file[start..raw_end].to_vec(), p)),
    };
    check_groups(&params, start, warnings);
    Ok((params, raw_end))
}

fn check_groups(params: &Parameters, start: usize, warnings: &mut Vec<Warning>) {
    let mut orphans: Vec<(u8, Vec<&str>)> = Vec::new();
    for r in &params.records {
        if let Record::Parameter(prm) = r {
            if params.groups().all(|g| g.id != prm.group_id) {
                match orphans.iter_mut().find(|(id, _)| *id == prm.group_id) {
                    Some((_, names)) => names.push(&prm.name),
                    None => orphans.push((prm.group_id, vec![&prm.name])),
                }
            }
        }
    }
    for (id, names) in orphans {
        warnings.push(Warning::new(
            Section::Parameters,
            Some(start),
            format!(
                "{} parameters ({}) belong to group {id}, which has no group record",
                names.len(),
                names.join(", ")
            ),
        ));
    }
}

/// Does the record at `pos` look like a real record (printable name, sane id)?
fn plausible_record(file: &[u8], pos: usize, end: usize) -> bool {
    if pos + 2 > end {
        return false;
    }
    let n = (file[pos] as i8).unsigned_abs() as usize;
    if n == 0 {
        return true; // terminator
    }
    pos + 2 + n <= end
        && file[pos + 1] != 0
        && file[pos + 2..pos + 2 + n]
            .iter()
            .all(|&c| c.is_ascii_graphic() || c == b' ')
}

type Parsed = Option<(Record, Option<usize>, usize)>;

/// Parse one record at `pos`. Returns the record, where the next one starts (None: last) and
/// the furthest byte used. `Ok(None)` means the record could not be read; parsing stops there.
fn parse_record(
    file: &[u8],
    pos: usize,
    end: usize,
    p: Processor,
    index: usize,
    warnings: &mut Vec<Warning>,
) -> Result<Parsed> {
    let sec = Section::Parameters;
    let name_len_raw = file[pos] as i8;
    let id = file[pos + 1] as i8;
    let nlen = name_len_raw.unsigned_abs() as usize;
    let off_pos = pos + 2 + nlen;
    // Records may run past the declared end (a known vendor fault) but never past the file.
    let hard_end = file.len();
    if off_pos + 2 > hard_end {
        warnings.push(Warning::new(
            sec,
            Some(pos),
            "record truncated by the end of the file; ignored",
        ));
        return Ok(None);
    }
    let name = latin1(&file[pos + 2..off_pos]);
    let offset = p.read_i16([file[off_pos], file[off_pos + 1]]) as u16 as usize;
    let body = off_pos + 2;
    let mut next = if offset == 0 {
        None
    } else {
        Some(off_pos + offset)
    };
    let what = if id < 0 { "group" } else { "parameter" };

    // The body's natural length, to judge the offset against.
    let natural_end = if id < 0 {
        body.checked_add(1)
            .filter(|&e| e <= hard_end)
            .map(|e| e + file[body] as usize)
    } else {
        body_natural_end(file, body)
    };
    if let (Some(n), Some(nat)) = (next, natural_end) {
        // A wrong offset: the next record would start inside this one, or at garbage while a
        // real record follows right after this one's contents.
        let inside = n < body + if id < 0 { 1 } else { 2 };
        if inside || (!plausible_record(file, n, hard_end) && plausible_record(file, nat, end)) {
            warnings.push(Warning::new(
                sec,
                Some(off_pos),
                format!(
                    "{what} {name}: offset to next record ({offset}) is wrong; \
                     using the end of its contents instead"
                ),
            ));
            next = Some(nat);
        }
    }
    // Where this record's bytes stop: the next record, or its natural end when it is the last.
    let rec_end = match (next, natural_end) {
        (Some(n), _) => n,
        (None, Some(nat)) => nat.min(hard_end),
        (None, None) => end,
    };
    if rec_end > end && pos < end {
        warnings.push(Warning::new(
            sec,
            Some(pos),
            format!(
                "{what} {name} extends past the end of the parameter section (byte {end}); read from the bytes that follow"
            ),
        ));
    }
    let lim = rec_end.min(hard_end);
    let record = if id < 0 {
        let (description, _) = read_description(file, body, lim, &name, warnings);
        Record::Group(Group {
            id: id.unsigned_abs(),
            name,
            locked: name_len_raw < 0,
            description,
            raw: None,
        })
    } else {
        let Some((dims, value, after)) = read_param_body(file, body, lim, p, &name, warnings)?
        else {
            return Ok(None);
        };
        let (description, _) = read_description(file, after, lim, &name, warnings);
        Record::Parameter(Parameter {
            group_id: id as u8,
            name,
            locked: name_len_raw < 0,
            dims,
            value,
            description,
            raw: None,
        })
    };
    let bytes = file[pos..lim].to_vec();
    let canonical = encode_record(&record, p);
    let raw = RawRecord {
        bytes,
        canonical,
        index,
    };
    let record = match record {
        Record::Group(mut g) => {
            g.raw = Some(raw);
            Record::Group(g)
        }
        Record::Parameter(mut prm) => {
            prm.raw = Some(raw);
            Record::Parameter(prm)
        }
    };
    if let Some(n) = next {
        if n > hard_end {
            warnings.push(Warning::new(
                sec,
                Some(off_pos),
                "offset to next record points past the end of the file",
            ));
            return Ok(Some((record, None, lim)));
        }
    }
    Ok(Some((record, next, lim)))
}

/// The natural end of a parameter body (type, dims, data, description) or None if unreadable.
fn body_natural_end(file: &[u8], body: usize) -> Option<usize> {
    let t = *file.get(body)? as i8;
    let nd = *file.get(body + 1)? as usize;
    if nd > 7 {
        return None;
    }
    let dims = file.get(body + 2..body + 2 + nd)?;
    let bytes = element_count(dims)?.checked_mul(t.unsigned_abs() as usize)?;
    let data_end = (body + 2 + nd).checked_add(bytes)?;
    let dl = *file.get(data_end)? as usize;
    Some(data_end + 1 + dl)
}

type ParamBody = Option<(Vec<u8>, Value, usize)>;

fn read_param_body(
    file: &[u8],
    body: usize,
    lim: usize,
    p: Processor,
    name: &str,
    warnings: &mut Vec<Warning>,
) -> Result<ParamBody> {
    let sec = Section::Parameters;
    // Data that overflows the section is still read from the file when the bytes exist.
    let data_lim = file.len();
    if body + 2 > data_lim {
        warnings.push(Warning::new(
            sec,
            Some(body),
            format!("parameter {name}: type and dimensions missing; ignored"),
        ));
        return Ok(None);
    }
    let t = file[body] as i8;
    let nd = file[body + 1] as usize;
    let elem = match t {
        -1 | 1 => 1,
        2 => 2,
        4 => 4,
        _ => {
            warnings.push(Warning::new(
                sec,
                Some(body),
                format!("parameter {name}: unknown type {t}; ignored"),
            ));
            return Ok(None);
        }
    };
    if nd > 7 {
        warnings.push(Warning::new(
            sec,
            Some(body + 1),
            format!("parameter {name}: {nd} dimensions (at most 7); ignored"),
        ));
        return Ok(None);
    }
    if body + 2 + nd > data_lim {
        warnings.push(Warning::new(
            sec,
            Some(body),
            format!("parameter {name}: dimensions truncated; ignored"),
        ));
        return Ok(None);
    }
    let dims = file[body + 2..body + 2 + nd].to_vec();
    // At most 255^7 elements: fits in usize, but is bounded by the bytes present below.
    let count = element_count(&dims).unwrap_or(usize::MAX);
    let start = body + 2 + nd;
    let len = count.saturating_mul(elem);
    // `count` is at most 255^7 in principle; bound it by the bytes present before allocating.
    if start.saturating_add(len) > data_lim {
        warnings.push(Warning::new(
            sec,
            Some(start),
            format!("parameter {name}: {len} bytes of data run past the end of the file; ignored"),
        ));
        return Ok(None);
    }
    if start + len > lim {
        warnings.push(Warning::new(
            sec,
            Some(start),
            format!("parameter {name}: data runs past the next record's start"),
        ));
    }
    let d = &file[start..start + len];
    let value = match t {
        -1 => Value::Char(d.to_vec()),
        1 => Value::Byte(d.to_vec()),
        2 => Value::Int(
            d.chunks_exact(2)
                .map(|c| p.read_i16([c[0], c[1]]))
                .collect(),
        ),
        _ => Value::Float(
            d.chunks_exact(4)
                .map(|c| p.read_f32([c[0], c[1], c[2], c[3]]))
                .collect(),
        ),
    };
    Ok(Some((dims, value, start + len)))
}

/// Read a description (length byte + text) at `at`, bounded by `lim`.
fn read_description(
    file: &[u8],
    at: usize,
    lim: usize,
    name: &str,
    warnings: &mut Vec<Warning>,
) -> (String, usize) {
    if at >= lim || at >= file.len() {
        warnings.push(Warning::new(
            Section::Parameters,
            Some(at),
            format!("{name}: the description's length byte is missing"),
        ));
        return (String::new(), at);
    }
    let n = file[at] as usize;
    let stop = (at + 1 + n).min(lim).min(file.len());
    if at + 1 + n > stop {
        warnings.push(Warning::new(
            Section::Parameters,
            Some(at),
            format!("{name}: description runs past the record's end; cut short"),
        ));
    }
    (latin1(&file[at + 1..stop]), stop)
}

/// Canonical bytes of a record, with the offset field pointing just past it.
pub(crate) fn encode_record(r: &Record, p: Processor) -> Vec<u8> {
    let mut out = Vec::new();
    let (name, locked, id): (&str, bool, i8) = match r {
        // Group numbers are stored negated; 128 (from -128) must round-trip, hence wrapping.
        Record::Group(g) => (&g.name, g.locked, (g.id as i8).wrapping_neg()),
        Record::Parameter(prm) => (&prm.name, prm.locked, prm.group_id as i8),
    };
    let name_b = to_latin1(name);
    let nlen = name_b.len().min(127) as i8;
    out.push(if locked { -nlen } else { nlen } as u8);
    out.push(id as u8);
    out.extend_from_slice(&name_b[..nlen as usize]);
    out.extend_from_slice(&[0, 0]); // offset, patched below
    let desc = |out: &mut Vec<u8>, d: &str| {
        let b = to_latin1(d);
        let n = b.len().min(255);
        out.push(n as u8);
        out.extend_from_slice(&b[..n]);
    };
    match r {
        Record::Group(g) => desc(&mut out, &g.description),
        Record::Parameter(prm) => {
            out.push(prm.value.type_byte() as u8);
            out.push(prm.dims.len() as u8);
            out.extend_from_slice(&prm.dims);
            match &prm.value {
                Value::Char(v) | Value::Byte(v) => out.extend_from_slice(v),
                Value::Int(v) => v.iter().for_each(|&x| out.extend(p.write_i16(x))),
                Value::Float(v) => v.iter().for_each(|&x| out.extend(p.write_f32(x))),
            }
            desc(&mut out, &prm.description);
        }
    }
    set_offset(&mut out, nlen.unsigned_abs() as usize, false, p);
    out
}

/// Point a record's offset field past its end (or to 0 when it is the last record).
fn set_offset(rec: &mut [u8], nlen: usize, last: bool, p: Processor) {
    let off_pos = 2 + nlen;
    let v = if last {
        0
    } else {
        (rec.len() - off_pos) as u16
    };
    rec[off_pos..off_pos + 2].copy_from_slice(&p.write_i16(v as i16));
}

impl Parameters {
    /// True when the records are exactly the ones read, in the same order and unchanged, so
    /// the section can be written from its original bytes.
    pub(crate) fn unchanged(&self, p: Processor) -> bool {
        let Some((_, rp)) = &self.raw else {
            return false;
        };
        *rp == p
            && self.records.len() == self.raw_record_count
            && self.records.iter().enumerate().all(|(i, r)| {
                r.raw()
                    .is_some_and(|raw| raw.index == i && raw.canonical == encode_record(r, p))
            })
    }

    /// Encode the section for processor `p`: the prelude, the records (unchanged ones from
    /// their original bytes when `p` is the file's processor), a terminating zero, and zero
    /// padding to whole blocks. Returns the bytes; the block count in the prelude is set.
    pub(crate) fn encode(&self, p: Processor) -> Result<Vec<u8>> {
        if self.unchanged(p) {
            if let Some((raw, _)) = &self.raw {
                return Ok(raw.clone());
            }
        }
        let same_processor = self.raw.as_ref().is_some_and(|(_, rp)| *rp == p);
        let mut out = Vec::with_capacity(BLOCK * 4);
        out.extend_from_slice(&self.prelude);
        out[3] = p.byte();
        let n = self.records.len();
        for (i, r) in self.records.iter().enumerate() {
            let fresh = encode_record(r, p);
            let mut bytes = match r.raw() {
                Some(raw) if same_processor && raw.canonical == fresh => raw.bytes.clone(),
                _ => fresh,
            };
            let nlen = to_latin1(r.name()).len().min(127);
            if bytes.len() - (2 + nlen) > i16::MAX as usize {
                return Err(Error::Unrepresentable(format!(
                    "parameter {} is {} bytes, too long for a record",
                    r.name(),
                    bytes.len()
                )));
            }
            set_offset(&mut bytes, nlen, i + 1 == n, p);
            out.extend(bytes);
        }
        out.push(0); // a terminator for readers that look for a zero name length
        let blocks = out.len().div_ceil(BLOCK);
        if blocks > 255 {
            return Err(Error::Unrepresentable(format!(
                "the parameter section needs {blocks} blocks (at most 255)"
            )));
        }
        out.resize(blocks * BLOCK, 0);
        out[2] = blocks as u8;
        Ok(out)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample() -> Parameters {
        let mut ps = Parameters::new();
        ps.set_i16("POINT", "USED", 2).unwrap();
        ps.set_f32("POINT", "RATE", 100.0).unwrap();
        ps.set_strings("POINT", "LABELS", &["LASI".into(), "RASI".into()])
            .unwrap();
        ps.set_f32("ANALOG", "RATE", 1000.0).unwrap();
        ps
    }

    #[test]
    fn encode_then_parse_gives_the_same_records() {
        for p in [Processor::Intel, Processor::Dec, Processor::Sgi] {
            let ps = sample();
            let mut file = vec![0u8; BLOCK];
            file.extend(ps.encode(p).unwrap());
            let mut w = Vec::new();
            let bounds = SectionBounds {
                start: BLOCK,
                end: file.len(),
            };
            let (back, _) = parse(&file, bounds, p, &mut w).unwrap();
            assert!(w.is_empty(), "{w:?}");
            assert_eq!(back.get_f32("point", "rate"), Some(100.0));
            assert_eq!(back.get_i32("POINT", "USED"), Some(2));
            assert_eq!(
                back.get_strings("POINT", "LABELS").unwrap(),
                vec!["LASI", "RASI"]
            );
            assert!(back.unchanged(p));
            assert_eq!(back.encode(p).unwrap(), file[BLOCK..].to_vec());
        }
    }

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
