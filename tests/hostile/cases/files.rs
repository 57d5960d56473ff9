//! Files that are not regular or too large (E0317, E0318): refused before they are read.

use super::{args, fifo, geometric, pick, write, Case, Expect, SMALL};
use cellc_lang::codes;

/// The cases of this module, in the order they run.
pub(super) fn cases() -> Vec<Case> {
    vec![
        Case {
            name: "fifo_cell",
            setup: |f| {
                fifo(f, "pick.cell");
                args(&["check", "pick.cell"])
            },
            expect: Expect {
                code: Some(codes::compile::NOT_A_REGULAR_FILE),
                seconds: 10,
                ..SMALL
            },
        },
        Case {
            name: "fifo_include",
            setup: |f| {
                fifo(f, "lib.cell");
                write(f, "pick.cell", pick("  include \"lib.cell\"\n"));
                args(&["check", "pick.cell"])
            },
            expect: Expect {
                code: Some(codes::compile::NOT_A_REGULAR_FILE),
                seconds: 10,
                ..SMALL
            },
        },
        Case {
            name: "fifo_urdf",
            setup: |f| {
                fifo(f, "r.urdf");
                write(f, "pick.cell", geometric("r.urdf", "boom", ""));
                args(&["check", "pick.cell"])
            },
            expect: Expect {
                code: Some(codes::compile::NOT_A_REGULAR_FILE),
                seconds: 10,
                ..SMALL
            },
        },
        Case {
            name: "fifo_artifact",
            setup: |f| {
                fifo(f, "pick.json");
                args(&["info", "pick.json"])
            },
            expect: Expect {
                code: Some(codes::compile::NOT_A_REGULAR_FILE),
                seconds: 10,
                ..SMALL
            },
        },
        Case {
            name: "fifo_database",
            setup: |f| {
                fifo(f, "grasps.db");
                args(&["import", "dualmanip", "grasps.db", "-o", "out.cell"])
            },
            expect: Expect {
                code: Some(codes::import::CANNOT_OPEN),
                seconds: 10,
                ..SMALL
            },
        },
        Case {
            name: "endless_device",
            setup: |_| args(&["check", "/dev/zero"]),
            expect: Expect {
                code: Some(codes::compile::NOT_A_REGULAR_FILE),
                seconds: 10,
                ..SMALL
            },
        },
        Case {
            name: "E0317_cell_over_16_mib",
            setup: |f| {
                let mut text = String::from("cell pick {\n");
                text.push_str(&" ".repeat(16 << 20));
                text.push_str("}\n");
                write(f, "huge.cell", text);
                args(&["check", "huge.cell"])
            },
            // Refused by its size alone: never read, so a small address space suffices.
            expect: Expect {
                code: Some(codes::compile::FILE_TOO_LARGE),
                memory_mib: 256,
                ..SMALL
            },
        },
        Case {
            name: "urdf_over_16_mib",
            setup: |f| {
                write(f, "r.urdf", vec![b' '; (16 << 20) + 1]);
                write(f, "pick.cell", geometric("r.urdf", "boom", ""));
                args(&["check", "pick.cell"])
            },
            expect: Expect {
                code: Some(codes::compile::FILE_TOO_LARGE),
                memory_mib: 256,
                ..SMALL
            },
        },
    ]
}
