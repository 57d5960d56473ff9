//! Fuzz target `format`: see `cellc::fuzzing::format` (the body is shared with the corpus
//! replay in `tests/fuzz_corpus.rs`).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| cellc::fuzzing::format(data));
