//! World documents (`cellc run --world`, R0008, R0009).

use super::{args, fifo, pick, write, Case, Expect, SMALL};
use cellc_lang::codes;

/// A task for [`pick`]'s cube, so `cellc run --task t` reads a world document first.
const WORLD_TASK: &str = "  task t {\n    cube to left_arm.held in w1\n  }\n";

/// The cases of this module, in the order they run.
pub(super) fn cases() -> Vec<Case> {
    vec![
        Case {
            name: "fifo_world",
            setup: |f| {
                fifo(f, "w.json");
                write(f, "pick.cell", pick(WORLD_TASK));
                args(&["run", "pick.cell", "--task", "t", "--world", "w.json"])
            },
            expect: Expect {
                code: Some(codes::request::WORLD_DOCUMENT),
                seconds: 10,
                ..SMALL
            },
        },
        Case {
            name: "world_over_its_budget",
            setup: |f| {
                let mut text = String::from("{\"objects\": {");
                text.push_str(&" ".repeat(5 << 20));
                text.push_str("}}");
                write(f, "w.json", text);
                write(f, "pick.cell", pick(WORLD_TASK));
                args(&["run", "pick.cell", "--task", "t", "--world", "w.json"])
            },
            expect: Expect {
                code: Some(codes::request::WORLD_DOCUMENT),
                ..SMALL
            },
        },
        Case {
            name: "world_nested_deep",
            setup: |f| {
                let depth = 1_000_000;
                let text = format!(
                    "{{\"objects\": {{\"cube\": {}{}}}}}",
                    "[".repeat(depth),
                    "]".repeat(depth)
                );
                write(f, "w.json", text);
                write(f, "pick.cell", pick(WORLD_TASK));
                args(&["run", "pick.cell", "--task", "t", "--world", "w.json"])
            },
            expect: Expect {
                code: Some(codes::request::WORLD_DOCUMENT),
                ..SMALL
            },
        },
        Case {
            name: "world_of_many_unknown_objects",
            setup: |f| {
                let entries: Vec<String> = (0..100_000)
                    .map(|i| format!("\"ghost{i}\": \"absent\""))
                    .collect();
                let text = format!("{{\"objects\": {{{}}}}}", entries.join(", "));
                write(f, "w.json", text);
                write(f, "pick.cell", pick(WORLD_TASK));
                args(&["run", "pick.cell", "--task", "t", "--world", "w.json"])
            },
            expect: Expect {
                code: Some(codes::request::WORLD),
                ..SMALL
            },
        },
    ]
}
