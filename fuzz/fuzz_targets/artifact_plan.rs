//! Fuzz target `artifact_plan`: see `cellc::fuzzing::artifact_plan` (the body is shared with the corpus
//! replay in `tests/fuzz_corpus.rs`).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| cellc::fuzzing::artifact_plan(data));
