//! Random layouts of the shipped cells round trip, and a source that does not match the
//! tree never makes the formatter panic or lose a comment.

use cellc_lang::{format, parse, FileId};
use proptest::prelude::*;

use super::{all_constructs, check, comments, fig3, parse_and_format};

/// Cuts a cell into tokens: comments and strings whole, `(` `)` `,` `:` `=` `{` `}` alone,
/// anything else (with backtick-quoted names inside it) split at white space.
fn tokens(text: &str) -> Vec<String> {
    const PUNCTUATION: &[char] = &['(', ')', ',', ':', '=', '{', '}'];
    let mut tokens = Vec::new();
    let mut chars = text.char_indices().peekable();
    while let Some(&(at, c)) = chars.peek() {
        if c.is_whitespace() {
            chars.next();
        } else if text[at..].starts_with("//") {
            let end = text[at..].find('\n').map_or(text.len(), |e| at + e);
            tokens.push(text[at..end].to_string());
            while chars.peek().is_some_and(|&(i, _)| i < end) {
                chars.next();
            }
        } else if c == '"' {
            chars.next();
            let mut token = String::from('"');
            let mut escaped = false;
            for (_, c) in chars.by_ref() {
                token.push(c);
                if c == '"' && !escaped {
                    break;
                }
                escaped = c == '\\' && !escaped;
            }
            tokens.push(token);
        } else if PUNCTUATION.contains(&c) {
            chars.next();
            tokens.push(c.to_string());
        } else {
            let mut token = String::new();
            let mut quoted = false;
            while let Some(&(_, c)) = chars.peek() {
                if !quoted && (c.is_whitespace() || c == '"' || PUNCTUATION.contains(&c)) {
                    break;
                }
                quoted ^= c == '`';
                token.push(c);
                chars.next();
            }
            tokens.push(token);
        }
    }
    tokens
}

/// True when `token` is a unit written after the number `before`: only spaces may separate
/// them (a quantity is one token to the grammar).
fn is_unit_after_number(before: &str, token: &str) -> bool {
    let number = before
        .trim_start_matches('-')
        .starts_with(|c: char| c.is_ascii_digit());
    number && matches!(token, "m" | "cm" | "mm" | "deg" | "rad")
}

/// What may stand between two tokens; `#` becomes `<N>` with N unique in the file, so that
/// the test can tell the inserted comments apart.
const SEPARATORS: &[&str] = &[
    " ",
    "   ",
    "\t",
    "\n",
    "\n\n",
    "\n\n\n    ",
    " /* c# */ ",
    "/*c#*/",
    " // c#\n",
    "\n// c#\n\n",
    "\n  /* c#\n  more */\n",
    " /* c# */ // d#\n",
];

/// `text` with its tokens joined by the chosen separators, and how many comments that
/// inserted.
fn relayout(text: &str, choices: &[usize]) -> (String, usize) {
    let tokens = tokens(text);
    let mut out = String::new();
    let mut inserted = 0;
    for (i, token) in tokens.iter().enumerate() {
        out.push_str(token);
        let choice = choices.get(i).copied().unwrap_or(0);
        let mut separator = SEPARATORS[choice % SEPARATORS.len()].to_string();
        if tokens
            .get(i + 1)
            .is_some_and(|next| is_unit_after_number(token, next))
        {
            separator = " ".to_string();
        }
        if token.starts_with("//") && !separator.starts_with('\n') {
            // A line comment ends at its line: whatever follows goes on the next one.
            separator.insert(0, '\n');
        }
        while let Some(at) = separator.find('#') {
            inserted += 1;
            separator.replace_range(at..at + 1, &format!("<{inserted}>"));
        }
        out.push_str(&separator);
    }
    (out, inserted)
}

/// The separators that are plain white space give the original layout back token for
/// token, so the test of random layouts is known to start from the file itself.
#[test]
fn relayout_with_single_spaces_keeps_the_tree() {
    for text in [fig3(), all_constructs()] {
        let (spaced, inserted) = relayout(&text, &[]);
        assert_eq!(inserted, 0);
        let (original, _) = parse_and_format(&text, "original");
        let (respaced, _) = parse_and_format(&spaced, "single spaces");
        assert_eq!(original, respaced);
    }
}

proptest! {
    // No failure persistence: a failure prints the minimal input, to be kept as a case of
    // its own.
    #![proptest_config(ProptestConfig {
        cases: 128,
        failure_persistence: None,
        ..ProptestConfig::default()
    })]

    /// fig3.cell (and the all-constructs cell) with random white space, newlines and
    /// comments between tokens: same tree, same canonical text as a second format, every
    /// comment printed exactly once.
    #[test]
    fn random_layouts_round_trip(
        which in 0..2usize,
        choices in proptest::collection::vec(0..SEPARATORS.len(), 1000),
    ) {
        let original = if which == 0 { fig3() } else { all_constructs() };
        let (text, inserted) = relayout(&original, &choices);
        let formatted = check(&text, "random layout");
        // Same tree as the original file, not only as the shuffled text.
        let (original_tree, _) = parse_and_format(&original, "original");
        let (shuffled_tree, _) = parse_and_format(&text, "random layout");
        prop_assert_eq!(original_tree, shuffled_tree);
        for n in 1..=inserted {
            let count = formatted.matches(&format!("<{n}>")).count();
            prop_assert_eq!(count, 1, "comment <{}> not printed exactly once", n);
        }
    }
}

// ---- robustness ------------------------------------------------------------------------

proptest! {
    #![proptest_config(ProptestConfig {
        cases: 512,
        failure_persistence: None,
        ..ProptestConfig::default()
    })]

    /// `format` is only meant for a tree and the text it came from, but given any text it
    /// must still not panic, and must not drop the comments it finds in it.
    #[test]
    fn mismatched_source_never_panics(source in "[a-z0-9 /*\"`{}\n\\\\é]{0,300}") {
        let text = all_constructs();
        let parsed = parse(FileId(0), &text);
        let file = parsed.file.ok_or_else(|| TestCaseError::fail("no tree"))?;
        let formatted = format(&file, &source);
        for comment in comments(&source) {
            prop_assert!(formatted.contains(&comment), "{:?} lost", comment);
        }
    }
}
