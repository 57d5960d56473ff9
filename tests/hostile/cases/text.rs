//! Files that are not cells, described and never quoted (E0319), and control characters,
//! refused at their place (E0004) and never printed.

use super::{args, geometric, pick, write, Case, Expect, SMALL};
use cellc_lang::codes;

/// A file of secrets that no message may quote.
const SECRET: &str = "API_TOKEN=sk-live-do-not-print\nDB_PASSWORD=hunter2\n";

/// The cases of this module, in the order they run.
pub(super) fn cases() -> Vec<Case> {
    vec![
        Case {
            name: "include_a_secret",
            setup: |f| {
                write(f, "secrets.env", SECRET);
                write(f, "pick.cell", pick("  include \"secrets.env\"\n"));
                args(&["check", "pick.cell"])
            },
            expect: Expect {
                code: Some(codes::compile::NOT_A_CELL_FILE),
                never: &["hunter2", "sk-live"],
                ..SMALL
            },
        },
        Case {
            name: "check_a_secret",
            setup: |f| {
                write(f, "secrets.env", SECRET);
                args(&["check", "secrets.env", "--format", "json"])
            },
            expect: Expect {
                code: Some(codes::compile::NOT_A_CELL_FILE),
                never: &["hunter2", "sk-live"],
                ..SMALL
            },
        },
        Case {
            name: "format_a_secret",
            setup: |f| {
                write(f, "secrets.env", SECRET);
                args(&["fmt", "--check", "secrets.env"])
            },
            expect: Expect {
                code: Some(codes::compile::NOT_A_CELL_FILE),
                never: &["hunter2", "sk-live"],
                ..SMALL
            },
        },
        Case {
            name: "secret_as_urdf",
            setup: |f| {
                write(
                    f,
                    "config.xml",
                    "<config><token>sk-live-do-not-print</token></config>",
                );
                write(f, "pick.cell", geometric("config.xml", "boom", ""));
                args(&["check", "pick.cell"])
            },
            expect: Expect {
                code: Some(codes::compile::URDF_INVALID),
                never: &["sk-live"],
                ..SMALL
            },
        },
        Case {
            name: "binary_cell",
            setup: |f| {
                write(f, "pick.cell", b"cell pick {\0\x01\x02 hunter2 }");
                args(&["check", "pick.cell"])
            },
            expect: Expect {
                code: Some(codes::compile::NOT_A_CELL_FILE),
                never: &["hunter2"],
                ..SMALL
            },
        },
        Case {
            name: "latin1_cell",
            setup: |f| {
                write(f, "pick.cell", b"cell pick { workspace caf\xe9 hunter2 }");
                args(&["check", "pick.cell"])
            },
            expect: Expect {
                code: Some(codes::compile::NOT_A_CELL_FILE),
                never: &["hunter2"],
                ..SMALL
            },
        },
        // ---- control characters are refused at their place (E0004), never printed ----
        Case {
            name: "escape_sequences",
            setup: |f| {
                let lines = "  workspace w\x1b]0;pwned\x07\x1b[2J\n".repeat(40);
                write(f, "pick.cell", pick(&lines));
                args(&["check", "pick.cell"])
            },
            expect: Expect {
                code: Some(codes::parse::CONTROL_CHARACTER),
                never: &["\x1b", "\x07"],
                ..SMALL
            },
        },
    ]
}
