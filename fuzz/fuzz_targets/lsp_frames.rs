//! Fuzz target `lsp_frames`: see `cellc::fuzzing::lsp_frames` (the body is shared with the
//! corpus replay in `tests/fuzz_corpus.rs`).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| cellc::fuzzing::lsp_frames(data));
