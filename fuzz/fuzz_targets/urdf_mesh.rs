//! Fuzz target `urdf_mesh`: see `cellc::fuzzing::urdf_mesh` (the body is shared with the corpus
//! replay in `tests/fuzz_corpus.rs`).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| cellc::fuzzing::urdf_mesh(data));
