//! Grasp and rest families: members' names and counts, symmetric members kept once, the
//! transitions between families (every pair, or `matching`), grasp-set files, and the
//! limits (E0323 to E0327).

use cellc_compiler::{compile, Compilation, MemoryFiles};
use cellc_lang::codes::compile::{
    BAD_GRASP_FILE, DUPLICATE_NAME, FAMILY_EMPTY, FAMILY_MISMATCH, FAMILY_TOO_LARGE,
    FILE_UNREADABLE,
};
use cellc_lang::{Code, Severity};

fn compiled(files: &[(&str, &str)]) -> Compilation {
    compile(&MemoryFiles::new(files.iter().copied()), files[0].0)
}

/// An abstract cell with `members` as the object's lines.
fn cell(members: &str) -> String {
    format!(
        "cell f {{
  units m, deg
  workspace w1
  workspace w2
  adjacent w1 w2
  fixed table reaches w1, w2
  movable left reaches w1, w2
  movable right reaches w1, w2
  hand paw
  object o {{
    shape cylinder radius 0.04 height 0.2
{members}
  }}
}}
"
    )
}

/// The codes of the errors (the unused-grasp warnings of the small cells left out).
fn codes(c: &Compilation) -> Vec<Code> {
    c.diagnostics
        .iter()
        .map(|d| d.code)
        .filter(|code| code.severity() == Severity::Error)
        .collect()
}

/// The object's grasps' names, in order.
fn grasp_names(c: &Compilation) -> Vec<String> {
    let cell = c.cell.as_ref().expect("a cell");
    let (_, object) = cell.objects.iter().next().expect("an object");
    object
        .grasps
        .iter()
        .map(|&g| cell.grasps[g].name.clone())
        .collect()
}

/// Directed transitions as (from, to) names.
fn transitions(c: &Compilation) -> Vec<(String, String)> {
    let cell = c.cell.as_ref().expect("a cell");
    let mut out: Vec<(String, String)> = cell
        .transitions
        .iter()
        .map(|t| {
            (
                cell.grasps[t.from].name.clone(),
                cell.grasps[t.to].name.clone(),
            )
        })
        .collect();
    out.sort();
    out
}

#[test]
fn members_are_named_by_index_in_clause_order() {
    let src = cell(
        "    rest down on table\n    grasp side by left at (0, 0.06, 0.1) every 90 deg about x along z at (-5 cm, 0, 5 cm)\n    transition down <-> side",
    );
    let c = compiled(&[("f.cell", &src)]);
    assert!(codes(&c).is_empty(), "{:?}", c.diagnostics);
    let names = grasp_names(&c);
    assert_eq!(names.len(), 1 + 4 * 3);
    assert_eq!(names[1], "side_0_0");
    assert_eq!(names[2], "side_0_1");
    assert_eq!(names[4], "side_1_0");
    assert_eq!(names[12], "side_3_2");
    // Every member joins the rest both ways.
    assert_eq!(transitions(&c).len(), 2 * 12);
}

#[test]
fn member_poses_move_the_holder_round_the_object() {
    let src = cell("    grasp side by left at (0, 0.06, 0) every 90 deg about z along z at (0, 0.05)\n    rest down on table\n    transition down <-> side");
    let c = compiled(&[("f.cell", &src)]);
    let cell = c.cell.as_ref().unwrap();
    let pose = |name: &str| {
        let (id, _) = cell.grasps.iter().find(|(_, g)| g.name == name).unwrap();
        cell.grasps[id].pose.unwrap()
    };
    // The hand moved 5 cm up along the object's z: the object is 5 cm lower in the hand.
    let up = pose("side_0_1");
    assert!((up.translation.vector.z + 0.05).abs() < 1e-12, "{up:?}");
    // The hand turned by 90° about z: the object's origin is where it was in the hand,
    // the object turned by -90° in it.
    let turned = pose("side_1_0");
    assert!((turned.translation.vector.y - 0.06).abs() < 1e-12);
    let expected = nalgebra::UnitQuaternion::from_axis_angle(
        &nalgebra::Vector3::z_axis(),
        -std::f64::consts::FRAC_PI_2,
    );
    assert!(turned.rotation.angle_to(&expected) < 1e-12);
}

#[test]
fn symmetric_members_are_one_state_and_their_names_aliases() {
    // `symmetry about z`: every turn about z is the same grasp.
    let src = cell("    symmetry about z\n    rest down on table\n    grasp side by left at (0, 0.06, 0.1) every 30 deg about z\n    transition down <-> side_7");
    let c = compiled(&[("f.cell", &src)]);
    assert!(codes(&c).is_empty(), "{:?}", c.diagnostics);
    assert_eq!(grasp_names(&c), ["down", "side_0"]);
    assert_eq!(
        transitions(&c),
        [
            ("down".into(), "side_0".into()),
            ("side_0".into(), "down".into())
        ]
    );
    // Order 2 (written after the family: the order of lines does not matter): half of
    // the twelve turns are new.
    let src = cell("    rest down on table\n    grasp side by left at (0, 0.06, 0.1) every 30 deg about z\n    symmetry about z order 2\n    transition down <-> side");
    let c = compiled(&[("f.cell", &src)]);
    let names = grasp_names(&c);
    assert_eq!(names.len(), 1 + 6, "{names:?}");
    assert_eq!(names[6], "side_5");
    assert_eq!(transitions(&c).len(), 2 * 6);
    // Without symmetry all twelve stay.
    let src = cell("    rest down on table\n    grasp side by left at (0, 0.06, 0.1) every 30 deg about z\n    transition down <-> side");
    assert_eq!(grasp_names(&compiled(&[("f.cell", &src)])).len(), 13);
}

#[test]
fn families_join_every_pair_or_matching_pairs() {
    let src = cell("    grasp a by left at (0, 0, 0.1) along z at (0, 0.01, 0.02)\n    grasp b by right at (0, 0, -0.1) along z at (0, 0.01, 0.02)\n    rest down on table\n    transition down <-> a, b\n    transition a <-> b matching");
    let c = compiled(&[("f.cell", &src)]);
    assert!(codes(&c).is_empty(), "{:?}", c.diagnostics);
    let t = transitions(&c);
    // 2 x 6 with the rest, then 2 x 3 matching pairs.
    assert_eq!(t.len(), 12 + 6);
    assert!(t.contains(&("a_1".into(), "b_1".into())));
    assert!(!t.contains(&("a_0".into(), "b_1".into())));
    let src = cell("    grasp a by left at (0, 0, 0.1) along z at (0, 0.01, 0.02)\n    grasp b by right at (0, 0, -0.1) along z at (0, 0.01, 0.02)\n    rest down on table\n    transition down <-> a, b\n    transition a <-> b");
    let c = compiled(&[("f.cell", &src)]);
    assert_eq!(transitions(&c).len(), 12 + 18);
}

#[test]
fn limits_and_misuse_are_coded() {
    let c = compiled(&[("f.cell", &cell("    grasp a by left every 0 deg about z"))]);
    assert_eq!(codes(&c), [FAMILY_EMPTY]);
    let c = compiled(&[("f.cell", &cell("    grasp a by left every 0.1 deg about z"))]);
    assert_eq!(codes(&c), [FAMILY_TOO_LARGE]);
    let c = compiled(&[("f.cell", &cell("    grasp a by left every 10 deg about z along z at (0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15, 16, 17, 18, 19, 20, 21, 22, 23, 24, 25, 26, 27, 28)"))]);
    assert_eq!(codes(&c), [FAMILY_TOO_LARGE]);
    let c = compiled(&[("f.cell", &cell("    grasp a by left every 90 deg about z\n    grasp b by right along z at (0, 1)\n    transition a <-> b matching"))]);
    assert_eq!(codes(&c), [FAMILY_MISMATCH]);
    let c = compiled(&[(
        "f.cell",
        &cell("    grasp a by left every 90 deg about z\n    grasp a_1 by right"),
    )]);
    assert_eq!(codes(&c), [DUPLICATE_NAME]);
}

#[test]
fn a_grasp_set_file_gives_one_member_per_row() {
    let mut rows = String::from("# from a planner\nx,y,z,qx,qy,qz,qw\n");
    for i in 0..200 {
        rows.push_str(&format!("0,0,{},0,0,0,1\n", f64::from(i) * 0.001));
    }
    let src = cell("    rest down on table\n    grasp planned by left from \"grasps/o.csv\"\n    transition down <-> planned");
    let c = compiled(&[("f.cell", &src), ("grasps/o.csv", &rows)]);
    assert!(codes(&c).is_empty(), "{:?}", c.diagnostics);
    let names = grasp_names(&c);
    assert_eq!(names.len(), 201);
    assert_eq!(names[200], "planned_199");
    // A bad row is an error in the file, and the family is not expanded.
    let bad = "x,y,z,qx,qy,qz,qw\n0,0,0,0,0,0,1\n0,0,nope,0,0,0,1\n";
    let c = compiled(&[("f.cell", &src), ("grasps/o.csv", bad)]);
    assert_eq!(codes(&c), [BAD_GRASP_FILE]);
    let error = c.diagnostics.iter().find(|d| d.is_error()).unwrap();
    let label = &error.labels[0];
    assert_eq!(c.sources.get(label.file).path, "grasps/o.csv");
    assert_eq!(&bad[label.span.range()], "nope");
    // A missing file is reported at the name.
    let c = compiled(&[("f.cell", &src)]);
    assert_eq!(codes(&c), [FILE_UNREADABLE]);
}
