//! Reading: bytes → [`C3d`]. Every count taken from the file is checked against the bytes
//! actually present before anything is allocated from it.

use crate::data::Layout;
use crate::error::{Error, Result, Section, Warning};
use crate::file::{C3d, Source};
use crate::header::{Header, BLOCK};
use crate::memory::Bytes;
use crate::parameters::{self, Parameters, SectionBounds};
use crate::processor::Processor;
use std::path::Path;

/// Read a C3D file from disk. A regular file is read whole; anything else (a FIFO, a device,
/// a terminal) is read only as far as its header and parameters announce, so that a stream
/// that is not C3D, or never ends, is refused instead of filling memory.
pub fn read_file(path: impl AsRef<Path>) -> Result<C3d> {
    read_path(path.as_ref(), |f| {
        crate::memory::read_file(f).map(Bytes::Owned)
    })
}

/// [`read_file`] for a command that reads a file and is soon done: a regular file is mapped
/// (privately; never changed) rather than copied into memory, so reading a long trial costs
/// neither a second copy nor the time to make one. While the result lives, the file must not
/// be truncated or rewritten in place by another program (the next access to its data would
/// fail or see the new bytes); objects that live long should come from [`read_file`].
pub fn read_file_mapped(path: impl AsRef<Path>) -> Result<C3d> {
    read_path(path.as_ref(), crate::memory::map_file)
}

/// Open `path`; take a regular file's bytes with `regular`, anything else as a stream.
fn read_path(
    path: &Path,
    regular: impl FnOnce(std::fs::File) -> std::io::Result<Bytes>,
) -> Result<C3d> {
    let f = std::fs::File::open(path)?;
    if f.metadata()?.is_file() {
        read_bytes(regular(f)?)
    } else {
        read(read_stream(f)?)
    }
}

/// The bytes of a C3D file from a stream of unknown length: the header, the parameter
/// section, then the data section's announced size, and no more. Bytes that cannot be C3D
/// (no 0x50 key in byte 2, no known processor) stop the reading at once; [`read`] then says
/// what is wrong with them.
fn read_stream(mut r: impl std::io::Read) -> Result<Vec<u8>> {
    let mut buf = Vec::new();
    fill(&mut r, &mut buf, BLOCK)?;
    if buf.len() < BLOCK || buf[1] != 0x50 || buf[0] == 0 {
        return Ok(buf);
    }
    let param_start = (buf[0] as usize - 1) * BLOCK;
    fill(&mut r, &mut buf, param_start + BLOCK)?;
    let Some(processor) = buf
        .get(param_start + 3)
        .copied()
        .and_then(Processor::from_byte)
    else {
        return Ok(buf);
    };
    let Ok(header) = Header::parse(&buf[..BLOCK], processor) else {
        return Ok(buf);
    };
    // The parameter section: its declared blocks, or (when it declares none) up to the data.
    let nblocks = buf[param_start + 2] as usize;
    let hdr_data = (header.data_start as usize).saturating_sub(1) * BLOCK;
    let param_end = match nblocks {
        0 => hdr_data.max(param_start + BLOCK),
        n => param_start + n * BLOCK,
    };
    fill(&mut r, &mut buf, param_end)?;
    let bounds = SectionBounds {
        start: param_start,
        end: param_end.min(buf.len()),
        reach: param_end.min(buf.len()),
    };
    let Ok((ps, _)) = parameters::parse(&buf, bounds, processor, &mut Vec::new()) else {
        return Ok(buf);
    };
    // The most any reading of the announcements could need: the later data start, the most
    // frames, and frames of the widest analog reading.
    let param_data = ps.get_u16("POINT", "DATA_START").unwrap_or(0) as usize;
    let data_offset = hdr_data.max(param_data.saturating_sub(1) * BLOCK);
    let first = header.first_frame as usize;
    let last = header.last_frame as usize;
    let frames = frame_count(&header, &ps, &mut Vec::new()).max(last.saturating_sub(first) + 1);
    let spf = (header.analog_samples_per_frame as usize).max(1);
    let used = ps.get_u16("ANALOG", "USED").unwrap_or(0) as usize;
    let analog_words = (header.analog_per_frame as usize).max(used.saturating_mul(spf));
    // Float data (a negative scale in the header or in POINT:SCALE) takes 4 bytes a word.
    let float = header.scale < 0.0 || ps.get_f32("POINT", "SCALE").is_some_and(|s| s < 0.0);
    let word_bytes = if float { 4 } else { 2 };
    let frame_bytes = (4 * header.point_count as usize + analog_words) * word_bytes;
    let need = data_offset
        .saturating_add(frames.saturating_mul(frame_bytes))
        .saturating_add(BLOCK - 1)
        / BLOCK
        * BLOCK;
    fill(&mut r, &mut buf, need)?;
    Ok(buf)
}

/// Read from `r` until `buf` holds `len` bytes or the stream ends, growing `buf` only with
/// what actually arrives.
fn fill(r: &mut impl std::io::Read, buf: &mut Vec<u8>, len: usize) -> Result<()> {
    use std::io::Read;
    if buf.len() < len {
        let want = (len - buf.len()) as u64;
        r.by_ref().take(want).read_to_end(buf)?;
    }
    Ok(())
}

/// Read a C3D file from its bytes (kept, so that an unchanged file is rewritten exactly).
pub fn read(bytes: Vec<u8>) -> Result<C3d> {
    read_bytes(Bytes::Owned(bytes))
}

/// The sections in order, each checked against the bytes present before it is read: the
/// header and the processor it is written for, the parameter section's extent and records,
/// the data section's start and layout; then one light pass over the samples and the
/// format's rules over the whole.
fn read_bytes(bytes: Bytes) -> Result<C3d> {
    let mut warnings = Vec::new();
    let (pb, param_start, processor, header) = header_of(&bytes)?;
    let hdr_data_start = header.data_start as usize;
    let end = parameters_end(&bytes, pb, param_start, hdr_data_start, &mut warnings);
    let (parameters, param_end) = parameters::parse(
        &bytes,
        SectionBounds {
            start: param_start,
            end,
            reach: if hdr_data_start > pb {
                end.max((hdr_data_start - 1) * BLOCK)
            } else {
                end
            },
        },
        processor,
        &mut warnings,
    )?;
    let (data_offset, layout) =
        data_section(&bytes, &header, &parameters, (pb, param_end), &mut warnings)?;
    let source = Source {
        header: header.clone(),
        processor,
        param_start,
        param_end,
        data_offset,
        layout,
        bytes,
    };
    let mut c = C3d::from_parts(header, parameters, layout, processor, Vec::new(), source);
    scan_notes(&c, &layout, data_offset, &mut warnings);
    crate::checks::check(&c.header, &c.parameters, &layout, &mut warnings);
    c.set_warnings(warnings);
    Ok(c)
}

/// The header block, read with the processor the parameter section's first block names:
/// (the parameter section's block, its first byte, the processor, the header).
fn header_of(bytes: &[u8]) -> Result<(usize, usize, Processor, Header)> {
    if bytes.len() < BLOCK {
        return Err(Error::malformed(
            Section::Header,
            0,
            format!(
                "file is {} bytes; a C3D file starts with a 512-byte header",
                bytes.len()
            ),
        ));
    }
    if bytes[1] != 0x50 {
        return Err(Error::malformed(
            Section::Header,
            1,
            format!(
                "not a C3D file: byte 2 is 0x{:02X}, expected 0x50",
                bytes[1]
            ),
        ));
    }
    let pb = bytes[0] as usize;
    if pb == 0 {
        return Err(Error::malformed(
            Section::Header,
            0,
            "parameter section block number is 0 (blocks start at 1)",
        ));
    }
    let param_start = (pb - 1) * BLOCK;
    if param_start + 4 > bytes.len() {
        return Err(Error::malformed(
            Section::Header,
            0,
            format!(
                "parameter section at block {pb} (byte {param_start}) lies beyond the end of the {}-byte file",
                bytes.len()
            ),
        ));
    }
    let pbyte = bytes[param_start + 3];
    let processor = Processor::from_byte(pbyte).ok_or_else(|| {
        Error::malformed(
            Section::Parameters,
            param_start + 3,
            format!("unknown processor type {pbyte} (expected 84 Intel, 85 DEC or 86 SGI/MIPS)"),
        )
    })?;
    let header = Header::parse(&bytes[..BLOCK], processor)?;
    Ok((pb, param_start, processor, header))
}

/// Where the parameter section ends: its declared block count, or (when that is 0) the
/// start of the data; a count that runs into the data stops at the data.
fn parameters_end(
    bytes: &[u8],
    pb: usize,
    param_start: usize,
    hdr_data_start: usize,
    warnings: &mut Vec<Warning>,
) -> usize {
    let nblocks = bytes[param_start + 2] as usize;
    let end = if nblocks == 0 {
        let fallback = if hdr_data_start > pb {
            (hdr_data_start - 1) * BLOCK
        } else {
            bytes.len()
        };
        warnings.push(Warning::new(
            Section::Parameters,
            Some(param_start + 2),
            format!("parameter section declares 0 blocks; reading up to byte {fallback}"),
        ));
        fallback
    } else {
        let declared = param_start + nblocks * BLOCK;
        let data_at = hdr_data_start.saturating_sub(1) * BLOCK;
        if hdr_data_start > pb && declared > data_at {
            warnings.push(Warning::new(
                Section::Parameters,
                Some(param_start + 2),
                format!(
                    "parameter section declares {nblocks} blocks but the data starts at block {hdr_data_start}; reading up to the data"
                ),
            ));
            data_at
        } else {
            declared
        }
    };
    if end > bytes.len() {
        warnings.push(Warning::new(
            Section::Parameters,
            Some(param_start + 2),
            format!("parameter section declares {nblocks} blocks, past the end of the file"),
        ));
    }
    end
}

/// The data section: its first byte and its layout, refused when the file is too short to
/// hold the frames the layout announces. `at` is (the parameter block, the byte where the
/// parameter section ends).
fn data_section(
    bytes: &[u8],
    header: &Header,
    parameters: &Parameters,
    at: (usize, usize),
    warnings: &mut Vec<Warning>,
) -> Result<(usize, Layout)> {
    let (pb, param_end) = at;
    let data_start = data_start_block(header, parameters, (pb, param_end, bytes.len()), warnings)?;
    let data_offset = (data_start - 1) * BLOCK;
    if data_offset < param_end && data_start > pb {
        warnings.push(Warning::new(
            Section::Data,
            Some(data_offset),
            format!("data section starts at byte {data_offset}, inside the parameter section (ends at {param_end})"),
        ));
    }
    let available = bytes.len().saturating_sub(data_offset);
    let layout = layout(header, parameters, available, warnings)?;
    let need = layout.data_bytes();
    if need > available {
        return Err(Error::malformed(
            Section::Data,
            bytes.len(),
            format!(
                "file is truncated: {} frames of {} bytes need {} bytes from byte {}, but only {} remain",
                layout.frames,
                layout.frame_bytes(),
                need,
                data_offset,
                available
            ),
        ));
    }
    // `need` fits in what remains (checked above); a data start beyond the end of the file is
    // only possible when nothing is stored, and is then worth a warning.
    if bytes.get(data_offset..data_offset + need).is_none() {
        warnings.push(Warning::new(
            Section::Header,
            Some(16),
            format!(
                "data section starts at byte {data_offset}, beyond the end of the {}-byte file",
                bytes.len()
            ),
        ));
    }
    Ok((data_offset, layout))
}

/// One pass over the stored samples for what the file says about itself (fourth words that
/// are not residuals, every sample flagged invalid); the arrays are decoded later, and only
/// if someone asks for them.
fn scan_notes(c: &C3d, layout: &Layout, data_offset: usize, warnings: &mut Vec<Warning>) {
    let scan = c.scan();
    let notes = scan.notes;
    if let Some(k) = notes.first_odd {
        let at = data_offset
            + (k / layout.points) * layout.frame_bytes()
            + (k % layout.points) * 16
            + 12;
        warnings.push(Warning::new(
            Section::Data,
            Some(at),
            format!(
                "{} point samples store a fourth word that is not a 16-bit integer; \
                 read as valid unless negative (the manual stores the 16-bit residual word there)",
                notes.odd_fourth_words
            ),
        ));
    }
    if layout.points > 0 && layout.frames > 0 && !scan.any_valid && scan.any_stored {
        warnings.push(Warning::new(
            Section::Data,
            Some(data_offset),
            "every point sample is flagged invalid (negative residual) although coordinates are stored",
        ));
    }
}

/// The data section's first block: the header's word 9, checked against POINT:DATA_START.
/// `at` is (the parameter block, the byte where the parameter section ends, the file size).
fn data_start_block(
    h: &Header,
    ps: &Parameters,
    at: (usize, usize, usize),
    warnings: &mut Vec<Warning>,
) -> Result<usize> {
    let (pb, param_end, len) = at;
    let from_param = ps.get_u16("POINT", "DATA_START").map(|v| v as usize);
    let from_header = h.data_start as usize;
    // Data cannot share bytes with the header or the parameters. A header start that points
    // there while POINT:DATA_START points past the parameters is a damaged header word:
    // reading from it would decode header and parameter bytes as samples, and writing them
    // back would overwrite the file's structure.
    let after_params = |b: usize| b > pb && (b - 1) * BLOCK >= param_end && (b - 1) * BLOCK < len;
    match (from_header, from_param) {
        (hd, Some(p)) if hd > 0 && !after_params(hd) && after_params(p) => {
            warnings.push(Warning::new(
                Section::Header,
                Some(16),
                format!(
                    "header data start {hd} lies inside the header or parameters (which end at byte {param_end}); using POINT:DATA_START = {p}"
                ),
            ));
            Ok(p)
        }
        (0, Some(p)) if p > 0 => {
            warnings.push(Warning::new(
                Section::Header,
                Some(16),
                format!("header data start is 0; using POINT:DATA_START = {p}"),
            ));
            Ok(p)
        }
        (0, _) => Err(Error::malformed(
            Section::Header,
            16,
            "data start block is 0 and POINT:DATA_START is missing",
        )),
        (hd, Some(p)) if p != hd => {
            warnings.push(Warning::new(
                Section::Header,
                Some(16),
                format!(
                    "header data start {hd} differs from POINT:DATA_START {p}; using the header"
                ),
            ));
            Ok(hd)
        }
        (hd, _) => {
            if hd == pb {
                warnings.push(Warning::new(
                    Section::Header,
                    Some(16),
                    "data start is the parameter section's block",
                ));
            }
            Ok(hd)
        }
    }
}

/// Work out the data layout from the header (which describes what is stored) and check it
/// against the parameters (which say what it means).
fn layout(
    h: &Header,
    ps: &Parameters,
    available: usize,
    warnings: &mut Vec<Warning>,
) -> Result<Layout> {
    let w = |msg: String| Warning::new(Section::Parameters, None, msg);
    let points = h.point_count as usize;
    if let Some(used) = ps.get_u16("POINT", "USED") {
        if used as usize != points {
            warnings.push(w(format!(
                "POINT:USED is {used} but the header stores {points} points per frame"
            )));
        }
    }
    let (scale, pscale) = point_scale(h, ps, warnings);
    let (channels, spf) = analog_layout(h, ps, points, scale, available, warnings);
    let unsigned_analog = ps
        .get_strings("ANALOG", "FORMAT")
        .and_then(|v| v.into_iter().next())
        .is_some_and(|f| f.trim().eq_ignore_ascii_case("UNSIGNED"));

    let mut l = Layout {
        points,
        analog_channels: channels,
        analog_samples_per_frame: spf,
        frames: 0,
        float: scale < 0.0,
        unsigned_analog,
        point_scale: scale.abs(),
    };
    // A scale sign that contradicts the file size is a vendor slip: trust the size.
    l.frames = frame_count(h, ps, warnings);
    let fits = |l: &Layout| l.data_bytes() <= available;
    if !fits(&l) {
        let mut other = l;
        other.float = !l.float;
        if fits(&other) && pscale.is_some_and(|s| (s < 0.0) != (h.scale < 0.0)) {
            warnings.push(w(format!(
                "the {} number format implied by POINT:SCALE does not fit the file; using the header's",
                if l.float { "float" } else { "integer" }
            )));
            l = other;
        }
    }
    Ok(l)
}

/// Number format and point scale: the sign of POINT:SCALE, else of the header's scale
/// (the scale used, and POINT:SCALE as the file has it).
fn point_scale(h: &Header, ps: &Parameters, warnings: &mut Vec<Warning>) -> (f32, Option<f32>) {
    let hscale = h.scale;
    let pscale = ps.get_f32("POINT", "SCALE");
    let scale = match pscale {
        Some(s) if s != 0.0 => {
            if (s < 0.0) != (hscale < 0.0) || (s.abs() - hscale.abs()).abs() > 1e-6 * s.abs() {
                warnings.push(Warning::new(
                    Section::Header,
                    Some(12),
                    format!(
                        "header scale {hscale} differs from POINT:SCALE {s}; using POINT:SCALE"
                    ),
                ));
            }
            s
        }
        _ => hscale,
    };
    (scale, pscale)
}

/// Analog layout: the header's word count and samples per frame, read as the candidate
/// reading whose size fills the file (channels, samples per frame).
fn analog_layout(
    h: &Header,
    ps: &Parameters,
    points: usize,
    scale: f32,
    available: usize,
    warnings: &mut Vec<Warning>,
) -> (usize, usize) {
    let w = |msg: String| Warning::new(Section::Parameters, None, msg);
    let words = h.analog_per_frame as usize;
    let mut spf = h.analog_samples_per_frame as usize;
    let used = ps.get_u16("ANALOG", "USED").map(|u| u as usize);
    let point_rate = ps
        .get_f32("POINT", "RATE")
        .filter(|r| *r > 0.0)
        .unwrap_or(h.frame_rate);
    if words > 0 && spf == 0 {
        if let Some(ar) = ps.get_f32("ANALOG", "RATE") {
            if point_rate > 0.0 {
                spf = (ar / point_rate).round() as usize;
            }
        }
        warnings.push(w(format!(
            "header gives 0 analog samples per frame; using {spf} from ANALOG:RATE"
        )));
    }
    let candidates = analog_readings(words, spf, used);
    let frames_guess = frame_count(h, ps, &mut Vec::new());
    let word_bytes = if scale < 0.0 { 4 } else { 2 };
    let size = |c: usize, s: usize| {
        c.saturating_mul(s)
            .saturating_add(4 * points)
            .saturating_mul(word_bytes)
            .saturating_mul(frames_guess)
    };
    let pick = candidates
        .iter()
        .position(|&(c, s, _)| size(c, s) <= available && available - size(c, s) < BLOCK)
        .or_else(|| {
            candidates
                .iter()
                .position(|&(c, s, _)| size(c, s) <= available)
        })
        .unwrap_or(0);
    let (channels, picked_spf, why) = candidates[pick];
    if !why.is_empty() {
        warnings.push(w(format!(
            "header says {words} analog words and {spf} samples per frame; reading {channels} channels × {picked_spf} samples ({why})"
        )));
    }
    spf = picked_spf;
    if let Some(u) = used {
        if words > 0 && u != channels {
            warnings.push(w(format!(
                "ANALOG:USED is {u} but the data holds {channels} channels"
            )));
        }
    }
    (channels, spf)
}

/// Candidate readings of the stored analog words (channels, samples per frame, the slip it
/// reads around), most standard first; the one whose size fills the file (to within its last
/// block) wins, so vendor slips in word 3 or 10 are read around (and reported).
fn analog_readings(
    words: usize,
    spf: usize,
    used: Option<usize>,
) -> Vec<(usize, usize, &'static str)> {
    let mut candidates: Vec<(usize, usize, &str)> = Vec::new();
    if words == 0 {
        candidates.push((0, spf.max(1), ""));
    } else {
        if spf > 0 && words.is_multiple_of(spf) {
            candidates.push((words / spf, spf, ""));
        }
        if spf > 1 {
            candidates.push((
                words,
                spf,
                "header word 3 holds the channel count, not channels × samples per frame",
            ));
        }
        if let Some(u) = used.filter(|&u| u > 0) {
            let s = spf.max(1);
            candidates.push((
                u,
                s,
                "analog words per frame follow ANALOG:USED × samples per frame",
            ));
        }
        candidates.push((
            words,
            1,
            "analog words read as one sample per channel per frame",
        ));
    }
    candidates
}

/// Number of frames: the header's first/last frame, or the long-trial parameters when the
/// header cannot hold the count (TRIAL:ACTUAL_START_FIELD/END_FIELD, POINT:LONG_FRAMES,
/// POINT:FRAMES read as unsigned).
fn frame_count(h: &Header, ps: &Parameters, warnings: &mut Vec<Warning>) -> usize {
    let first = h.first_frame as usize;
    let last = h.last_frame as usize;
    let from_header = if last >= first && !(first == 0 && last == 0) {
        last - first + 1
    } else {
        0
    };
    let field = |name: &str| -> Option<usize> {
        let p = ps.get("TRIAL", name)?;
        let v = p.as_u16s();
        match v.as_slice() {
            [lo, hi, ..] => Some(*lo as usize + ((*hi as usize) << 16)),
            [lo] => Some(*lo as usize),
            [] => None,
        }
    };
    let from_trial = match (field("ACTUAL_START_FIELD"), field("ACTUAL_END_FIELD")) {
        (Some(s), Some(e)) if e >= s => Some(e - s + 1),
        _ => None,
    };
    let long = ps
        .get("POINT", "LONG_FRAMES")
        .and_then(|p| p.as_f32s().first().copied())
        .filter(|v| *v > 0.0)
        .map(|v| v as usize);
    let frames_param = ps.get_u16("POINT", "FRAMES").map(|v| v as usize);
    // The header caps at 65535 frames: a larger count from parameters wins.
    let candidates = [from_trial, long, frames_param];
    let best_param = candidates.iter().flatten().copied().max();
    match best_param {
        Some(n) if n > from_header && (from_header == 0 || last == 65535 || n > 65535) => {
            if n > 65535 || from_header == 0 {
                if from_header == 0 && n <= 65535 {
                    warnings.push(Warning::new(
                        Section::Header,
                        Some(6),
                        format!("header frame range {first}–{last} is empty; using {n} frames from the parameters"),
                    ));
                }
                n
            } else {
                from_header
            }
        }
        _ => from_header,
    }
}
