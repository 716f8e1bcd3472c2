//! Fuzz target: see `spraysim_fuzz::profile`.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| spraysim_fuzz::profile(data));
