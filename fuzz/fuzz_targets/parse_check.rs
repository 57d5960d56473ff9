//! Fuzz target `parse_check`: see `cellc::fuzzing::parse_check` (the body is shared with the corpus
//! replay in `tests/fuzz_corpus.rs`).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| cellc::fuzzing::parse_check(data));
