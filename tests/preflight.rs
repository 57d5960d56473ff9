//! The scene as a whole, before any arc: a base on its table is reported once with the
//! `allow contact` line that fixes it (and fixing it lets the arcs verify), a colliding
//! home is refused naming the pair, and no pruned arc blames an arm standing by.

use std::process::Command;

use cellc_driver::fs_files::FsFiles;
use cellc_driver::BuildOptions;
use cellc_runtime::scene::Scene;
use cellc_runtime::verify::preflight::{preflight, Preflight};
use cellc_runtime::verify::{verify, VerifyOptions};
use cellc_schema::{Artifact, FileError, Files, Infeasibility};

/// One file's text replaced, the rest from the disk.
struct Edited<'a> {
    path: &'a str,
    text: String,
}

impl Files for Edited<'_> {
    fn read(&self, path: &str) -> Result<Vec<u8>, FileError> {
        if path == self.path {
            return Ok(self.text.as_bytes().to_vec());
        }
        FsFiles.read(path)
    }
}

/// The cell compiled and lowered, its scene and what the preflight finds.
fn checked(
    files: &dyn Files,
    path: &str,
) -> (cellc_compiler::Compilation, Artifact, Scene, Preflight) {
    let built = cellc_driver::build(files, path, &BuildOptions::unverified());
    let compilation = built.compilation;
    let artifact = built
        .artifact
        .unwrap_or_else(|| panic!("{:?}", compilation.diagnostics));
    let scene = Scene::load(&artifact, files).expect("loads");
    let found = preflight(&artifact, &scene);
    (compilation, artifact, scene, found)
}

#[test]
fn a_base_on_its_table_gets_the_allow_contact_line_and_the_line_fixes_it() {
    let path = "tests/ui/cli/support/base_on_table.cell";
    let (compilation, artifact, _, found) = checked(&FsFiles, path);
    assert!(found.blocks_verification());
    let diagnostics =
        cellc_driver::scene_report::diagnostics(&artifact, &found, &compilation.sources);
    let codes: Vec<cellc_lang::Code> = diagnostics.iter().map(|d| d.code).collect();
    assert_eq!(
        codes,
        [cellc_driver::scene_report::codes::PERMANENT_CONTACT],
        "{diagnostics:?}"
    );
    let line = "allow contact left.lwr_base_link table";
    assert!(
        diagnostics[0]
            .help
            .as_deref()
            .is_some_and(|h| h.contains(line)),
        "{:?}",
        diagnostics[0].help
    );
    assert!(
        diagnostics[0]
            .notes
            .iter()
            .any(|n| n.starts_with("to fix, add `allow contact")),
        "{:?}",
        diagnostics[0].notes
    );
    // The edit the note describes, made: the contact is gone and the arm's arcs verify.
    let edit =
        cellc_driver::fixes::allow_contact(&artifact, line, &compilation.sources).expect("an edit");
    let text = std::fs::read_to_string(path).expect("readable");
    let fixed = Edited {
        path,
        text: cellc_driver::fixes::apply(&text, &[&edit]).expect("applies"),
    };
    let (_, mut artifact, scene, found) = checked(&fixed, path);
    assert_eq!(found, Preflight::default());
    let report = verify(&mut artifact, &scene, &VerifyOptions::default(), &|_, _| {});
    assert!(report.n_checked > 0 && report.n_pruned == 0, "{report:?}");
}

#[test]
fn a_colliding_home_is_refused_naming_the_pair() {
    let path = "tests/ui/cli/support/leaning_home.cell";
    let out = Command::new(env!("CARGO_BIN_EXE_cellc"))
        .args(["build", path, "-o", "target/leaning_home.json"])
        .output()
        .expect("cellc runs");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("error[E0420]"), "{stderr}");
    assert!(
        stderr
            .contains("`left` collides at its home: `left.lwr_link_4` touches `right.lwr_link_1`"),
        "{stderr}"
    );
    assert!(stderr.contains("no artifact written"), "{stderr}");
    // Standing straight up (its default home), the left arm is clear.
    let text = std::fs::read_to_string(path).expect("readable");
    let upright = Edited {
        path,
        text: text.replace(" home (lwr_a1_joint 90, lwr_a2_joint 90)", ""),
    };
    assert_ne!(upright.text, text);
    let (_, _, _, found) = checked(&upright, path);
    assert_eq!(found, Preflight::default());
}

#[test]
fn pruning_never_blames_an_arm_standing_by() {
    // Both bases touch the torso; each arm's arcs must be blamed on its own base (or its
    // own links, hand or the object), never on the other arm standing at home.
    let path = "tests/data/preflight/bases_touch_torso.cell";
    let (_, mut artifact, scene, _) = checked(&FsFiles, path);
    verify(&mut artifact, &scene, &VerifyOptions::default(), &|_, _| {});
    let mut collisions = 0;
    for object in &artifact.objects {
        for pruned in &object.graph.pruned {
            let Infeasibility::Collision { a, b } = &pruned.reason else {
                continue;
            };
            collisions += 1;
            let nodes = [pruned.arc.from, pruned.arc.to].map(|n| object.graph.nodes[n as usize]);
            let ours = |body: &str| {
                body == object.name
                    || nodes.iter().any(|n| {
                        let e = &artifact.end_effectors[n.end_effector.index()];
                        body.split('/').next() == Some(e.name.as_str())
                    })
            };
            assert!(
                ours(a) || ours(b),
                "`{a}` and `{b}` blamed for {:?}",
                pruned.arc
            );
        }
    }
    assert!(collisions > 10, "{collisions} arcs pruned for collisions");
}
