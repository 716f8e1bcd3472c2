//! Fuzz target: see `spraysim_fuzz::mesh`.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| spraysim_fuzz::mesh(data));
