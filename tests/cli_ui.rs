//! Command-line UI tests: each `tests/ui/cli/CODE_what.args` holds one `cellc` command line
//! (split as a POSIX shell would: quote an argument that has spaces; run from the
//! repository root), optionally after `NAME=value` words that set environment variables
//! as a shell prefix does (`NO_COLOR=1 check ...`). The command must fail
//! with exactly that code in a rendered diagnostic (on either stream), never panic, and its output (exit
//! status, standard output, standard error) is snapshotted, the escape character written
//! `\e` so that colour shows in the snapshot as text.

use std::process::Command;

/// The variables that decide colour, cleared for every command so that the test's own
/// environment (a CI that sets `NO_COLOR` or `CLICOLOR_FORCE`) cannot change a snapshot;
/// a command line sets them itself.
const COLOR_VARIABLES: [&str; 3] = ["NO_COLOR", "CLICOLOR", "CLICOLOR_FORCE"];

/// A leading `NAME=value` word: an environment variable, as in a shell.
fn assignment(word: &str) -> Option<(&str, &str)> {
    let (name, value) = word.split_once('=')?;
    let mut chars = name.chars();
    let first = chars.next()?;
    let valid = (first.is_ascii_uppercase() || first == '_')
        && chars.all(|c| c.is_ascii_uppercase() || c.is_ascii_digit() || c == '_');
    valid.then_some((name, value))
}

#[test]
fn environment_prefixes_are_read_as_a_shell_reads_them() {
    assert_eq!(assignment("NO_COLOR=1"), Some(("NO_COLOR", "1")));
    assert_eq!(assignment("NO_COLOR="), Some(("NO_COLOR", "")));
    assert_eq!(assignment("--weights=1,2"), None);
    assert_eq!(assignment("check"), None);
    assert_eq!(assignment("lower=1"), None);
}

#[test]
fn cli_ui() {
    let mut checked = 0;
    insta::glob!("ui/cli/*.args", |path| {
        let name = path.file_name().unwrap().to_string_lossy().to_string();
        let code = name.split('_').next().unwrap_or_default().to_string();
        let line = std::fs::read_to_string(path).expect("readable");
        let words: Vec<String> = shlex::split(&line).expect("a command line");
        let n_env = words.iter().take_while(|w| assignment(w).is_some()).count();
        let (env, args) = words.split_at(n_env);
        let mut command = Command::new(env!("CARGO_BIN_EXE_cellc"));
        for name in COLOR_VARIABLES {
            command.env_remove(name);
        }
        for (name, value) in env.iter().filter_map(|w| assignment(w)) {
            command.env(name, value);
        }
        let out = command
            .args(args)
            .current_dir(env!("CARGO_MANIFEST_DIR"))
            .output()
            .expect("cellc runs");
        let stdout = String::from_utf8_lossy(&out.stdout).replace('\u{1b}', "\\e");
        let stderr = String::from_utf8_lossy(&out.stderr).replace('\u{1b}', "\\e");
        assert!(!out.status.success(), "{name}: succeeded");
        assert!(!stderr.contains("panicked"), "{name}: {stderr}");
        // Human diagnostics are on standard error; `--format short` and `json` put them
        // on standard output.
        let rendered = [format!("error[{code}]"), format!("\"code\": \"{code}\"")];
        assert!(
            rendered
                .iter()
                .any(|r| stderr.contains(r.as_str()) || stdout.contains(r.as_str())),
            "{name}: no {code} in\n{stdout}\n{stderr}"
        );
        let prefix: String = env.iter().map(|w| format!("{w} ")).collect();
        insta::assert_snapshot!(format!(
            "$ {prefix}cellc {}\nexit: {:?}\n----- stdout -----\n{stdout}----- stderr -----\n{stderr}",
            args.join(" "),
            out.status.code()
        ));
        checked += 1;
    });
    assert!(checked >= 4, "{checked} command lines");
}
