//! The hostile cases: what each builds, runs and expects. The cases are grouped by what
//! is hostile about them, one module each; [`cases`] lists them all, in that order.

use std::path::Path;
use std::process::Command;

mod files;
mod meshes;
mod robots;
mod size;
mod text;
mod worlds;

/// What a case builds and runs.
pub struct Case {
    pub name: &'static str,
    /// Writes the inputs into the folder and returns the command line (run there).
    pub setup: fn(&Path) -> Vec<String>,
    pub expect: Expect,
}

/// What must happen.
pub struct Expect {
    pub exit: i32,
    /// The code that must be reported (`None`: no diagnostic code is required).
    pub code: Option<cellc_lang::Code>,
    /// Wall-clock bound, for the unoptimised test build on a busy machine.
    pub seconds: u64,
    /// Address-space bound of the child.
    pub memory_mib: u64,
    /// Texts that must not appear in standard output or standard error.
    pub never: &'static [&'static str],
    /// Bound on the length of the output.
    pub max_output_bytes: usize,
}

const SMALL: Expect = Expect {
    exit: 1,
    code: None,
    seconds: 20,
    memory_mib: 512,
    never: &[],
    max_output_bytes: 20_000,
};

fn repo(path: &str) -> String {
    format!("{}/{path}", env!("CARGO_MANIFEST_DIR"))
}

fn write(folder: &Path, name: &str, bytes: impl AsRef<[u8]>) {
    std::fs::write(folder.join(name), bytes).expect("input written");
}

fn fifo(folder: &Path, name: &str) {
    let made = Command::new("mkfifo")
        .arg(folder.join(name))
        .status()
        .expect("mkfifo runs");
    assert!(made.success(), "mkfifo {name}");
}

fn args(words: &[&str]) -> Vec<String> {
    words.iter().map(|w| w.to_string()).collect()
}

/// A small abstract cell, with `extra` lines inside it.
fn pick(extra: &str) -> String {
    format!(
        "cell pick {{\n{extra}  workspace w1\n  fixed table reaches w1\n  movable left_arm reaches w1\n\n  object cube {{\n    grasp on_table by table\n    grasp held by left_arm\n    transition on_table <-> held\n  }}\n}}\n"
    )
}

/// A one-arm geometric cell on `urdf`, with `object` as its object's members.
fn geometric(urdf: &str, tip: &str, object: &str) -> String {
    format!(
        "cell pick {{\n  units m, deg\n  robot r urdf \"{urdf}\" base base tip {tip}\n  hand gripper\n  support tabletop\n  arm left = r at (0, 0, 1) with gripper\n  reach left box center (0.5, 0, 0.8) size (0.6, 0.8, 0.4)\n  surface table : tabletop box center (0.5, 0, 0.75) size (0.6, 0.8, 0.02)\n  workspaces from reach\n  object cube {{\n{object}    rest standing on tabletop at (0, 0, 0.05)\n    grasp top by gripper at (0, 0, 0.1) rpy (180, 0, 0)\n    transition standing <-> top\n  }}\n}}\n"
    )
}

/// Every case: files, texts, sizes, robot descriptions, meshes, world documents.
pub fn cases() -> Vec<Case> {
    [
        files::cases(),
        text::cases(),
        size::cases(),
        robots::cases(),
        meshes::cases(),
        worlds::cases(),
    ]
    .into_iter()
    .flatten()
    .collect()
}
