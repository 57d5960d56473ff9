//! `reach ARM auto` on the shipped Vito cell (a test copy: its three `reach` boxes
//! replaced by `reach left auto` and `reach right auto`): the boxes found hold poses
//! where inverse kinematics solves, the same cell gives the same artifact, and the named
//! requests plan the same kinds of plans as with the hand-written boxes.

use std::time::Duration;

use cellc_compiler::Compilation;
use cellc_driver::fs_files::FsFiles;
use cellc_runtime::kinematics::{solve_ik, IkOptions, IkTarget};
use cellc_runtime::math::{aabb_from_schema, Aabb, Iso, Point, Quat, Vec3};
use cellc_runtime::plan::PlanOptions;
use cellc_runtime::scene::{Holder, ObjectPlacement, SceneScratch};
use cellc_runtime::validity::{SceneValidity, StateValidity};
use cellc_runtime::{Cell, Termination, VerifyOptions};
use cellc_schema::{Artifact, Encoding, FileError, Files};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// `cells/vito_auto.cell`: the Vito cell with its reach computed; every other file from
/// the disk.
struct VitoAuto {
    text: String,
}

const AUTO: &str = "cells/vito_auto.cell";

impl VitoAuto {
    fn new() -> VitoAuto {
        let vito = std::fs::read_to_string("cells/vito.cell").expect("the shipped cell");
        let mut text = String::new();
        let mut replaced = false;
        for line in vito.lines() {
            if line.trim_start().starts_with("reach ") {
                if !replaced {
                    text.push_str("  reach left auto\n  reach right auto\n");
                    replaced = true;
                }
                continue;
            }
            text.push_str(line);
            text.push('\n');
        }
        assert!(replaced, "the Vito cell has reach boxes");
        VitoAuto { text }
    }
}

impl Files for VitoAuto {
    fn read(&self, path: &str) -> Result<Vec<u8>, FileError> {
        if path == AUTO {
            return Ok(self.text.as_bytes().to_vec());
        }
        FsFiles.read(path)
    }
}

fn compiled(files: &dyn Files, path: &str) -> (Compilation, Artifact) {
    let built = cellc_driver::build(files, path, &cellc_driver::BuildOptions::unverified());
    let errors: Vec<_> = built
        .diagnostics
        .iter()
        .filter(|d| d.is_error())
        .map(|d| d.message.clone())
        .collect();
    let artifact = built
        .artifact
        .unwrap_or_else(|| panic!("{path}: {errors:?}"));
    (built.compilation, artifact)
}

#[test]
fn the_same_cell_gives_the_same_boxes_and_the_same_artifact() {
    let files = VitoAuto::new();
    let (first, a) = compiled(&files, AUTO);
    let (second, b) = compiled(&files, AUTO);
    assert_eq!(a.to_bytes(Encoding::Binary), b.to_bytes(Encoding::Binary));
    let boxes = |c: &Compilation| -> Vec<_> {
        let cell = c.cell.as_ref().expect("resolved");
        cell.auto_reach.iter().map(|r| r.boxes.clone()).collect()
    };
    assert_eq!(boxes(&first), boxes(&second));
    // Both arms found boxes over the table, the right one over the bin too.
    let cell = first.cell.as_ref().expect("resolved");
    assert_eq!(cell.auto_reach.len(), 2);
    let over =
        |arm: usize, surface: &str| cell.auto_reach[arm].boxes.iter().any(|(s, _)| s == surface);
    assert!(over(0, "table") && over(1, "table") && over(1, "bin"));
    assert!(!over(0, "bin"), "the left arm does not reach the bin");
    for reach in &cell.auto_reach {
        eprintln!(
            "reach auto of {}: {} boxes, {} columns, {} solves, {:?}",
            cell.end_effectors[reach.end_effector].name,
            reach.boxes.len(),
            reach.tried,
            reach.solves,
            reach.elapsed
        );
        // A budget for a loaded CI machine at the test profile's optimisation, not a
        // benchmark: the time is reported by `cellc info`.
        assert!(
            reach.elapsed < Duration::from_secs(60),
            "{:?}",
            reach.elapsed
        );
    }
}

/// Whether `arm` holds the object with one of `grasps` at `centre`, upright at some yaw,
/// with far more effort than `reach auto` spends (a test oracle, not the same search).
fn holds(
    artifact: &Artifact,
    cell: &Cell,
    arm: u32,
    centre: Point,
    rng: &mut ChaCha8Rng,
    scratch: &mut SceneScratch,
) -> bool {
    let scene = cell.scene().expect("geometric");
    let Holder::Arm { robot, base, home } = &scene.holders[arm as usize] else {
        panic!("an arm");
    };
    let kind = artifact.end_effectors[arm as usize].kind;
    let ik = IkOptions {
        restarts: 40,
        ..IkOptions::default()
    };
    for (o, object) in artifact.objects.iter().enumerate() {
        for grasp in object.grasps.iter().filter(|g| !g.rest) {
            if !matches!(grasp.holder, cellc_schema::Holder::Kind(k) if Some(k) == kind) {
                continue;
            }
            let g = grasp
                .pose
                .as_ref()
                .map_or_else(Iso::identity, cellc_runtime::math::iso_from_schema);
            for i in 0..8 {
                let yaw = std::f64::consts::TAU * f64::from(i) / 8.0;
                let pose = Iso::from_parts(
                    centre.coords.into(),
                    Quat::from_axis_angle(&Vec3::z_axis(), yaw),
                );
                let Ok(q) = solve_ik(
                    &scene.robots[*robot],
                    base,
                    &IkTarget::Pose(pose * g.inverse()),
                    home,
                    rng,
                    &ik,
                    &Termination::never(),
                ) else {
                    continue;
                };
                let arm = cellc_schema::EndEffectorId(arm);
                let placement = ObjectPlacement::Held { by: arm, grasp: g };
                let validity = SceneValidity::new(
                    scene,
                    &[arm],
                    &[],
                    cellc_schema::ObjectId(o as u32),
                    placement,
                )
                .expect("a layout");
                if validity.is_valid(&q, scratch).expect("a state") {
                    return true;
                }
            }
        }
    }
    false
}

#[test]
fn reach_auto_boxes_hold_poses_where_ik_solves() {
    let files = VitoAuto::new();
    let (compilation, artifact) = compiled(&files, AUTO);
    let cell = Cell::from_artifact(artifact.clone(), &files).expect("loads");
    let resolved = compilation.cell.as_ref().expect("resolved");
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    let mut scratch = SceneScratch::default();
    let (mut tried, mut held) = (0, 0);
    for reach in &resolved.auto_reach {
        for (_, b) in &reach.boxes {
            // Above the lowest 10 cm, where the objects rest rather than being held.
            let upper = Aabb::new(Point::new(b.mins.x, b.mins.y, b.mins.z + 0.1), b.maxs);
            for _ in 0..12 {
                let p = Point::from(Vec3::from_fn(|k, _| {
                    upper.mins[k] + rng.random::<f64>() * (upper.maxs[k] - upper.mins[k])
                }));
                tried += 1;
                if holds(
                    &artifact,
                    &cell,
                    reach.end_effector.0,
                    p,
                    &mut rng,
                    &mut scratch,
                ) {
                    held += 1;
                }
            }
        }
    }
    assert!(tried >= 60, "{tried} poses tried");
    // Sampling leaves holes narrower than its spacing: nearly every pose, not all.
    assert!(held * 100 >= tried * 95, "{held} of {tried} poses held");
    // The test tells reach from no reach: over the whole table, where each arm reaches
    // a part, far fewer poses are held.
    let table = aabb_from_schema(&cellc_schema::Aabb {
        min: [-0.23, -0.42, 1.0],
        max: [1.22, 0.72, 1.5],
    });
    let (mut anywhere, mut held_anywhere) = (0, 0);
    for arm in [0u32, 1] {
        for _ in 0..30 {
            let p = Point::from(Vec3::from_fn(|k, _| {
                table.mins[k] + rng.random::<f64>() * (table.maxs[k] - table.mins[k])
            }));
            anywhere += 1;
            if holds(&artifact, &cell, arm, p, &mut rng, &mut scratch) {
                held_anywhere += 1;
            }
        }
    }
    eprintln!(
        "held {held} of {tried} poses in the boxes, {held_anywhere} of {anywhere} over the table"
    );
    assert!(
        held_anywhere * 100 <= anywhere * 80,
        "{held_anywhere} of {anywhere}"
    );
}

/// The holders and strategy of a named request's plan.
fn planned(cell: &Cell, name: &str) -> (Vec<String>, String) {
    let request = cell
        .named_request(name, PlanOptions::default())
        .expect("declared");
    let plan = cell
        .plan(&cell.home_world(), &request)
        .unwrap_or_else(|e| panic!("{name}: {e:?}"));
    let a = cell.artifact();
    let mut holders: Vec<String> = Vec::new();
    for s in &plan.states {
        let h = a.end_effectors[s.end_effector.index()].name.clone();
        if holders.last() != Some(&h) {
            holders.push(h);
        }
    }
    (holders, plan.strategy.to_string())
}

#[test]
fn vito_with_reach_auto_plans_what_its_hand_written_reach_plans() {
    let load = |files: &dyn Files, path: &str| {
        let (_, artifact) = compiled(files, path);
        let mut cell = Cell::from_artifact(artifact, files).expect("loads");
        cell.verify(&VerifyOptions::default());
        cell
    };
    let written = load(&FsFiles, "cells/vito.cell");
    let files = VitoAuto::new();
    let auto = load(&files, AUTO);
    // The same derived workspaces: the named requests name them.
    let names = |c: &Cell| -> Vec<String> {
        c.artifact()
            .workspaces
            .iter()
            .map(|w| w.name.clone())
            .collect()
    };
    assert_eq!(names(&written), names(&auto));
    for request in &written.artifact().requests {
        let name = request.name.as_str();
        assert_eq!(
            planned(&written, name),
            planned(&auto, name),
            "{name} plans differently"
        );
    }
}

#[test]
fn cellc_info_shows_the_boxes_found_and_how_long_it_took() {
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_cellc"))
        .args(["info", "tests/data/reach_auto.cell"])
        .output()
        .expect("cellc runs");
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let section = stdout
        .split("\nreach auto (1 arm)\n")
        .nth(1)
        .unwrap_or_else(|| panic!("no reach section in\n{stdout}"));
    let mut lines = section.lines();
    let summary = lines.next().unwrap_or_default();
    assert!(
        summary.starts_with("  left: ")
            && summary.contains(" places tried, ")
            && summary.ends_with(" s"),
        "{summary}"
    );
    let boxes: Vec<&str> = lines
        .filter(|l| l.starts_with("    over table: box x "))
        .collect();
    assert!(!boxes.is_empty(), "{section}");
    // The arm's workspace over the table is derived from those boxes.
    assert!(stdout.contains("ws_left_table"), "{stdout}");
}

/// One file's text replaced, the rest from the disk.
struct Edited {
    path: &'static str,
    text: String,
}

impl Files for Edited {
    fn read(&self, path: &str) -> Result<Vec<u8>, FileError> {
        if path == self.path {
            return Ok(self.text.as_bytes().to_vec());
        }
        FsFiles.read(path)
    }
}

#[test]
fn a_base_on_its_table_is_reported_at_check_time_rather_than_no_reach() {
    // With its reach computed, a cell is checked as `cellc build` checks it: the base
    // standing on the table would make every sample fail, so E0421 says why instead of
    // E0423 saying nothing was found.
    let path = "tests/ui/cli/support/base_on_table.cell";
    let text = std::fs::read_to_string(path).expect("readable");
    let auto = Edited {
        path,
        text: text.replace(
            "reach left box center (0.5, 0, 0.95) size (0.3, 0.4, 0.4)",
            "reach left auto",
        ),
    };
    assert_ne!(auto.text, text);
    let compilation = cellc_driver::compile(&auto, path, &Default::default());
    let codes: Vec<cellc_lang::Code> = compilation.diagnostics.iter().map(|d| d.code).collect();
    assert_eq!(
        codes,
        [cellc_driver::scene_report::codes::PERMANENT_CONTACT],
        "{:?}",
        compilation.diagnostics
    );
}
