//! The grammar (`cell.pest`) as pest's parser type and its `Rule` enum: the one definition
//! that the parser (which runs the rules) and the phrases (which put each rule into words)
//! both use, so neither depends on the other for it.

#[derive(pest_derive::Parser)]
#[grammar = "cell.pest"]
pub(crate) struct CellParser;
