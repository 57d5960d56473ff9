//! Parsing the `world` and `task` items: the tree they give, the words that became
//! reserved, and the syntax errors of a broken line (reported line by line, like an
//! object's members).

use cellc_lang::ast::*;
use cellc_lang::{parse, FileId};

/// The items of `body` wrapped in a cell, which must parse without diagnostics.
fn items(body: &str) -> Vec<Item> {
    let text = format!("cell c {{\n{body}\n}}\n");
    let parsed = parse(FileId(0), &text);
    assert!(
        parsed.diagnostics.is_empty(),
        "unexpected diagnostics {:#?}\n--- text ---\n{text}",
        parsed.diagnostics
    );
    parsed.file.expect("a tree").items
}

/// The messages and the text under the primary label of each syntax error of `body`.
fn errors(body: &str) -> Vec<(String, String)> {
    let text = format!("cell c {{\n{body}\n}}\n");
    let parsed = parse(FileId(0), &text);
    parsed
        .diagnostics
        .iter()
        .map(|d| {
            let label = d.primary_label().expect("a primary label");
            let under = &text[label.span.start as usize..label.span.end as usize];
            (d.message.clone(), under.to_string())
        })
        .collect()
}

fn holder(q: &Qualified) -> String {
    match &q.object {
        Some(h) => format!("{}.{}", h.text, q.name.text),
        None => q.name.text.clone(),
    }
}

#[test]
fn a_world_has_one_line_per_object_in_every_form() {
    let items = items(
        "  world {
    cylinder: table at (0.45, 0.45, 1.0)
    colander: table at (0.4, 0.45, 0.95) rpy (0, 0, 90)
    ball: table.lying in ws_left_table
    pitcher: left.top
    box: `the arm`
  }",
    );
    let [Item::World(world)] = items.as_slice() else {
        panic!("one world item: {items:#?}");
    };
    let lines: Vec<(&str, String, String)> = world
        .entries
        .iter()
        .map(|e| {
            let form = match &e.placement {
                WorldPlacement::Placed(RequestPlacement {
                    place: PlaceSpec::In(w),
                    ..
                }) => format!("in {}", w.text),
                WorldPlacement::Placed(RequestPlacement {
                    place: PlaceSpec::At(pose),
                    ..
                }) => format!("at, rotated: {}", pose.rotation.is_some()),
                WorldPlacement::Bare(_) => "bare".to_string(),
            };
            (e.object.text.as_str(), holder(e.placement.holder()), form)
        })
        .collect();
    let expected = [
        ("cylinder", "table", "at, rotated: false"),
        ("colander", "table", "at, rotated: true"),
        ("ball", "table.lying", "in ws_left_table"),
        ("pitcher", "left.top", "bare"),
        ("box", "the arm", "bare"),
    ]
    .map(|(o, h, f)| (o, h.to_string(), f.to_string()));
    assert_eq!(lines, expected);
}

#[test]
fn entry_and_step_spans_cover_their_lines_only() {
    let text = "cell c {\n  world {\n    ball: left.top // held\n  }\n  task t {\n    ball to table in w1\n  }\n}\n";
    let parsed = parse(FileId(0), text);
    assert!(parsed.diagnostics.is_empty(), "{:#?}", parsed.diagnostics);
    let file = parsed.file.expect("a tree");
    let span_text = |s: cellc_lang::Span| &text[s.start as usize..s.end as usize];
    let Item::World(world) = &file.items[0] else {
        panic!("a world first");
    };
    assert_eq!(span_text(world.entries[0].span), "ball: left.top");
    assert_eq!(span_text(world.entries[0].placement.span()), "left.top");
    assert!(span_text(world.span).starts_with("world {") && span_text(world.span).ends_with('}'));
    let Item::Task(task) = &file.items[1] else {
        panic!("a task second");
    };
    assert_eq!(task.name.text, "t");
    assert_eq!(span_text(task.steps[0].span), "ball to table in w1");
    assert_eq!(span_text(task.steps[0].to.span), "table in w1");
}

#[test]
fn a_task_lists_its_steps_in_order() {
    let items = items(
        "  task clear_table {
    cylinder to bin in ws_right_bin
    colander to table at (0.4, -0.3, 0.95)
    ball to right.power at (0.4, -0.3, 1.1) quat (1, 0, 0, 0)
  }
  task nothing_yet {}",
    );
    let [Item::Task(clear), Item::Task(empty)] = items.as_slice() else {
        panic!("two tasks: {items:#?}");
    };
    assert_eq!(clear.name.text, "clear_table");
    let steps: Vec<(&str, String)> = clear
        .steps
        .iter()
        .map(|s| (s.object.text.as_str(), holder(&s.to.holder)))
        .collect();
    assert_eq!(
        steps,
        [
            ("cylinder", "bin".to_string()),
            ("colander", "table".to_string()),
            ("ball", "right.power".to_string())
        ]
    );
    // An empty task is grammatical; the compiler refuses it with its own code.
    assert!(empty.steps.is_empty());
}

/// `to` stays an ordinary name (requests and tasks use it after a name, where no name can
/// follow), and an object may be called `to`.
#[test]
fn to_is_still_a_name() {
    let items = items(
        "  workspace to
  task t { to to table in to }
  request r: to from table in to to table in to",
    );
    let Item::Task(task) = &items[1] else {
        panic!("a task: {items:#?}");
    };
    assert_eq!(task.steps[0].object.text, "to");
    let Item::Request(request) = &items[2] else {
        panic!("a request: {items:#?}");
    };
    assert_eq!(request.object.text, "to");
}

#[test]
fn world_and_task_are_reserved_and_may_be_quoted() {
    let items = items(
        "  workspace `world`
  object `task` {}
  world { `task`: table in `world` }",
    );
    assert_eq!(items.len(), 3);
    for word in ["world", "task"] {
        let found = errors(&format!("  workspace {word}"));
        assert_eq!(found.len(), 1, "{word}: {found:?}");
        assert!(found[0].0.contains("a name"), "{word}: {found:?}");
    }
    let text = "cell c {\n  workspace task\n}\n";
    let parsed = parse(FileId(0), text);
    assert_eq!(
        parsed.diagnostics[0].help.as_deref(),
        Some("`task` is a reserved word: write `` `task` `` to use it as a name")
    );
}

/// A broken line is reported where it breaks, and the lines around it still parse.
#[test]
fn broken_lines_are_reported_one_by_one() {
    let found = errors(
        "  world {
    cylinder table in w1
    ball: table in w1
    box: table at (0, 0)
  }
  task t {
    ball bin in w2
    box to table in w1
    ball to table in
  }",
    );
    let found: Vec<(&str, &str)> = found
        .iter()
        .map(|(m, u)| (m.as_str(), u.as_str()))
        .collect();
    assert_eq!(
        found,
        [
            ("expected `:`", "table"),
            (
                "expected a unit (`m`, `cm`, `mm`, `deg` or `rad`) or `,`",
                ")"
            ),
            ("expected `to`", "bin"),
            ("expected a name", "}"),
        ]
    );
    // A step without `in`/`at` is a syntax error: only the world has bare placements.
    let found = errors("  task t { ball to table }");
    assert_eq!(found.len(), 1, "{found:#?}");
    assert_eq!(found[0].0, "expected `at` or `in`", "{found:#?}");
}
