//! libFuzzer target `hash_grid`; the body is shared with the CI smoke test.
#![no_main]

#[path = "../bodies.rs"]
mod bodies;

libfuzzer_sys::fuzz_target!(|data: &[u8]| bodies::hash_grid(data));
