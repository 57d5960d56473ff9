//! The command line: what `cellc import dualmanip` writes, nothing on errors, and the doc
//! pages of its codes against what it prints.

use super::*;
use cellc_lang::Code;

fn cellc(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_cellc"))
        .args(args)
        .output()
        .expect("cellc runs")
}

#[test]
fn command_writes_a_cell_that_checks() {
    let dir = scratch("command");
    let out = dir.join("vito_full.cell");
    let out_s = out.to_string_lossy().to_string();
    let run = cellc(&["import", "dualmanip", VITO, "-o", &out_s]);
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    assert!(String::from_utf8_lossy(&run.stdout).contains("cellc check"));
    assert_eq!(std::fs::read_to_string(&out).unwrap(), import(VITO).text);
    assert!(cellc(&["fmt", "--check", &out_s]).status.success());
    assert!(cellc(&["check", &out_s]).status.success());
    // Only the output file is left in the directory (no temporary file).
    assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 1);
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn command_writes_nothing_on_errors() {
    let dir = scratch("errors");
    let out = dir.join("out.cell");
    let out_s = out.to_string_lossy().to_string();
    let run = cellc(&[
        "import",
        "dualmanip",
        "tests/ui/import/E0604_cross_object.db",
        "-o",
        &out_s,
    ]);
    assert_eq!(run.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&run.stderr).contains("error[E0604]"));
    assert!(!out.exists());
    let run = cellc(&[
        "import",
        "dualmanip",
        "tests/data/dualmanip/no_such.db",
        "-o",
        &out_s,
    ]);
    assert_eq!(run.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&run.stderr).contains("error[E0601]"));
    assert!(!out.exists());
    assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 0);
    let _ = std::fs::remove_dir_all(dir);
}

/// The doc pages of the import's codes show real output: the output pasted under
/// `$ cellc import dualmanip cell.db -o cell.cell` is what the command prints for the UI
/// database the page's example was made from.
#[test]
fn pages_show_real_output() {
    use cellc::import::diagnostics::codes;
    const PAGES: &[(Code, &str)] = &[
        (codes::CANNOT_OPEN, "E0601_not_sqlite.db"),
        (codes::BAD_SCHEMA, "E0602_missing_column.db"),
        (codes::UNKNOWN_ID, "E0603_unknown_grasp.db"),
        (codes::CROSS_OBJECT_TRANSITION, "E0604_cross_object.db"),
        (codes::DUPLICATE_ID, "E0605_duplicate_id.db"),
        (codes::BAD_MOVABLE, "E0606_movable_two.db"),
        (codes::FIXED_TO_FIXED, "E0607_fixed_to_fixed.db"),
        (codes::REACH_GAP, "E0608_unreached_workspace.db"),
        (codes::BAD_ADJACENCY, "E0609_useless_adjacency.db"),
    ];
    const COMMAND: &str = "$ cellc import dualmanip cell.db -o cell.cell\n";
    assert_eq!(
        codes::ALL,
        PAGES.iter().map(|(c, _)| *c).collect::<Vec<_>>()
    );
    let mut stale = Vec::new();
    for (code, db) in PAGES {
        assert!(db.starts_with(code.as_str()), "{db} is not {code}'s");
        let page = code.page();
        let start = page.find(COMMAND).expect("page shows the command") + COMMAND.len();
        let end = start + page[start..].find("```").unwrap();
        let dir = scratch(&format!("page-{code}"));
        std::fs::copy(format!("tests/ui/import/{db}"), dir.join("cell.db")).unwrap();
        let run = Command::new(env!("CARGO_BIN_EXE_cellc"))
            .args(["import", "dualmanip", "cell.db", "-o", "cell.cell"])
            .current_dir(&dir)
            .output()
            .unwrap();
        let printed = format!(
            "{}{}",
            String::from_utf8_lossy(&run.stdout),
            String::from_utf8_lossy(&run.stderr)
        );
        if printed.trim_end() != page[start..end].trim_end() {
            stale.push(format!(
                "docs/diagnostics/{code}.md: the command prints\n{printed}"
            ));
        }
        let _ = std::fs::remove_dir_all(dir);
    }
    assert!(stale.is_empty(), "{}", stale.join("\n"));
}
