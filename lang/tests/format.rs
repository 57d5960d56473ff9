//! Tests of the canonical formatter: round trip (same tree up to spans), idempotence, and
//! that every comment survives exactly once, in order.

use std::path::{Path, PathBuf};

use cellc_lang::{format, parse, FileId};
use proptest::prelude::*;

// ---- helpers ---------------------------------------------------------------------------

/// A tree dump without spans: `Span`'s Debug is `@start..end`, and two layouts of one
/// file differ only there.
fn strip_spans(dump: &str) -> String {
    let bytes = dump.as_bytes();
    let mut out = String::with_capacity(dump.len());
    let mut i = 0;
    while i < bytes.len() {
        if bytes[i] == b'@' {
            if let Some(len) = span_len(&bytes[i + 1..]) {
                i += 1 + len;
                continue;
            }
        }
        // Copy one whole character (the dump may hold non-ASCII names and labels).
        let len = dump[i..].chars().next().map_or(1, char::len_utf8);
        out.push_str(&dump[i..i + len]);
        i += len;
    }
    out
}

/// Length of `<digits>..<digits>` at the start of `bytes`, if it is there.
fn span_len(bytes: &[u8]) -> Option<usize> {
    let digits = |from: usize| {
        bytes[from..]
            .iter()
            .take_while(|b| b.is_ascii_digit())
            .count()
    };
    let first = digits(0);
    if first == 0 || bytes.get(first..first + 2) != Some(b"..".as_slice()) {
        return None;
    }
    let second = digits(first + 2);
    (second > 0).then_some(first + 2 + second)
}

/// The comments of a text, in order, as the formatter prints them (line comments without
/// trailing white space). Written independently of the formatter's scanner, as an oracle;
/// like the grammar, it ends strings and quoted names at the end of their line.
fn comments(text: &str) -> Vec<String> {
    let mut found = Vec::new();
    let mut rest = text;
    loop {
        let next = rest.find(['/', '"', '`']);
        let Some(at) = next else { break };
        let tail = &rest[at..];
        if tail.starts_with("//") {
            let end = tail.find('\n').unwrap_or(tail.len());
            found.push(tail[..end].trim_end().to_string());
            rest = &tail[end..];
        } else if let Some(body) = tail.strip_prefix("/*") {
            let end = body.find("*/").map_or(tail.len(), |e| e + 4);
            found.push(tail[..end].to_string());
            rest = &tail[end..];
        } else if tail.starts_with('"') {
            let mut end = 1;
            let b = tail.as_bytes();
            while end < b.len() && b[end] != b'"' && b[end] != b'\n' {
                end += if b[end] == b'\\' { 2 } else { 1 };
            }
            rest = tail.get(end + 1..).unwrap_or("");
        } else if let Some(body) = tail.strip_prefix('`') {
            let end = body.find(['`', '\n']).map_or(tail.len(), |e| e + 2);
            rest = &tail[end..];
        } else {
            rest = &tail[1..];
        }
    }
    found
}

/// Parses `text`, which must have no syntax errors, and returns the tree dump without
/// spans together with the formatted text.
fn parse_and_format(text: &str, what: &str) -> (String, String) {
    let parsed = parse(FileId(0), text);
    assert!(
        parsed.diagnostics.is_empty(),
        "{what}: unexpected diagnostics {:#?}\n--- text ---\n{text}",
        parsed.diagnostics
    );
    let file = parsed
        .file
        .unwrap_or_else(|| panic!("{what}: no tree without diagnostics"));
    (strip_spans(&format!("{file:#?}")), format(&file, text))
}

/// Formats `text` and checks everything the formatter promises: the result parses to the
/// same tree (up to spans), formatting it again changes nothing, and it holds exactly the
/// comments of the input, in order. Returns the formatted text.
fn check(text: &str, what: &str) -> String {
    let (tree, formatted) = parse_and_format(text, what);
    let (tree_again, formatted_again) =
        parse_and_format(&formatted, &format!("{what} (formatted)"));
    assert_eq!(
        tree, tree_again,
        "{what}: formatting changed the tree\n--- formatted ---\n{formatted}"
    );
    assert_eq!(
        formatted, formatted_again,
        "{what}: formatting is not idempotent"
    );
    assert_eq!(
        comments(text),
        comments(&formatted),
        "{what}: comments lost, duplicated or reordered\n--- formatted ---\n{formatted}"
    );
    formatted
}

/// Every `*.cell` file under `dir`, recursively, sorted (an absent directory has none).
fn cell_files(dir: &Path) -> Vec<PathBuf> {
    let mut found = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(dir) = stack.pop() {
        let Ok(entries) = std::fs::read_dir(&dir) else {
            continue;
        };
        for entry in entries.flatten() {
            let path = entry.path();
            if path.is_dir() {
                stack.push(path);
            } else if path.extension().is_some_and(|e| e == "cell") {
                found.push(path);
            }
        }
    }
    found.sort();
    found
}

fn manifest_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn read(path: &Path) -> String {
    std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

fn all_constructs() -> String {
    read(&manifest_dir().join("tests/data/all_constructs.cell"))
}

fn fig3() -> String {
    read(&manifest_dir().join("../cells/fig3.cell"))
}

// ---- files in the repository -----------------------------------------------------------

#[test]
fn example_cells_round_trip() {
    let dir = manifest_dir().join("../cells");
    let files = cell_files(&dir);
    assert!(!files.is_empty(), "no cells found under {}", dir.display());
    for path in files {
        check(&read(&path), &path.display().to_string());
    }
}

#[test]
fn ui_cells_that_parse_round_trip() {
    for path in cell_files(&manifest_dir().join("../tests/ui")) {
        let text = read(&path);
        let parsed = parse(FileId(0), &text);
        if parsed.file.is_none() || !parsed.diagnostics.is_empty() {
            continue;
        }
        check(&text, &path.display().to_string());
    }
}

#[test]
fn all_constructs_round_trip() {
    check(&all_constructs(), "all_constructs.cell");
}

/// The test data is written in the canonical layout, so it is a fixed point.
#[test]
fn all_constructs_is_canonical() {
    let text = all_constructs();
    let (_, formatted) = parse_and_format(&text, "all_constructs.cell");
    assert_eq!(formatted, text);
}

/// The canonical layout is the one the hand-written example already uses.
#[test]
fn fig3_is_canonical() {
    let text = fig3();
    let (_, formatted) = parse_and_format(&text, "fig3.cell");
    assert_eq!(formatted, text);
}

// ---- comments --------------------------------------------------------------------------

#[test]
fn comments_in_every_position() {
    let input = r#"// top of file
/* a block
   comment at the top */

// after a blank line
cell c /* between name and brace */ { // after the cell's brace


  // leading, after blank lines that follow the brace
  units m // trailing on units
  /* leading block */ support s /* trailing block */ // and a line after it

  // leading before a blank line

  fixed t reaches /* inside the item */ w1, // inside, at a line end
    w2
  object o { // after the object's brace
    // leading inside the object
    shape box size (1, 1, 1) // trailing inside the object

    grasp g "// not a comment" by t /* trailing */
    // at the end of the object

  } // after the object's closing brace
  hand h {
    // before the only solid
    box size (1, 1, 1)
  }
  // at the end of the cell
} // after the last brace
// after everything
"#;
    let expected = r#"// top of file
/* a block
   comment at the top */

// after a blank line
/* between name and brace */
cell c { // after the cell's brace
  // leading, after blank lines that follow the brace
  units m // trailing on units
  /* leading block */
  support s /* trailing block */ // and a line after it

  // leading before a blank line

  /* inside the item */
  // inside, at a line end
  fixed t reaches w1, w2
  object o { // after the object's brace
    // leading inside the object
    shape box size (1, 1, 1) // trailing inside the object

    grasp g "// not a comment" by t /* trailing */
    // at the end of the object
  } // after the object's closing brace
  // before the only solid
  hand h { box size (1, 1, 1) }
  // at the end of the cell
} // after the last brace
// after everything
"#;
    let formatted = check(input, "comments");
    assert_eq!(formatted, expected);
    // Each comment exactly once (`check` compares the lists; this says it plainly).
    for comment in comments(input) {
        assert_eq!(
            formatted.matches(comment.as_str()).count(),
            1,
            "{comment:?} is not in the output exactly once"
        );
    }
}

#[test]
fn comments_in_blocks_without_members() {
    let input = "cell c {\n  object o { /* nothing yet */ }\n  object p {\n    // todo\n  }\n}\n";
    let expected =
        "cell c {\n  object o { /* nothing yet */\n  }\n  object p {\n    // todo\n  }\n}\n";
    assert_eq!(check(input, "empty blocks"), expected);
    let input = "// only comments\ncell c { // here\n  // and here\n}\n";
    assert_eq!(check(input, "empty cell"), input);
}

#[test]
fn comments_between_solids_of_a_hand() {
    let input = "cell c {\n  hand h { // two solids\n    // first\n    box size (1, 1, 1) // the palm\n\n    sphere radius 1 // a finger\n    // no more\n  }\n}\n";
    assert_eq!(check(input, "hand"), input);
}

#[test]
fn multi_line_block_comment_keeps_its_text() {
    let input =
        "cell c {\n  units m /* one\n     two */ support s\n  /*\n   * boxed\n   */\n  support t\n}\n";
    let expected =
        "cell c {\n  units m /* one\n     two */\n  support s\n  /*\n   * boxed\n   */\n  support t\n}\n";
    assert_eq!(check(input, "block comment"), expected);
}

#[test]
fn crlf_line_comments_lose_their_carriage_return() {
    let input = "cell c { // a\r\n  units m // b\r\n}\r\n";
    assert_eq!(check(input, "crlf"), "cell c { // a\n  units m // b\n}\n");
}

// ---- layout ----------------------------------------------------------------------------

#[test]
fn messy_layout_becomes_canonical() {
    let input = "cell   messy{units m,deg weights move 0.1,transition 2
workspace w1\"Left\"workspace    w2
  \"Right\" box center(0,0,0)size(1,1,1,)
adjacent w1 w2 fixed table reaches w1,w2, movable arm_1
reaches w2,
hand h{box size(1,2,3)at(0,0,1)rpy(90deg,0,0)sphere radius 2cm}
    robot r urdf \"r.urdf\" base b tip t arm a=r at(0,0,0)quat(1,0,0,0,)with h
surface s:k box center(0,0,0)size(1,1,0.1)reach height    5e-1 m
object o{shape cylinder radius 0.04height 0.2 symmetry about z order 4 grasp g1\"Top\"by arm_1 at(0,0,0.1)
rest r1 on table transition g1<->r1,o.g1, transition r1->g1}expect o:table in w1->arm_1.g1 in w2
expect w2 reached by at least 01 fixed expect no isolated states for o}";
    let expected = "cell messy {
  units m, deg
  weights move 0.1, transition 2
  workspace w1 \"Left\"
  workspace w2 \"Right\" box center (0, 0, 0) size (1, 1, 1)
  adjacent w1 w2
  fixed table reaches w1, w2
  movable arm_1 reaches w2
  hand h {
    box size (1, 2, 3) at (0, 0, 1) rpy (90 deg, 0, 0)
    sphere radius 2 cm
  }
  robot r urdf \"r.urdf\" base b tip t
  arm a = r at (0, 0, 0) quat (1, 0, 0, 0) with h
  surface s : k box center (0, 0, 0) size (1, 1, 0.1) reach height 5e-1 m
  object o {
    shape cylinder radius 0.04 height 0.2
    symmetry about z order 4
    grasp g1 \"Top\" by arm_1 at (0, 0, 0.1)
    rest r1 on table
    transition g1 <-> r1, o.g1
    transition r1 -> g1
  }
  expect o: table in w1 -> arm_1.g1 in w2
  expect w2 reached by at least 1 fixed
  expect no isolated states for o
}
";
    assert_eq!(check(input, "messy"), expected);
}

#[test]
fn blank_lines_collapse_to_one_and_never_touch_braces() {
    let input = "\n\ncell c {\n\n\n  units m\n\n\n\n  support s\n  support t\n\n  object o {\n\n    shape sphere radius 1\n\n\n    symmetry about x\n\n  }\n\n}\n\n";
    let expected = "cell c {\n  units m\n\n  support s\n  support t\n\n  object o {\n    shape sphere radius 1\n\n    symmetry about x\n  }\n}\n";
    assert_eq!(check(input, "blank lines"), expected);
}

#[test]
fn names_and_strings_are_quoted_and_escaped() {
    let input = "library `my lib` {\n  support `reach`\n  support `plain`\n  hand `two words` {}\n  include \"a \\\"b\\\" \\\\ c\\n\\td\"\n  object `o` { transition `a-b` <-> `o 2`.`c`, `object`.d }\n}\n";
    let expected = "library `my lib` {\n  support `reach`\n  support plain\n  hand `two words`\n  include \"a \\\"b\\\" \\\\ c\\n\\td\"\n  object o {\n    transition `a-b` <-> `o 2`.c, `object`.d\n  }\n}\n";
    assert_eq!(check(input, "names"), expected);
}

#[test]
fn empty_cell() {
    assert_eq!(check("cell   e {  }", "empty"), "cell e {}\n");
    assert_eq!(check("cell e {}\n// end\n", "empty"), "cell e {}\n// end\n");
}

// ---- random layouts ----------------------------------------------------------------------

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
    // No failure persistence: integration tests have no lib.rs for proptest to put its
    // regression file next to; a failure prints the minimal input instead.
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

// ---- the world and tasks -----------------------------------------------------------------

#[test]
fn world_and_task_blocks_are_laid_out_one_line_each() {
    let input = "cell c {
world{cylinder :table at(0.45,0.45,1.0)  ball:left.top
  box : table.lying in w1}
  task   clear{cylinder   to bin in w2 ball to table at (1,2,3) rpy(0,0,90)}
  task empty {   }
}
";
    let expected = "cell c {
  world {
    cylinder: table at (0.45, 0.45, 1.0)
    ball: left.top
    box: table.lying in w1
  }
  task clear {
    cylinder to bin in w2
    ball to table at (1, 2, 3) rpy (0, 0, 90)
  }
  task empty {}
}
";
    assert_eq!(check(input, "world and task"), expected);
}

#[test]
fn comments_in_world_and_task_blocks_stay() {
    let input = "cell c {
  // the start
  world { // where things are
    // the cylinder first
    cylinder: table in w1 // on the left

    ball: /* held */ left.top
    // nothing else
  } // end of the world
  task t { /* one step */
    cylinder to /* the bin */ bin in w2 // away
  }
}
";
    let expected = "cell c {
  // the start
  world { // where things are
    // the cylinder first
    cylinder: table in w1 // on the left

    /* held */
    ball: left.top
    // nothing else
  } // end of the world
  task t { /* one step */
    /* the bin */
    cylinder to bin in w2 // away
  }
}
";
    assert_eq!(check(input, "world comments"), expected);
}
