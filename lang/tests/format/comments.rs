//! Comments in every position survive, once each, in order.

use super::{check, comments};

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
