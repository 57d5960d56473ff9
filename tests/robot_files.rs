//! Robot files as ROS ships them: the shipped Franka Panda and UR5 descriptions load
//! unmodified through the real readers; the cells that use them find their reach from
//! kinematics (`reach auto`), build, verify, plan and run;
//! `package://` files are found through a cell's `package` item, `--package-path` and
//! `ROS_PACKAGE_PATH` (and an artifact needs none of them); an SRDF's disabled pair
//! changes a verdict.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use cellc_driver::fs_files::FsFiles;
use cellc_runtime::plan::PlanOptions;
use cellc_runtime::robot::Robot;
use cellc_runtime::SimulatorTolerance;
use cellc_runtime::{Cell, ExecuteOptions, ExecutionError, StepError};
use cellc_schema::MeshFile;
use cellc_urdf::{package, Description, MeshPaths, PackagePath, Srdf};

const PACKAGES: &str = "cells/robots/example-robot-data";

fn cellc(args: &[&str], dir: &Path, env: &[(&str, &str)]) -> Output {
    let mut command = Command::new(env!("CARGO_BIN_EXE_cellc"));
    command
        .args(args)
        .current_dir(dir)
        .env_remove("ROS_PACKAGE_PATH");
    for (k, v) in env {
        command.env(k, v);
    }
    command.output().expect("the cellc binary runs")
}

fn text(output: &Output) -> String {
    format!(
        "{}{}",
        String::from_utf8_lossy(&output.stdout),
        String::from_utf8_lossy(&output.stderr)
    )
}

/// A shipped description: URDF, SRDF, chain and what loading it must give.
struct Shipped {
    urdf: &'static str,
    srdf: &'static str,
    base: &'static str,
    tip: &'static str,
    joints: usize,
    meshes: usize,
    disabled: usize,
}

const SHIPPED: [Shipped; 2] = [
    Shipped {
        urdf: "robots/panda_description/urdf/panda.urdf",
        srdf: "robots/panda_description/srdf/panda.srdf",
        base: "panda_link0",
        tip: "panda_hand_tcp",
        joints: 7,
        meshes: 9,
        disabled: 35,
    },
    Shipped {
        urdf: "robots/ur_description/urdf/ur5_robot.urdf",
        srdf: "robots/ur_description/srdf/ur5.srdf",
        base: "base_link",
        tip: "tool0",
        joints: 6,
        meshes: 7,
        disabled: 10,
    },
];

#[test]
fn the_shipped_descriptions_load_unmodified() {
    let mut packages = PackagePath::new();
    packages.search("cells/robots");
    for shipped in SHIPPED {
        let urdf_path = format!("{PACKAGES}/{}", shipped.urdf);
        let urdf = std::fs::read_to_string(&urdf_path).expect("shipped URDF");
        let description = Description::parse(&urdf).expect("the URDF parses");
        assert!(description.problems().is_empty(), "{urdf_path} is unsound");
        let srdf_text =
            std::fs::read_to_string(format!("{PACKAGES}/{}", shipped.srdf)).expect("shipped SRDF");
        let srdf = Srdf::parse(&srdf_text).expect("the SRDF parses");
        assert!(srdf.problems(&description).is_empty(), "{}", shipped.srdf);
        assert_eq!(srdf.disabled_collisions.len(), shipped.disabled);
        // Every collision mesh is a `package://` URI, found in the shipped package.
        let meshes: Vec<MeshFile> = description
            .collision_meshes()
            .into_iter()
            .map(|written| {
                assert!(written.starts_with("package://example-robot-data/"));
                let path = package::resolve(&urdf_path, written, &packages, &FsFiles)
                    .expect("the package resolves");
                MeshFile {
                    written: written.to_string(),
                    path,
                }
            })
            .collect();
        assert_eq!(meshes.len(), shipped.meshes, "{urdf_path}");
        let robot = Robot::from_urdf_with(
            &urdf,
            MeshPaths::Resolved(&meshes),
            shipped.base,
            shipped.tip,
            &FsFiles,
        )
        .unwrap_or_else(|e| panic!("{urdf_path}: {e}"));
        assert_eq!(robot.n_joints(), shipped.joints);
        // Every mesh on the chain became a solid (the Panda's fingers are off the chain).
        assert!(robot.shapes().len() >= shipped.joints, "{urdf_path}");
    }
}

#[test]
fn the_panda_srdf_gives_the_chain_and_the_home() {
    let urdf = std::fs::read_to_string(format!("{PACKAGES}/{}", SHIPPED[0].urdf)).expect("urdf");
    let srdf = std::fs::read_to_string(format!("{PACKAGES}/{}", SHIPPED[0].srdf)).expect("srdf");
    let (description, srdf) = (
        Description::parse(&urdf).expect("urdf"),
        Srdf::parse(&srdf).expect("srdf"),
    );
    assert_eq!(
        srdf.group_chain("arm", &description),
        Ok(("panda_link0".to_string(), "panda_link7".to_string()))
    );
    let default: Vec<_> = srdf.states_named("default").collect();
    assert_eq!(default.len(), 1);
    assert_eq!(
        default[0].values.len(),
        8,
        "seven arm joints and the finger"
    );

    // In a cell (compiled as the binary does: its reach is `auto`): the home is the
    // state's arm joints, in chain order.
    let compilation = cellc_driver::compile(&FsFiles, "cells/two_pandas.cell", &Default::default());
    assert!(!compilation.has_errors());
    let cell = compilation.cell.expect("resolves");
    let (_, left) = cell
        .end_effectors
        .iter()
        .find(|(_, e)| e.name == "left")
        .expect("left arm");
    let cellc_compiler::model::Body::Arm { home, .. } = &left.body else {
        panic!("left is an arm");
    };
    // The SRDF's own digits, in chain order, without the finger.
    let expected: Vec<f64> = (1..=7)
        .map(|j| {
            let joint = format!("panda_joint{j}");
            default[0]
                .values
                .iter()
                .find(|(name, _)| *name == joint)
                .map(|(_, v)| *v)
                .expect("the state sets every arm joint")
        })
        .collect();
    assert_eq!(home, &expected);
    assert_eq!(expected[3], -2.35619);
}

/// A shipped cell whose arms use `reach auto`: what `cellc info` says it found, per arm.
struct AutoCell {
    path: &'static str,
    /// Per arm: its name and how many boxes were found over each surface, in order.
    boxes: &'static [(&'static str, &'static [(&'static str, usize)])],
    /// Named requests and the strategy each plans.
    requests: &'static [(&'static str, &'static str)],
}

/// The error of the simulated object from the goal that `cellc run` reports, millimetres
/// (none when the goal is a grasp in a workspace, not a pose).
fn final_error_mm(said: &str) -> Option<f64> {
    let line = said
        .lines()
        .find(|l| l.starts_with("final object pose:"))
        .unwrap_or_else(|| panic!("no final pose:\n{said}"));
    let (_, after) = line.split_once("; error ")?;
    let (mm, _) = after.split_once(" mm").expect("millimetres");
    Some(mm.parse().expect("a number"))
}

/// The cell's reach is found (as `cellc info` reports it), it builds with every arc
/// verified, and every named request plans with its strategy from the cell and from the
/// artifact, and runs in the simulator to within the request's tolerance of its goal.
fn builds_verifies_plans_and_runs(cell: &AutoCell) {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let path = cell.path;
    let info = cellc(&["info", path], root, &[]);
    let said = text(&info);
    assert!(info.status.success(), "{path}:\n{said}");
    let arms = if cell.boxes.len() == 1 { "arm" } else { "arms" };
    assert!(
        said.contains(&format!("reach auto ({} {arms})", cell.boxes.len())),
        "{said}"
    );
    for (arm, surfaces) in cell.boxes {
        let total: usize = surfaces.iter().map(|(_, n)| n).sum();
        let header = format!("  {arm}: {total} boxes over the surfaces, ");
        let at = said
            .find(&header)
            .unwrap_or_else(|| panic!("{path}: no `{header}` in\n{said}"));
        // The work and the time it took, then one line per box.
        let (summary, rest) = said[at..].split_once('\n').expect("lines");
        assert!(summary.ends_with(" s"), "{summary}");
        assert!(summary.contains("places tried") && summary.contains("solves"));
        let listed: Vec<&str> = rest.lines().take(total).collect();
        for (surface, n) in *surfaces {
            let over = format!("    over {surface}: box x ");
            let found = listed.iter().filter(|l| l.starts_with(&over)).count();
            assert_eq!(found, *n, "{path}, {arm} over {surface}:\n{said}");
        }
    }

    let out = std::env::temp_dir().join(format!(
        "cellc-robot-files-{}-{}.json",
        std::process::id(),
        Path::new(path).file_stem().unwrap().to_string_lossy()
    ));
    let out_text = out.to_string_lossy().to_string();
    let built = cellc(&["build", path, "-o", &out_text], root, &[]);
    assert!(built.status.success(), "{path}:\n{}", text(&built));
    assert!(text(&built).contains(": 0 pruned"), "{}", text(&built));
    let artifact = std::fs::read_to_string(&out).expect("artifact written");
    // The artifact records where each `package://` mesh was found.
    assert!(artifact.contains("\"written\":\"package://example-robot-data/"));
    for (request, strategy) in cell.requests {
        let from_cell = text(&cellc(&["plan", path, "--request", request], root, &[]));
        let planned = cellc(&["plan", &out_text, "--request", request], root, &[]);
        let said = text(&planned);
        assert!(planned.status.success(), "{path} {request}:\n{said}");
        assert!(said.contains(strategy), "{path} {request}:\n{said}");
        // The cell gives the artifact's boxes, so the same plan.
        assert_eq!(from_cell, said, "{path} {request}");

        let run = cellc(&["run", &out_text, "--request", request], root, &[]);
        let said = text(&run);
        assert!(run.status.success(), "{path} {request}:\n{said}");
        assert!(!said.contains("replan"), "{path} {request}:\n{said}");
        assert!(said.contains("\ndone: "), "{path} {request}:\n{said}");
        // Within the request's position tolerance (the default, 1 cm).
        if let Some(error) = final_error_mm(&said) {
            assert!(error <= 10.0, "{path} {request}: {error} mm off:\n{said}");
        }
    }
    let _ = std::fs::remove_file(&out);
}

#[test]
fn two_pandas_builds_verifies_plans_and_runs() {
    builds_verifies_plans_and_runs(&AutoCell {
        path: "cells/two_pandas.cell",
        boxes: &[("left", &[("table", 3)]), ("right", &[("table", 3)])],
        requests: &[
            ("handoff", "handoff"),
            ("pick_and_place", "pick-and-place"),
            ("regrasp", "regrasp"),
        ],
    });
}

#[test]
fn ur_shelf_builds_verifies_plans_and_runs() {
    builds_verifies_plans_and_runs(&AutoCell {
        path: "cells/ur_shelf.cell",
        boxes: &[("ur", &[("table", 3), ("shelf", 1)])],
        requests: &[("table_to_shelf", "pick-and-place")],
    });
}

/// The shelf's goal is written 1.5 mm above the board (a carry from the table may touch
/// only the table, so it must end clear of the board): the carton is let go there and
/// falls onto the board, as the request's position tolerance says it may; with no drop
/// allowed the simulator refuses the put-down.
#[test]
fn a_carton_let_go_just_above_the_shelf_falls_onto_it() {
    let artifact = built("cells/ur_shelf.cell").artifact.expect("builds");
    let cell = Cell::from_artifact(artifact, &FsFiles).expect("loads");
    let request = cell
        .named_request("table_to_shelf", PlanOptions::default())
        .expect("declared");
    let start = cell
        .request_world(&cell.home_world(), &request)
        .expect("a start");
    let plan = cell
        .plan_move(&start, request.object, &request.goal, &request.options)
        .expect("plans");
    let goal = plan.goal.pose.expect("a goal pose");
    let once = ExecuteOptions {
        max_replans: 0,
        ..ExecuteOptions::default()
    };

    let mut strict = cell
        .simulator(&start, &plan)
        .with_tolerance(SimulatorTolerance {
            drop: 0.0,
            ..SimulatorTolerance::default()
        });
    match cell.execute(&mut start.clone(), plan.clone(), &mut strict, &once) {
        Err(ExecutionError::TooManyFailures {
            last: StepError::NotResting { height_error, .. },
            ..
        }) => assert!((height_error - 0.0015).abs() < 2e-4, "{height_error}"),
        other => panic!("a floating put-down was accepted: {other:?}"),
    }

    let mut simulator = cell
        .simulator(&start, &plan)
        .with_tolerance(SimulatorTolerance {
            drop: request.options.position_tolerance,
            ..SimulatorTolerance::default()
        });
    let run = cell
        .execute(&mut start.clone(), plan, &mut simulator, &once)
        .expect("runs");
    let pose = run.final_pose.expect("a final pose");
    // On the board (top 1.125 m, the carton's centre 6.25 cm above it), under the goal.
    assert!((pose.translation.z - 1.1875).abs() < 2e-4, "{pose:?}");
    let off = pose.translation.vector - goal.translation.vector;
    assert!(
        off.xy().norm() < 2e-4 && (off.z + 0.0015).abs() < 2e-4,
        "{off:?}"
    );
}

/// A package `tiny_robot` (with a COLLADA collision mesh) in `DIR/pkgs`, and a cell in
/// `DIR/cell` that names it by `package://` only.
fn tiny_package(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("cellc-packages-{}-{name}", std::process::id()));
    let write = |path: &str, text: &str| {
        let path = dir.join(path);
        std::fs::create_dir_all(path.parent().expect("parent")).expect("folder");
        std::fs::write(path, text).expect("written");
    };
    write(
        "pkgs/tiny_robot/package.xml",
        "<package format=\"3\"><name>tiny_robot</name></package>\n",
    );
    write(
        "pkgs/tiny_robot/urdf/tiny.urdf",
        r#"<robot name="tiny">
  <link name="base"/>
  <link name="boom">
    <collision><geometry><mesh filename="package://tiny_robot/meshes/box.dae" scale="10 10 10"/></geometry></collision>
  </link>
  <joint name="swing" type="revolute">
    <parent link="base"/><child link="boom"/><origin xyz="0 0 0.1"/><axis xyz="0 0 1"/>
    <limit lower="-1.5" upper="1.5" effort="10" velocity="1"/>
  </joint>
</robot>
"#,
    );
    write(
        "pkgs/tiny_robot/meshes/box.dae",
        r##"<?xml version="1.0"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
  <asset><unit meter="0.001"/><up_axis>Z_UP</up_axis></asset>
  <library_geometries><geometry id="g"><mesh>
    <source id="p"><float_array id="a" count="24">0 0 0 1 0 0 0 1 0 1 1 0 0 0 1 1 0 1 0 1 1 1 1 1</float_array>
      <technique_common><accessor source="#a" count="8" stride="3"/></technique_common></source>
    <vertices id="v"><input semantic="POSITION" source="#p"/></vertices>
  </mesh></geometry></library_geometries>
  <library_visual_scenes><visual_scene id="s"><node><instance_geometry url="#g"/></node></visual_scene></library_visual_scenes>
  <scene><instance_visual_scene url="#s"/></scene>
</COLLADA>
"##,
    );
    write(
        "cell/pick.cell",
        r#"cell pick {
  units m, deg
  robot tiny urdf "package://tiny_robot/urdf/tiny.urdf" base base tip boom
  hand gripper
  support tabletop
  arm left = tiny at (0, 0, 0) with gripper
  reach left box center (0.5, 0, 0.5) size (0.3, 0.3, 0.3)
  surface table : tabletop box center (0.5, 0, 0.4) size (0.4, 0.4, 0.02)
  workspaces from reach
  object ball {
    shape sphere radius 0.04
    rest on_table on tabletop at (0, 0, 0.04)
    grasp power by gripper at (0, 0, 0.1)
    transition on_table <-> power
  }
}
"#,
    );
    dir
}

#[test]
fn packages_are_found_through_the_flag_and_the_environment_in_that_order() {
    let dir = tiny_package("search");
    let check = |args: &[&str], env: &[(&str, &str)]| cellc(args, &dir, env);

    let none = check(&["check", "cell/pick.cell"], &[]);
    assert_eq!(none.status.code(), Some(1));
    assert!(text(&none).contains("E0408"), "{}", text(&none));
    assert!(text(&none).contains("tiny_robot"), "{}", text(&none));

    let flag = check(&["check", "--package-path", "pkgs", "cell/pick.cell"], &[]);
    assert!(flag.status.success(), "{}", text(&flag));
    let env = check(
        &["check", "cell/pick.cell"],
        &[("ROS_PACKAGE_PATH", "/nowhere:pkgs")],
    );
    assert!(env.status.success(), "{}", text(&env));
    // The package itself as a search entry.
    let itself = check(
        &[
            "check",
            "--package-path",
            "pkgs/tiny_robot",
            "cell/pick.cell",
        ],
        &[],
    );
    assert!(itself.status.success(), "{}", text(&itself));

    // The flag comes first: an empty decoy package on it shadows the real one.
    std::fs::create_dir_all(dir.join("decoy/tiny_robot")).expect("decoy");
    std::fs::write(dir.join("decoy/tiny_robot/package.xml"), "<package/>").expect("decoy");
    let shadowed = check(
        &["check", "--package-path", "decoy", "cell/pick.cell"],
        &[("ROS_PACKAGE_PATH", "pkgs")],
    );
    assert_eq!(shadowed.status.code(), Some(1), "{}", text(&shadowed));
    assert!(text(&shadowed).contains("decoy/tiny_robot/urdf/tiny.urdf"));

    // Built with the flag, the artifact knows where the (COLLADA, scaled) mesh is: the
    // runtime reads it from there, and `info` and `plan` need no package path.
    std::fs::create_dir_all(dir.join("out")).expect("output folder");
    let built = check(
        &[
            "build",
            "--package-path",
            "pkgs",
            "cell/pick.cell",
            "-o",
            "out/pick.json",
        ],
        &[],
    );
    assert!(built.status.success(), "{}", text(&built));
    let artifact = std::fs::read_to_string(dir.join("out/pick.json")).expect("artifact");
    assert!(
        artifact.contains(r#""path":"../pkgs/tiny_robot/meshes/box.dae""#),
        "{artifact}"
    );
    let info = check(&["info", "out/pick.json"], &[]);
    assert!(info.status.success(), "{}", text(&info));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_package_item_comes_before_the_search_folders() {
    let dir = tiny_package("item");
    let cell = std::fs::read_to_string(dir.join("cell/pick.cell")).expect("cell");
    let declared = cell.replace(
        "  units m, deg\n",
        "  units m, deg\n  package tiny_robot at \"../pkgs/tiny_robot\"\n",
    );
    std::fs::write(dir.join("cell/pick.cell"), declared).expect("written");
    std::fs::create_dir_all(dir.join("decoy/tiny_robot")).expect("decoy");
    std::fs::write(dir.join("decoy/tiny_robot/package.xml"), "<package/>").expect("decoy");
    let out = cellc(
        &["check", "--package-path", "decoy", "cell/pick.cell"],
        &dir,
        &[("ROS_PACKAGE_PATH", "decoy")],
    );
    assert!(out.status.success(), "{}", text(&out));
    let _ = std::fs::remove_dir_all(&dir);
}

fn built(path: &str) -> cellc_driver::Built {
    cellc_driver::build(&FsFiles, path, &Default::default())
}

#[test]
fn an_srdf_disabled_pair_changes_the_verdict() {
    // The guard on the base touches the upper arm in every configuration: the build
    // refuses the scene, naming the pair, before any arc.
    let without = built("tests/data/srdf/without_srdf.cell");
    assert!(without.artifact.is_none());
    let codes: Vec<cellc_lang::Code> = without.diagnostics.iter().map(|d| d.code).collect();
    assert_eq!(codes, [cellc_driver::scene_report::codes::HOME_COLLIDES]);
    let message = &without.diagnostics[0].message;
    assert!(
        message.contains("shoulder_guard") && message.contains("lwr_link_2"),
        "{message}"
    );
    // Its SRDF disables the pair: every arc the compiler made is kept, with witnesses.
    let compiled = cellc_driver::build(
        &FsFiles,
        "tests/data/srdf/with_srdf.cell",
        &cellc_driver::BuildOptions::unverified(),
    )
    .artifact
    .expect("compiles");
    let with = built("tests/data/srdf/with_srdf.cell")
        .artifact
        .expect("builds");
    assert_eq!(
        with.robots[0].disabled_collisions,
        [("shoulder_guard".to_string(), "lwr_link_2".to_string())]
    );
    assert!(with.objects[0].graph.pruned.is_empty());
    assert!(!with.objects[0].graph.arcs.is_empty());
    assert_eq!(
        with.objects[0].graph.arcs.len(),
        compiled.objects[0].graph.arcs.len()
    );
    assert!(with.objects[0]
        .graph
        .arcs
        .iter()
        .all(|a| a.witness.is_some()));
}
