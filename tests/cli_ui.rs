//! Command-line UI tests: each `tests/ui/cli/CODE_what.args` holds one `cellc` command line
//! (split as a POSIX shell would: quote an argument that has spaces; run from the
//! repository root). The command must fail
//! with exactly that code in a rendered diagnostic, never panic, and its output (exit
//! status, standard output, standard error) is snapshotted.

use std::process::Command;

#[test]
fn cli_ui() {
    let mut checked = 0;
    insta::glob!("ui/cli/*.args", |path| {
        let name = path.file_name().unwrap().to_string_lossy().to_string();
        let code = name.split('_').next().unwrap_or_default().to_string();
        let line = std::fs::read_to_string(path).expect("readable");
        let args: Vec<String> = shlex::split(&line).expect("a command line");
        let out = Command::new(env!("CARGO_BIN_EXE_cellc"))
            .args(&args)
            .current_dir(env!("CARGO_MANIFEST_DIR"))
            .output()
            .expect("cellc runs");
        let stdout = String::from_utf8_lossy(&out.stdout);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "{name}: succeeded");
        assert!(!stderr.contains("panicked"), "{name}: {stderr}");
        assert!(
            stderr.contains(&format!("error[{code}]")),
            "{name}: no {code} in\n{stderr}"
        );
        insta::assert_snapshot!(format!(
            "$ cellc {}\nexit: {:?}\n----- stdout -----\n{stdout}----- stderr -----\n{stderr}",
            args.join(" "),
            out.status.code()
        ));
        checked += 1;
    });
    assert!(checked >= 4, "{checked} command lines");
}
