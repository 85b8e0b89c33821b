//! Writing the parameter section: unchanged records from their original bytes, changed ones
//! from their canonical encoding.

use super::model::{Parameters, Record, Value};
use crate::error::{Error, Result};
use crate::header::BLOCK;
use crate::processor::Processor;
use crate::text::to_latin1;

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
    use crate::parameters::{parse, SectionBounds};

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
                reach: file.len(),
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
}
