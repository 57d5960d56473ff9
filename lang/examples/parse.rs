fn main() {
    let path = std::env::args().nth(1).unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    let parsed = cellc_lang::parse(cellc_lang::FileId(0), &text);
    if std::env::args().nth(2).is_some() {
        println!("{:#?}", parsed.file);
    }
    for d in parsed.diagnostics {
        let l = d.primary_label().unwrap();
        println!(
            "{} {:?} [{}] {} ({}) | help: {:?}",
            d.code,
            l.span,
            &text[l.span.range()],
            d.message,
            l.message,
            d.help
        );
    }
}
