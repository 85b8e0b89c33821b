//! Byte strings in C3D files are 8-bit text; we map bytes to chars one to one (Latin-1) so that
//! any name or label converts back to exactly the bytes it came from.

/// Bytes to a string, one char per byte.
pub fn latin1(bytes: &[u8]) -> String {
    bytes.iter().map(|&b| b as char).collect()
}

/// A string back to bytes; chars above U+00FF become `?` (they cannot be stored).
pub fn to_latin1(s: &str) -> Vec<u8> {
    s.chars()
        .map(|c| if (c as u32) < 256 { c as u8 } else { b'?' })
        .collect()
}
