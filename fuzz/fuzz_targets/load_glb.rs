//! libFuzzer target `load_glb`; the body is shared with the CI smoke test.
#![no_main]

#[path = "../bodies.rs"]
mod bodies;

libfuzzer_sys::fuzz_target!(|data: &[u8]| bodies::load_glb(data));
