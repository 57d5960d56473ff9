//! Parsing and formatting the `limits` item: the tree it gives (a robot's line, a joint's,
//! MoveIt's file), its rate units, the formatter's round trip, and the syntax errors of
//! the shapes it refuses.

use cellc_lang::ast::*;
use cellc_lang::{format, parse, FileId};

fn parse_cell(body: &str) -> (String, Option<File>, Vec<String>) {
    let text = format!("cell c {{\n{body}\n}}\n");
    let parsed = parse(FileId(0), &text);
    let messages = parsed
        .diagnostics
        .iter()
        .map(|d| {
            let label = d.primary_label().expect("a primary label");
            let under = &text[label.span.start as usize..label.span.end as usize];
            format!("{} at `{under}`", d.message)
        })
        .collect();
    (text, parsed.file, messages)
}

fn limits(body: &str) -> Vec<LimitsItem> {
    let (_, file, errors) = parse_cell(body);
    assert!(errors.is_empty(), "unexpected errors {errors:#?}");
    file.expect("a tree")
        .items
        .into_iter()
        .filter_map(|i| match i {
            Item::Limits(l) => Some(l),
            _ => None,
        })
        .collect()
}

#[test]
fn a_robots_line_a_joints_line_and_a_file() {
    let items = limits(
        "limits lwr4 acceleration 4 rad/s2 jerk 40 rad/s3\n\
         limits lwr4.lwr_a1_joint velocity 1.5 rad/s acceleration 180 deg/s2\n\
         limits panda from \"config/joint_limits.yaml\" jerk 5000\n\
         limits belt.slide velocity 250 mm/s",
    );
    assert_eq!(items.len(), 4);
    assert_eq!(items[0].robot().text, "lwr4");
    assert!(items[0].joint().is_none());
    let kinds: Vec<LimitKind> = items[0].values.iter().map(|v| v.kind).collect();
    assert_eq!(kinds, [LimitKind::Acceleration, LimitKind::Jerk]);
    assert_eq!(
        items[0].values[0].rate.unit,
        Some(RateUnit {
            base: Unit::Rad,
            order: 2
        })
    );
    assert_eq!(items[0].values[1].rate.value, 40.0);
    assert_eq!(items[1].robot().text, "lwr4");
    assert_eq!(
        items[1].joint().map(|j| j.text.as_str()),
        Some("lwr_a1_joint")
    );
    assert_eq!(
        items[1].values[1].rate.unit,
        Some(RateUnit {
            base: Unit::Deg,
            order: 2
        })
    );
    assert_eq!(
        items[2].file.as_ref().map(|f| f.value.as_str()),
        Some("config/joint_limits.yaml")
    );
    assert_eq!(items[2].values[0].rate.unit, None);
    assert_eq!(
        items[3].values[0].rate.unit.map(|u| u.as_string()),
        Some("mm/s".into())
    );
}

#[test]
fn limits_lines_format_canonically_and_round_trip() {
    let (text, file, errors) = parse_cell(
        "  limits   lwr4   acceleration 4rad/s2 // robot-wide\n\
         limits `odd robot`.`j-1` velocity 2 deg/s\n\
         limits p from \"l.yaml\"",
    );
    assert!(errors.is_empty(), "{errors:#?}");
    let formatted = format(&file.expect("a tree"), &text);
    assert!(
        formatted.contains("  limits lwr4 acceleration 4 rad/s2 // robot-wide\n"),
        "{formatted}"
    );
    assert!(formatted.contains("  limits `odd robot`.`j-1` velocity 2 deg/s\n"));
    assert!(formatted.contains("  limits p from \"l.yaml\"\n"));
    let again = parse(FileId(0), &formatted);
    assert!(again.diagnostics.is_empty());
    assert_eq!(format(&again.file.expect("a tree"), &formatted), formatted);
}

#[test]
fn limits_is_reserved_and_the_limit_words_are_not() {
    // `limits` starts an item, so a name must quote it; `velocity` starts none.
    let (_, _, errors) = parse_cell("support limits");
    assert!(!errors.is_empty());
    let items = limits("limits `limits`.velocity jerk 1 rad/s3");
    assert_eq!(items[0].robot().text, "limits");
    assert_eq!(items[0].joint().map(|j| j.text.as_str()), Some("velocity"));
}

#[test]
fn shapes_the_grammar_refuses_are_syntax_errors() {
    for body in [
        // A file belongs to a robot, not to one joint.
        "limits lwr4.a1 from \"joint_limits.yaml\"",
        // A line must say something.
        "limits lwr4",
        // A limit needs its value.
        "limits lwr4 acceleration",
        // Not a rate unit.
        "limits lwr4 acceleration 4 rad/min",
        "limits lwr4 velocity 4 rad/s4",
    ] {
        let (_, _, errors) = parse_cell(body);
        assert!(!errors.is_empty(), "`{body}` parsed");
        assert!(
            errors
                .iter()
                .all(|e| !e.contains("limits_") && !e.contains("rate_unit")),
            "a rule name leaked: {errors:#?}"
        );
    }
}
