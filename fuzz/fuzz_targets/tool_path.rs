//! Fuzz target: see `spraysim_fuzz::tool_path`.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| spraysim_fuzz::tool_path(data));
