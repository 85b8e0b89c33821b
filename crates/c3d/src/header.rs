//! The header block (the file's first 512 bytes). Word numbers are 1-based 16-bit words, as
//! in the C3D manual.
//!
//! The raw block is kept by the reader; [`Header::encode_into`] writes only the fields whose
//! values differ from the ones read, so reserved words and vendor bytes survive a rewrite.

use crate::error::{Error, Result, Section};
use crate::processor::Processor;
use serde::Serialize;

/// Size of a C3D block in bytes.
pub const BLOCK: usize = 512;
/// Key in word 148 and 150 that marks the label/range section and 4-character event labels.
pub const KEY_12345: u16 = 12345;
/// The header holds at most 18 events.
pub const MAX_HEADER_EVENTS: usize = 18;

/// The header block's fields.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Header {
    /// Byte 1: block number of the parameter section (usually 2).
    pub parameter_block: u8,
    /// Byte 2: 0x50 in every C3D file.
    pub key: u8,
    /// Word 2: 3D points per frame.
    pub point_count: u16,
    /// Word 3: analog measurements per 3D frame (channels × samples per frame).
    pub analog_per_frame: u16,
    /// Word 4: first frame number (1-based).
    pub first_frame: u16,
    /// Word 5: last frame number (65535 at most; longer trials use parameters).
    pub last_frame: u16,
    /// Word 6: maximum interpolation gap in frames.
    pub max_gap: u16,
    /// Words 7–8: POINT:SCALE; negative means floating-point data.
    pub scale: f32,
    /// Word 9: first block of the data section.
    pub data_start: u16,
    /// Word 10: analog samples per 3D frame.
    pub analog_samples_per_frame: u16,
    /// Words 11–12: 3D frame rate in Hz.
    pub frame_rate: f32,
    /// Word 148: 12345 when a label/range section is present.
    pub label_range_key: u16,
    /// Word 149: first block of the label/range section.
    pub label_range_block: u16,
    /// Word 150: 12345 when event labels are 4 characters.
    pub event_label_key: u16,
    /// Word 151: number of header events (0–18).
    pub event_count: u16,
    /// Words 153–188: event times in seconds.
    pub event_times: [f32; MAX_HEADER_EVENTS],
    /// Words 189–197: event display flags (0 = on, 1 = off), one byte each.
    pub event_display: [u8; MAX_HEADER_EVENTS],
    /// Words 199–234: event labels, 4 bytes each.
    pub event_labels: [[u8; 4]; MAX_HEADER_EVENTS],
}

/// One event stored in the header.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct HeaderEvent {
    pub label: String,
    pub time: f32,
    /// True when the display flag is 0 (the manual's "on").
    pub displayed: bool,
}

/// A header word and how to get it from a [`Header`].
type WordField = fn(&Header) -> u16;

const fn word(n: usize) -> usize {
    (n - 1) * 2
}

impl Header {
    /// Decode the header from the file's first block.
    pub fn parse(block: &[u8], p: Processor) -> Result<Header> {
        if block.len() < BLOCK {
            return Err(Error::malformed(
                Section::Header,
                block.len(),
                format!(
                    "file is {} bytes, shorter than the 512-byte header",
                    block.len()
                ),
            ));
        }
        let w = |n: usize| p.read_i16([block[word(n)], block[word(n) + 1]]) as u16;
        let f = |n: usize| {
            let o = word(n);
            p.read_f32([block[o], block[o + 1], block[o + 2], block[o + 3]])
        };
        let mut event_times = [0f32; MAX_HEADER_EVENTS];
        let mut event_display = [0u8; MAX_HEADER_EVENTS];
        let mut event_labels = [[0u8; 4]; MAX_HEADER_EVENTS];
        for i in 0..MAX_HEADER_EVENTS {
            event_times[i] = f(153 + 2 * i);
            event_display[i] = block[word(189) + i];
            let o = word(199) + 4 * i;
            event_labels[i].copy_from_slice(&block[o..o + 4]);
        }
        Ok(Header {
            parameter_block: block[0],
            key: block[1],
            point_count: w(2),
            analog_per_frame: w(3),
            first_frame: w(4),
            last_frame: w(5),
            max_gap: w(6),
            scale: f(7),
            data_start: w(9),
            analog_samples_per_frame: w(10),
            frame_rate: f(11),
            label_range_key: w(148),
            label_range_block: w(149),
            event_label_key: w(150),
            event_count: w(151),
            event_times,
            event_display,
            event_labels,
        })
    }

    /// Write the fields into `block`. With `original`, only fields that differ from it are
    /// written (bitwise for floats), so untouched bytes stay exactly as read.
    pub fn encode_into(&self, block: &mut [u8], p: Processor, original: Option<&Header>) {
        let put_w = |block: &mut [u8], n: usize, v: u16| {
            block[word(n)..word(n) + 2].copy_from_slice(&p.write_i16(v as i16));
        };
        let put_f = |block: &mut [u8], n: usize, v: f32| {
            block[word(n)..word(n) + 4].copy_from_slice(&p.write_f32(v));
        };
        let o = original;
        let changed_u8 = |get: fn(&Header) -> u8| o.is_none_or(|o| get(o) != get(self));
        let changed_w = |get: fn(&Header) -> u16| o.is_none_or(|o| get(o) != get(self));
        let changed_f =
            |get: fn(&Header) -> f32| o.is_none_or(|o| get(o).to_bits() != get(self).to_bits());
        if changed_u8(|h| h.parameter_block) {
            block[0] = self.parameter_block;
        }
        if changed_u8(|h| h.key) {
            block[1] = self.key;
        }
        let words: [(usize, WordField); 11] = [
            (2, |h| h.point_count),
            (3, |h| h.analog_per_frame),
            (4, |h| h.first_frame),
            (5, |h| h.last_frame),
            (6, |h| h.max_gap),
            (9, |h| h.data_start),
            (10, |h| h.analog_samples_per_frame),
            (148, |h| h.label_range_key),
            (149, |h| h.label_range_block),
            (150, |h| h.event_label_key),
            (151, |h| h.event_count),
        ];
        for (n, get) in words {
            if changed_w(get) {
                put_w(block, n, get(self));
            }
        }
        if changed_f(|h| h.scale) {
            put_f(block, 7, self.scale);
        }
        if changed_f(|h| h.frame_rate) {
            put_f(block, 11, self.frame_rate);
        }
        for i in 0..MAX_HEADER_EVENTS {
            if o.is_none_or(|o| o.event_times[i].to_bits() != self.event_times[i].to_bits()) {
                put_f(block, 153 + 2 * i, self.event_times[i]);
            }
            if o.is_none_or(|o| o.event_display[i] != self.event_display[i]) {
                block[word(189) + i] = self.event_display[i];
            }
            if o.is_none_or(|o| o.event_labels[i] != self.event_labels[i]) {
                let at = word(199) + 4 * i;
                block[at..at + 4].copy_from_slice(&self.event_labels[i]);
            }
        }
    }

    /// The events the header declares (at most 18).
    pub fn events(&self) -> Vec<HeaderEvent> {
        let n = (self.event_count as usize).min(MAX_HEADER_EVENTS);
        (0..n)
            .map(|i| HeaderEvent {
                label: crate::text::latin1(&self.event_labels[i])
                    .trim_end_matches(['\0', ' '])
                    .to_string(),
                time: self.event_times[i],
                displayed: self.event_display[i] == 0,
            })
            .collect()
    }

    /// A blank header for a new file.
    pub fn new() -> Header {
        Header {
            parameter_block: 2,
            key: 0x50,
            point_count: 0,
            analog_per_frame: 0,
            first_frame: 1,
            last_frame: 0,
            max_gap: 0,
            scale: -1.0,
            data_start: 0,
            analog_samples_per_frame: 0,
            frame_rate: 0.0,
            label_range_key: 0,
            label_range_block: 0,
            event_label_key: KEY_12345,
            event_count: 0,
            event_times: [0.0; MAX_HEADER_EVENTS],
            event_display: [0; MAX_HEADER_EVENTS],
            event_labels: [[b' '; 4]; MAX_HEADER_EVENTS],
        }
    }
}

impl Default for Header {
    fn default() -> Self {
        Header::new()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn encode_parse_round_trip_all_processors() {
        let mut h = Header::new();
        h.point_count = 26;
        h.analog_per_frame = 64;
        h.last_frame = 450;
        h.scale = 0.083333;
        h.data_start = 11;
        h.analog_samples_per_frame = 4;
        h.frame_rate = 50.0;
        h.event_count = 1;
        h.event_times[0] = 1.25;
        h.event_labels[0] = *b"RHS ";
        for p in [Processor::Intel, Processor::Dec, Processor::Sgi] {
            let mut block = vec![0u8; BLOCK];
            h.encode_into(&mut block, p, None);
            let back = Header::parse(&block, p).unwrap();
            assert_eq!(back, h, "{p:?}");
            assert_eq!(back.events()[0].label, "RHS");
        }
    }

    #[test]
    fn short_block_is_an_error() {
        let e = Header::parse(&[0u8; 100], Processor::Intel).unwrap_err();
        assert!(
            e.to_string().contains("shorter than the 512-byte header"),
            "{e}"
        );
    }
}
