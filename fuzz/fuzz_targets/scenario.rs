//! Fuzz target: see `spraysim_fuzz::scenario`.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| spraysim_fuzz::scenario(data));
