//! Fuzz target: see `spraysim_fuzz::checkpoint`.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| spraysim_fuzz::checkpoint(data));
