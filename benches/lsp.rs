//! What an edit costs the language server (issue 15): `cells/vito.cell` open in the
//! editor, a keystroke (the cell's text alternates between two versions), and the
//! cell compiled again with its names and trees, as `cellc lsp` does after a change:
//! without the parse cache (every file parsed by the compiler and again for the trees
//! the requests read, as before the cache), with a fresh cache (every file parsed once,
//! the requests reading the compiler's trees), and with the server's warm cache (only
//! the edited cell parsed).

use std::str::FromStr;

use cellc::lsp::analysis::{Analysis, ParseCache, ReachCache};
use cellc::lsp::documents::Documents;
use cellc_compiler::load::{Fresh, Parser};
use cellc_compiler::CompileOptions;
use criterion::{criterion_group, criterion_main, Criterion};

fn benches(c: &mut Criterion) {
    let root = env!("CARGO_MANIFEST_DIR");
    let path = format!("{root}/cells/vito.cell");
    let text = std::fs::read_to_string(&path).expect("the shipped cell");
    let uri = lsp_types::Uri::from_str(&format!("file://{path}")).expect("a URI");
    let versions = [text.clone(), format!("{text}// edited\n")];
    let mut documents = Documents::default();
    let reach = ReachCache::default();
    let options = CompileOptions::default();
    let mut keystroke = 0usize;
    let mut edit = |documents: &mut Documents, trees: &ParseCache| {
        keystroke += 1;
        documents.open(
            uri.clone(),
            keystroke as i32,
            versions[keystroke % 2].clone(),
        );
        let overlay = documents.overlay();
        let analysis = Analysis::new(&overlay, (&reach, trees), &path, &options);
        assert!(!analysis.compilation.has_errors());
        std::hint::black_box(analysis.names().occurrences().len())
    };
    let warm = ParseCache::default();
    edit(&mut documents, &warm);
    let files = warm.misses.get();
    println!("lsp: vito.cell reads {files} cell files");
    c.bench_function("lsp/vito_edit_no_cache", |b| {
        let mut keystroke = 0usize;
        b.iter(|| {
            keystroke += 1;
            documents.open(
                uri.clone(),
                keystroke as i32,
                versions[keystroke % 2].clone(),
            );
            let overlay = documents.overlay();
            let compilation = cellc_driver::compile(&overlay, &path, &options);
            let trees: Vec<_> = compilation
                .sources
                .iter()
                .map(|(id, f)| Fresh.parse(id, &f.path, &f.text).file)
                .collect();
            std::hint::black_box((compilation.names.occurrences().len(), trees.len()))
        })
    });
    c.bench_function("lsp/vito_edit_every_file_parsed_once", |b| {
        b.iter(|| edit(&mut documents, &ParseCache::default()))
    });
    c.bench_function("lsp/vito_edit_parse_cache", |b| {
        b.iter(|| edit(&mut documents, &warm))
    });
}

criterion_group!(lsp_benches, benches);
criterion_main!(lsp_benches);
