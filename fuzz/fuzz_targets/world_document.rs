//! Fuzz target `world_document`: see `cellc::fuzzing::world_document` (the body is shared
//! with the corpus replay in `tests/fuzz_corpus.rs`).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| cellc::fuzzing::world_document(data));
