//! Mutated C3D files through `c3dfix repair` (in memory), then `info` on the output.
//! `cargo +nightly fuzz run repair` (see fuzz/README.md).
#![no_main]

#[path = "../../crates/cli/tests/common/repair_check.rs"]
mod repair_check;

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    repair_check::check(data);
});
