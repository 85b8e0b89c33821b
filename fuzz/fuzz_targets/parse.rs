//! Parse arbitrary bytes; for those that read, rewrite and convert round trips.
//! `cargo +nightly fuzz run parse` (see fuzz/README.md).
#![no_main]

#[path = "../../crates/c3d/tests/common/fuzz_check.rs"]
mod fuzz_check;

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    fuzz_check::check(data);
});
