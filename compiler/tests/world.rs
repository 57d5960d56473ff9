//! The cell's `world` and `task`s: resolved like requests, lowered into `Artifact.world`
//! and `Artifact.tasks` with the right ids and spans, accepted by the artifact's
//! validation, and refused with a coded diagnostic when they say too little or too much.

use cellc_compiler::{compile, Compilation, MemoryFiles};
use cellc_lang::codes::compile::{
    DUPLICATE_NAME, EMPTY_TASK, PLACED_TWICE, PLACEMENT_GRASP_MISMATCH, SECOND_WORLD, UNKNOWN_NAME,
    WORLD_PLACEMENT_INCOMPLETE,
};
use cellc_lang::Code;
use cellc_schema::{Artifact, Encoding, EndEffectorId, GraspId, ObjectId, WorkspaceId};

/// An abstract cell in the shape of `cells/fig3.cell`, with two objects (the box's grasps
/// are numbered from 0 in the artifact, not by their global ids), a world and a task.
const ABSTRACT: &str = "cell w {
  units m, deg
  workspace w1
  workspace w2
  workspace w3
  adjacent w1 w2
  adjacent w2 w3
  fixed table reaches w1, w2, w3
  movable left_arm reaches w1, w2
  movable right_arm reaches w2, w3

  object cylinder {
    grasp g1 by table
    grasp g4 by left_arm
    grasp g7 by right_arm
    transition g1 <-> g4, g7
    transition g4 <-> g7
  }
  object box {
    grasp on by table
    grasp held by right_arm
    grasp lifted by left_arm
    transition on <-> held, lifted
    transition held <-> lifted
  }

  world {
    cylinder: table.g1 in w1
    box: table at (0.5, 0, 80 cm) rpy (0, 0, 90)
  }
  task clear {
    cylinder to table.g1 in w3
    box to right_arm.held in w3
  }
}
";

fn compiled(files: &[(&str, &str)]) -> Compilation {
    compile(&MemoryFiles::new(files.iter().copied()), files[0].0)
}

fn artifact(source: &str) -> (Compilation, Artifact) {
    let compilation = compiled(&[("w.cell", source)]);
    assert!(
        compilation.diagnostics.is_empty(),
        "{:#?}",
        compilation.diagnostics
    );
    let cell = compilation.cell.as_ref().expect("a resolved cell");
    let artifact = cellc_compiler::artifact::lower(cell, &compilation.graphs, &compilation.sources);
    (compilation, artifact)
}

/// The source text a span of the artifact's table points at.
fn spanned<'a>(artifact: &Artifact, source: &'a str, span: u32) -> &'a str {
    let s = &artifact.spans[span as usize];
    assert_eq!(s.file, 0);
    &source[s.start as usize..s.end as usize]
}

fn end_effector(a: &Artifact, name: &str) -> EndEffectorId {
    let i = a.end_effectors.iter().position(|e| e.name == name);
    EndEffectorId(i.expect("declared") as u32)
}

fn workspace(a: &Artifact, name: &str) -> WorkspaceId {
    let i = a.workspaces.iter().position(|w| w.name == name);
    WorkspaceId(i.expect("declared") as u32)
}

/// A lowered step: object, holder, grasp, workspace, and its source line.
type Step<'a> = (
    ObjectId,
    EndEffectorId,
    Option<GraspId>,
    Option<WorkspaceId>,
    &'a str,
);

#[test]
fn world_and_task_lower_with_ids_and_spans() {
    let (_, a) = artifact(ABSTRACT);
    let table = end_effector(&a, "table");
    assert_eq!(a.world.len(), 2);
    let cylinder = &a.world[0];
    assert_eq!(cylinder.object, ObjectId(0));
    assert_eq!(cylinder.placement.end_effector, table);
    assert_eq!(cylinder.placement.grasp, Some(GraspId(0)));
    assert_eq!(cylinder.placement.workspace, Some(workspace(&a, "w1")));
    assert_eq!(cylinder.placement.pose, None);
    assert_eq!(
        spanned(&a, ABSTRACT, cylinder.span),
        "cylinder: table.g1 in w1"
    );
    let boxed = &a.world[1];
    assert_eq!(boxed.object, ObjectId(1));
    assert_eq!(boxed.placement.grasp, None);
    assert_eq!(boxed.placement.workspace, None);
    let pose = boxed.placement.pose.as_ref().expect("a pose");
    // 80 cm in metres, 90 deg about z in radians: a quarter turn, `[x, y, z, w]` with
    // z = w = sin 45 deg.
    assert!((pose.translation[2] - 0.8).abs() < 1e-12, "{pose:?}");
    let half = std::f64::consts::FRAC_1_SQRT_2;
    for (got, want) in pose.rotation.iter().zip([0.0, 0.0, half, half]) {
        assert!((got - want).abs() < 1e-9, "{pose:?}");
    }

    assert_eq!(a.tasks.len(), 1);
    let task = &a.tasks[0];
    assert_eq!(task.name, "clear");
    assert!(spanned(&a, ABSTRACT, task.span).starts_with("task clear {"));
    let steps: Vec<Step> = task
        .steps
        .iter()
        .map(|s| {
            (
                s.object,
                s.to.end_effector,
                s.to.grasp,
                s.to.workspace,
                spanned(&a, ABSTRACT, s.span),
            )
        })
        .collect();
    let w3 = Some(workspace(&a, "w3"));
    assert_eq!(
        steps,
        [
            (
                ObjectId(0),
                table,
                Some(GraspId(0)),
                w3,
                "cylinder to table.g1 in w3"
            ),
            (
                ObjectId(1),
                end_effector(&a, "right_arm"),
                // `held` is the box's second grasp (the fifth of the cell).
                Some(GraspId(1)),
                w3,
                "box to right_arm.held in w3"
            ),
        ]
    );
}

#[test]
fn the_artifact_with_a_world_and_a_task_validates_and_round_trips() {
    let (_, a) = artifact(ABSTRACT);
    cellc_schema::validate::validate(&a).expect("valid");
    for encoding in [Encoding::Json, Encoding::Binary] {
        let (back, _) = Artifact::from_bytes(&a.to_bytes(encoding)).expect("reads back");
        assert_eq!(back.world, a.world);
        assert_eq!(back.tasks, a.tasks);
    }
}

#[test]
fn a_cell_without_a_world_has_no_objects_placed() {
    let source = ABSTRACT
        .split("  world {")
        .next()
        .expect("the items before the world")
        .to_string()
        + "}\n";
    let (compilation, a) = artifact(&source);
    assert!(a.world.is_empty() && a.tasks.is_empty());
    assert!(compilation.cell.expect("resolved").world_origin.is_none());
}

/// A geometric cell with one arm: a bare `ARM.GRASP` places an object in the hand (no
/// workspace, no pose); on the table a placement needs `in` or `at`.
fn geometric_cell(world: &str, task: &str) -> Compilation {
    let urdf = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../cells/robots/kuka_lwr4.urdf"
    ))
    .expect("the shipped LWR URDF");
    let source = format!(
        "cell g {{
  units m, deg
  robot lwr4 urdf \"kuka_lwr4.urdf\" base lwr_base_link tip lwr_flange
  hand softhand
  support tabletop
  arm left = lwr4 at (0, 0, 1) with softhand
  reach left box center (0.5, 0, 1.0) size (0.4, 0.4, 0.3)
  surface table : tabletop box center (0.5, 0, 0.8) size (1, 1, 0.1)
  workspaces from reach
  object ball {{
    shape sphere radius 0.05
    rest on_table on tabletop at (0, 0, 0.05)
    grasp power by softhand at (0, 0, 0.1)
    transition on_table <-> power
  }}
  object cube {{
    shape box size (0.05, 0.05, 0.05)
    rest flat on tabletop at (0, 0, 0.025)
    grasp pinch by softhand at (0, 0, 0.1)
    transition flat <-> pinch
  }}
{world}
{task}
}}
"
    );
    compiled(&[("g.cell", &source), ("kuka_lwr4.urdf", &urdf)])
}

/// The code, message and help of each diagnostic of [`geometric_cell`].
fn geometric(world: &str, task: &str) -> Vec<(Code, String, String)> {
    geometric_cell(world, task)
        .diagnostics
        .iter()
        .map(|d| {
            (
                d.code,
                d.message.clone(),
                d.help.clone().unwrap_or_default(),
            )
        })
        .collect()
}

fn codes(found: &[(Code, String, String)]) -> Vec<Code> {
    found.iter().map(|(c, _, _)| *c).collect()
}

#[test]
fn a_bare_grasp_of_an_arm_is_a_hand_holding_the_object() {
    let compilation = geometric_cell(
        "  world {\n    ball: left.power\n    cube: table at (0.5, 0.1, 0.875)\n  }",
        "  task t {\n    ball to table at (0.5, -0.1, 0.9)\n  }",
    );
    assert!(!compilation.has_errors(), "{:#?}", compilation.diagnostics);
    let cell = compilation.cell.as_ref().expect("resolved");
    let a = cellc_compiler::artifact::lower(cell, &compilation.graphs, &compilation.sources);
    let held = &a.world[0].placement;
    assert_eq!(held.end_effector, end_effector(&a, "left"));
    assert_eq!(held.grasp, Some(GraspId(1)));
    assert_eq!((held.workspace, held.pose), (None, None));
    cellc_schema::validate::validate(&a).expect("valid");
}

#[test]
fn a_bare_placement_that_says_too_little_is_e0106() {
    let found = geometric("  world {\n    ball: table.on_table\n  }", "");
    assert_eq!(codes(&found), [WORLD_PLACEMENT_INCOMPLETE], "{found:#?}");
    assert_eq!(found[0].1, "the world does not say where `ball` is");
    assert!(
        found[0]
            .2
            .starts_with("write `table.on_table in WORKSPACE` or `table.on_table at (x, y, z)`"),
        "{found:#?}"
    );
    let found = geometric("  world {\n    cube: left\n  }", "");
    assert_eq!(codes(&found), [WORLD_PLACEMENT_INCOMPLETE], "{found:#?}");
    assert_eq!(found[0].1, "the world does not say how `left` holds `cube`");
    assert!(found[0].2.contains("e.g. `left.pinch`"), "{found:#?}");
}

#[test]
fn a_grasp_its_holder_cannot_hold_is_e0316_in_the_world_and_in_tasks() {
    let found = geometric(
        "  world {\n    ball: left.on_table\n  }",
        "  task t {\n    cube to table.pinch at (0.5, 0, 0.875)\n  }",
    );
    assert_eq!(
        codes(&found),
        [PLACEMENT_GRASP_MISMATCH, PLACEMENT_GRASP_MISMATCH],
        "{found:#?}"
    );
}

#[test]
fn an_object_placed_twice_is_e0105_naming_both_lines() {
    let found = compiled(&[(
        "w.cell",
        &ABSTRACT.replace(
            "    box: table at",
            "    cylinder: left_arm.g4 in w2\n    box: table at",
        ),
    )]);
    let [d] = compilation_errors(&found)[..] else {
        panic!("{:#?}", found.diagnostics);
    };
    assert_eq!(d.code, PLACED_TWICE);
    assert_eq!(d.message, "`cylinder` is placed twice in the world");
    let source = found.sources.get(cellc_lang::FileId(0)).text.clone();
    let under: Vec<&str> = d
        .labels
        .iter()
        .map(|l| &source[l.span.start as usize..l.span.end as usize])
        .collect();
    assert_eq!(
        under,
        ["cylinder: left_arm.g4 in w2", "cylinder: table.g1 in w1"]
    );
}

fn compilation_errors(c: &Compilation) -> Vec<&cellc_lang::Diagnostic> {
    c.diagnostics.iter().filter(|d| d.is_error()).collect()
}

#[test]
fn a_second_world_even_in_a_library_is_e0104() {
    let library = "library places {\n  world {\n    box: table.on in w2\n  }\n}\n";
    let cell = ABSTRACT.replace(
        "  units m, deg\n",
        "  units m, deg\n  include \"places.cell\"\n",
    );
    let found = compiled(&[("w.cell", &cell), ("places.cell", library)]);
    let [d] = compilation_errors(&found)[..] else {
        panic!("{:#?}", found.diagnostics);
    };
    assert_eq!(d.code, SECOND_WORLD);
    // The main file's world comes first; the library's is the second.
    let files: Vec<u32> = d.labels.iter().map(|l| l.file.0).collect();
    assert_eq!(files, [1, 0]);
    // The world that counts is the first one, whole.
    let cell = found.cell.expect("resolved");
    assert_eq!(cell.world.len(), 2);
}

#[test]
fn a_task_without_steps_is_e0107() {
    let source = format!(
        "{}  task nothing {{}}\n}}\n",
        ABSTRACT.trim_end().trim_end_matches('}')
    );
    let found = compiled(&[("w.cell", &source)]);
    let [d] = compilation_errors(&found)[..] else {
        panic!("{:#?}", found.diagnostics);
    };
    assert_eq!(d.code, EMPTY_TASK);
    assert_eq!(d.message, "task `nothing` has no steps");
}

#[test]
fn tasks_and_requests_share_one_namespace() {
    let source = format!(
        "{}  request clear: box from table in w1 to table in w2\n  task clear {{\n    box to table in w1\n  }}\n}}\n",
        ABSTRACT.trim_end().trim_end_matches('}')
    );
    let found = compiled(&[("w.cell", &source)]);
    let messages: Vec<(Code, &str)> = compilation_errors(&found)
        .iter()
        .map(|d| (d.code, d.labels[0].message.as_str()))
        .collect();
    assert_eq!(
        messages,
        [
            (DUPLICATE_NAME, "request `clear` declared again here"),
            (DUPLICATE_NAME, "task `clear` declared again here"),
        ]
    );
}

#[test]
fn steps_resolve_names_like_requests_with_suggestions() {
    let source = ABSTRACT.replace("box to right_arm.held in w3", "bx to right_arm.hold in w3x");
    let found = compiled(&[("w.cell", &source)]);
    let helps: Vec<(Code, Option<&str>)> = compilation_errors(&found)
        .iter()
        .map(|d| (d.code, d.help.as_deref()))
        .collect();
    assert_eq!(
        helps,
        [
            (UNKNOWN_NAME, Some("did you mean `box`?")),
            (UNKNOWN_NAME, Some("did you mean `w3`?")),
        ]
    );
    // Nothing of a task with a broken step reaches the cell.
    assert!(found.cell.expect("resolved").tasks.is_empty());
}
