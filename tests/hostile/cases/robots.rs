//! Robot descriptions that are unsound (E0406, E0407), in `check` and in `build`.

use super::{args, geometric, repo, write, Case, Expect, SMALL};
use cellc_lang::codes;

/// The cases of this module, in the order they run.
pub(super) fn cases() -> Vec<Case> {
    vec![
        Case {
            name: "nan_limit_check",
            setup: |f| {
                write(
                    f,
                    "pick.cell",
                    geometric(&repo("tests/ui/support/nan_limit.urdf"), "boom", ""),
                );
                args(&["check", "pick.cell"])
            },
            expect: Expect {
                code: Some(codes::compile::URDF_BAD_VALUE),
                ..SMALL
            },
        },
        Case {
            name: "nan_limit_build",
            setup: |f| {
                write(
                    f,
                    "pick.cell",
                    geometric(&repo("tests/ui/support/nan_limit.urdf"), "boom", ""),
                );
                args(&["build", "pick.cell", "-o", "pick.json"])
            },
            expect: Expect {
                code: Some(codes::compile::URDF_BAD_VALUE),
                ..SMALL
            },
        },
        Case {
            name: "joint_cycle_build",
            setup: |f| {
                write(
                    f,
                    "pick.cell",
                    geometric(&repo("tests/ui/support/cycle.urdf"), "upper", ""),
                );
                args(&["build", "pick.cell", "-o", "pick.json"])
            },
            expect: Expect {
                code: Some(codes::compile::URDF_NOT_A_TREE),
                ..SMALL
            },
        },
        Case {
            name: "absurd_urdf_values",
            setup: |f| {
                let urdf = std::fs::read_to_string(repo("tests/ui/support/nan_limit.urdf"))
                    .expect("readable")
                    .replace("lower=\"NaN\"", "lower=\"-1\"")
                    .replace("<axis xyz=\"0 0 1\"/>", "<axis xyz=\"0 0 0\"/>")
                    .replace("radius=\"0.05\"", "radius=\"1e9\"")
                    .replace("xyz=\"0 0 0.1\"", "xyz=\"0 0 inf\"");
                write(f, "r.urdf", urdf);
                write(f, "pick.cell", geometric("r.urdf", "boom", ""));
                args(&["check", "pick.cell"])
            },
            expect: Expect {
                code: Some(codes::compile::URDF_BAD_VALUE),
                ..SMALL
            },
        },
    ]
}
