//! Processor formats: how 16-bit integers and 32-bit floats are laid out in bytes.
//!
//! Each format is a zero-sized [`Codec`]; the data decoders are generic over it and chosen once
//! per file (see [`Processor::dispatch`]), so no sample pays for a format branch.

use serde::Serialize;

/// The processor type stored in byte 4 of the parameter section (83 + 1/2/3).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Processor {
    /// Little-endian integers, IEEE floats.
    Intel,
    /// Little-endian integers, VAX F-floating floats.
    Dec,
    /// SGI/MIPS: big-endian integers and IEEE floats.
    Sgi,
}

impl Processor {
    pub fn from_byte(b: u8) -> Option<Self> {
        match b {
            84 => Some(Processor::Intel),
            85 => Some(Processor::Dec),
            86 => Some(Processor::Sgi),
            _ => None,
        }
    }

    pub fn byte(self) -> u8 {
        match self {
            Processor::Intel => 84,
            Processor::Dec => 85,
            Processor::Sgi => 86,
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            Processor::Intel => "Intel",
            Processor::Dec => "DEC",
            Processor::Sgi => "SGI/MIPS",
        }
    }

    pub fn parse_name(s: &str) -> Option<Self> {
        match s.to_ascii_lowercase().as_str() {
            "intel" | "pc" => Some(Processor::Intel),
            "dec" | "vax" => Some(Processor::Dec),
            "sgi" | "mips" => Some(Processor::Sgi),
            _ => None,
        }
    }

    /// Run `f` with the codec of this processor, monomorphised.
    pub(crate) fn dispatch<R>(self, f: impl CodecFn<R>) -> R {
        match self {
            Processor::Intel => f.call::<Intel>(),
            Processor::Dec => f.call::<Dec>(),
            Processor::Sgi => f.call::<Sgi>(),
        }
    }

    pub fn read_i16(self, b: [u8; 2]) -> i16 {
        match self {
            Processor::Intel => Intel::read_i16(b),
            Processor::Dec => Dec::read_i16(b),
            Processor::Sgi => Sgi::read_i16(b),
        }
    }

    pub fn write_i16(self, v: i16) -> [u8; 2] {
        match self {
            Processor::Intel => Intel::write_i16(v),
            Processor::Dec => Dec::write_i16(v),
            Processor::Sgi => Sgi::write_i16(v),
        }
    }

    pub fn read_f32(self, b: [u8; 4]) -> f32 {
        match self {
            Processor::Intel => Intel::read_f32(b),
            Processor::Dec => Dec::read_f32(b),
            Processor::Sgi => Sgi::read_f32(b),
        }
    }

    pub fn write_f32(self, v: f32) -> [u8; 4] {
        match self {
            Processor::Intel => Intel::write_f32(v),
            Processor::Dec => Dec::write_f32(v),
            Processor::Sgi => Sgi::write_f32(v),
        }
    }
}

/// A generic function over codecs (Rust has no generic closures).
pub(crate) trait CodecFn<R> {
    fn call<C: Codec>(self) -> R;
}

/// Word encoding of one processor format.
pub trait Codec: Copy + 'static {
    fn read_i16(b: [u8; 2]) -> i16;
    fn write_i16(v: i16) -> [u8; 2];
    fn read_f32(b: [u8; 4]) -> f32;
    fn write_f32(v: f32) -> [u8; 4];
}

#[derive(Debug, Clone, Copy)]
pub struct Intel;
#[derive(Debug, Clone, Copy)]
pub struct Dec;
#[derive(Debug, Clone, Copy)]
pub struct Sgi;

/// A codec storing integers and IEEE floats in one byte order: Intel's (little-endian) and
/// SGI's (big-endian) differ only in that order, so one definition serves both.
macro_rules! ieee_codec {
    ($codec:ty, $from:ident, $to:ident) => {
        impl Codec for $codec {
            #[inline(always)]
            fn read_i16(b: [u8; 2]) -> i16 {
                i16::$from(b)
            }
            #[inline(always)]
            fn write_i16(v: i16) -> [u8; 2] {
                v.$to()
            }
            #[inline(always)]
            fn read_f32(b: [u8; 4]) -> f32 {
                f32::$from(b)
            }
            #[inline(always)]
            fn write_f32(v: f32) -> [u8; 4] {
                v.$to()
            }
        }
    };
}

ieee_codec!(Intel, from_le_bytes, to_le_bytes);
ieee_codec!(Sgi, from_be_bytes, to_be_bytes);

/// VAX F-floating: the two 16-bit halves are swapped relative to IEEE, the exponent bias is
/// 128 instead of 127 and the hidden bit stands for 0.5 — so the IEEE reading of the swapped
/// bytes is four times the value. An exponent of zero is zero (whatever the other bits).
/// Its integers are Intel's.
impl Codec for Dec {
    #[inline(always)]
    fn read_i16(b: [u8; 2]) -> i16 {
        Intel::read_i16(b)
    }
    #[inline(always)]
    fn write_i16(v: i16) -> [u8; 2] {
        Intel::write_i16(v)
    }
    #[inline(always)]
    fn read_f32(b: [u8; 4]) -> f32 {
        let word0 = u16::from_le_bytes([b[0], b[1]]);
        if word0 & 0x7f80 == 0 {
            return 0.0;
        }
        f32::from_le_bytes([b[2], b[3], b[0], b[1]]) / 4.0
    }
    #[inline(always)]
    fn write_f32(v: f32) -> [u8; 4] {
        if v == 0.0 || !v.is_finite() {
            // VAX has no infinities or NaN; zero is the only safe stand-in.
            return [0; 4];
        }
        let mut w = v * 4.0;
        if !w.is_finite() {
            w = f32::MAX.copysign(v);
        }
        if !w.is_normal() {
            return [0; 4];
        }
        let c = w.to_le_bytes();
        [c[2], c[3], c[0], c[1]]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dec_float_known_values() {
        // 1.0 in VAX F is 0x4080 0x0000 (exponent 129, fraction .1000…).
        assert_eq!(Dec::read_f32([0x80, 0x40, 0, 0]), 1.0);
        assert_eq!(Dec::write_f32(1.0), [0x80, 0x40, 0, 0]);
        // -2.5: sign 1, exponent 130, fraction .101 → 0xC120 0x0000.
        assert_eq!(Dec::read_f32([0x20, 0xC1, 0, 0]), -2.5);
        assert_eq!(Dec::write_f32(-2.5), [0x20, 0xC1, 0, 0]);
        assert_eq!(Dec::read_f32([0, 0, 0x12, 0x34]), 0.0);
    }

    #[test]
    fn every_codec_round_trips() {
        for v in [0.0f32, 1.0, -1.0, 0.083333, 1234.567, -9.81e5, 3.0e-30] {
            for p in [Processor::Intel, Processor::Dec, Processor::Sgi] {
                assert_eq!(p.read_f32(p.write_f32(v)), v, "{p:?} {v}");
            }
        }
        for v in [0i16, 1, -1, 12345, i16::MIN, i16::MAX] {
            for p in [Processor::Intel, Processor::Dec, Processor::Sgi] {
                assert_eq!(p.read_i16(p.write_i16(v)), v);
            }
        }
        assert_eq!(Sgi::write_i16(1), [0, 1]);
    }
}
