//! Parse arbitrary text as BVH; what parses must write and parse back the same.
//! `cargo +nightly fuzz run bvh_parse` (see fuzz/README.md).
#![no_main]

#[path = "../../crates/bvh/tests/common/fuzz_check.rs"]
mod fuzz_check;

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    fuzz_check::check(data);
});
