//! Reading the parameter section from a file's bytes, leniently: damaged records are read as
//! far as they make sense and reported as warnings.

use super::encoding::encode_record;
use super::model::{element_count, Group, Parameter, Parameters, RawRecord, Record, Value};
use crate::error::{Error, Result, Section, Warning};
use crate::processor::Processor;
use crate::text::latin1;

/// Where to look for records, computed from the header and the section's prelude.
pub(crate) struct SectionBounds {
    /// Offset of the section's first byte.
    pub start: usize,
    /// End declared by the prelude's block count (or by the data start when the count is 0).
    pub end: usize,
    /// How far a chain of records that runs over `end` may still be followed: the data start
    /// when it lies beyond `end`, else `end`. Some writers count the section's blocks short
    /// (sample_15's FP files declare 3 blocks and write 4, with FORCE_PLATFORM in the fourth);
    /// stopping at the declared end would lose whole groups that the file does hold.
    pub reach: usize,
}

/// Parse the section at `bounds` from the whole file.
pub(crate) fn parse(
    file: &[u8],
    bounds: SectionBounds,
    p: Processor,
    warnings: &mut Vec<Warning>,
) -> Result<(Parameters, usize)> {
    let SectionBounds { start, end, reach } = bounds;
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
    let reach = reach.min(file.len()).max(end);
    let mut followed_past_end = false;
    loop {
        if pos + 2 > end {
            // Past the declared end, go on only along a chain of records that already ran
            // over it, and only while what follows reads as a record.
            if !(extent > end && pos + 2 <= reach && plausible_record(file, pos, reach)) {
                break;
            }
            if !followed_past_end {
                followed_past_end = true;
                warnings.push(Warning::new(
                    sec,
                    Some(pos),
                    format!(
                        "parameter records go on past the section's declared end (byte {end}); read up to the data (byte {reach})"
                    ),
                ));
            }
        }
        let name_len = file[pos] as i8;
        if name_len == 0 {
            terminated = true;
            break;
        }
        let id = file[pos + 1] as i8;
        let limit = if pos + 2 > end { reach } else { end };
        match parse_record(file, pos, limit, p, records.len(), warnings)? {
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
    // Records may run past the declared end (a known vendor fault) but never past the file.
    let hard_end = file.len();
    let Some(head) = read_head(file, pos, p, warnings) else {
        return Ok(None);
    };
    let (next, rec_end) = record_bounds(file, &head, end, warnings);
    let lim = rec_end.min(hard_end);
    let off_pos = head.off_pos;
    let Some(record) = read_contents(file, head, lim, p, warnings)? else {
        return Ok(None);
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
                Section::Parameters,
                Some(off_pos),
                "offset to next record points past the end of the file",
            ));
            return Ok(Some((record, None, lim)));
        }
    }
    Ok(Some((record, next, lim)))
}

/// What a record's first bytes say: its name (a negative length: locked), its id (negative:
/// a group), the offset to the next record and where its body starts.
struct Head {
    pos: usize,
    name_len_raw: i8,
    id: i8,
    name: String,
    /// Where the offset to the next record is stored, and what it says.
    off_pos: usize,
    offset: usize,
    body: usize,
}

impl Head {
    fn what(&self) -> &'static str {
        if self.id < 0 {
            "group"
        } else {
            "parameter"
        }
    }
}

/// The record's head at `pos`; None (with a warning) when the file ends inside it.
fn read_head(file: &[u8], pos: usize, p: Processor, warnings: &mut Vec<Warning>) -> Option<Head> {
    let name_len_raw = file[pos] as i8;
    let id = file[pos + 1] as i8;
    let nlen = name_len_raw.unsigned_abs() as usize;
    let off_pos = pos + 2 + nlen;
    if off_pos + 2 > file.len() {
        warnings.push(Warning::new(
            Section::Parameters,
            Some(pos),
            "record truncated by the end of the file; ignored",
        ));
        return None;
    }
    let name = latin1(&file[pos + 2..off_pos]);
    let offset = p.read_i16([file[off_pos], file[off_pos + 1]]) as u16 as usize;
    Some(Head {
        pos,
        name_len_raw,
        id,
        name,
        off_pos,
        offset,
        body: off_pos + 2,
    })
}

/// Where the next record starts (None: this is the last) and where this one's bytes stop:
/// the offset as stored, or the end of the record's contents when the offset is wrong.
fn record_bounds(
    file: &[u8],
    h: &Head,
    end: usize,
    warnings: &mut Vec<Warning>,
) -> (Option<usize>, usize) {
    let (sec, hard_end, body, what, name) =
        (Section::Parameters, file.len(), h.body, h.what(), &h.name);
    let mut next = if h.offset == 0 {
        None
    } else {
        Some(h.off_pos + h.offset)
    };
    // The body's natural length, to judge the offset against.
    let natural_end = if h.id < 0 {
        body.checked_add(1)
            .filter(|&e| e <= hard_end)
            .map(|e| e + file[body] as usize)
    } else {
        body_natural_end(file, body)
    };
    if let (Some(n), Some(nat)) = (next, natural_end) {
        // A wrong offset: the next record would start inside this one, or at garbage while a
        // real record follows right after this one's contents.
        let inside = n < body + if h.id < 0 { 1 } else { 2 };
        if inside || (!plausible_record(file, n, hard_end) && plausible_record(file, nat, end)) {
            warnings.push(Warning::new(
                sec,
                Some(h.off_pos),
                format!(
                    "{what} {name}: offset to next record ({}) is wrong; \
                     using the end of its contents instead",
                    h.offset
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
    if rec_end > end && h.pos < end {
        warnings.push(Warning::new(
            sec,
            Some(h.pos),
            format!(
                "{what} {name} extends past the end of the parameter section (byte {end}); read from the bytes that follow"
            ),
        ));
    }
    (next, rec_end)
}

/// The group or parameter the record's body holds up to `lim`; `Ok(None)` when a
/// parameter's body cannot be read.
fn read_contents(
    file: &[u8],
    h: Head,
    lim: usize,
    p: Processor,
    warnings: &mut Vec<Warning>,
) -> Result<Option<Record>> {
    let Head {
        name_len_raw,
        id,
        name,
        body,
        ..
    } = h;
    Ok(Some(if id < 0 {
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
    }))
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
