//! The shipped robot models as the runtime reads them: the collision solids of the URDFs
//! (primitives and meshes, STL and OBJ, scaled), the errors of models it cannot use, and
//! configurations sampled within the joint limits.

use cellc_runtime::kinematics::random_configuration;
use cellc_runtime::math::{Point, Vec3};
use cellc_runtime::robot::{ChainError, Problem, Robot, RobotError};
use cellc_runtime::MemoryFiles;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

#[path = "support/models.rs"]
mod models;
use models::*;

#[test]
fn lwr_collision_shapes_follow_the_urdf() {
    let robot = lwr();
    let shapes = robot.shapes();
    // (link, frame, number of <collision> elements), base to tip; the flange has none.
    let expected = [
        ("lwr_base_link", 0, 1),
        ("lwr_link_1", 1, 2),
        ("lwr_link_2", 2, 1),
        ("lwr_link_3", 3, 2),
        ("lwr_link_4", 4, 1),
        ("lwr_link_5", 5, 2),
        ("lwr_link_6", 6, 1),
        ("lwr_link_7", 7, 1),
    ];
    let mut at = 0;
    for (link, frame, count) in expected {
        for _ in 0..count {
            assert_eq!(shapes[at].link, link);
            assert_eq!(shapes[at].frame, frame);
            at += 1;
        }
    }
    assert_eq!(shapes.len(), at);

    // The base: a cylinder r 0.07, 0.11 long, centred 0.055 up, along z (parry's
    // cylinders run along y, so the local pose turns y onto z).
    let base = &shapes[0];
    let cylinder = base.shape.as_cylinder().expect("a cylinder");
    assert!((cylinder.radius - 0.07).abs() < 1e-12);
    assert!((cylinder.half_height - 0.055).abs() < 1e-12);
    assert_close(
        &base.local.translation.vector,
        &Vec3::new(0.0, 0.0, 0.055),
        1e-12,
        "base cylinder centre",
    );
    assert_close(
        &(base.local.rotation * Vec3::y()),
        &Vec3::z(),
        1e-9,
        "base axis",
    );
    // The A2 housing: rpy (90, 0, 0) deg lays the URDF cylinder along -y.
    let housing = &shapes[2];
    assert_eq!(housing.link, "lwr_link_1");
    let axis = housing.local.rotation * Vec3::y();
    assert!((axis.y.abs() - 1.0).abs() < 1e-6, "housing axis {axis:?}");
    assert!((housing.shape.as_cylinder().expect("a cylinder").half_height - 0.07).abs() < 1e-12);

    assert!(robot.adjacent_frames(3, 4));
    assert!(robot.adjacent_frames(4, 4));
    assert!(!robot.adjacent_frames(2, 4));

    let belt = conveyor();
    let frames: Vec<(usize, &str)> = belt
        .shapes()
        .iter()
        .map(|s| (s.frame, s.link.as_str()))
        .collect();
    assert_eq!(frames, [(0, "conveyor_base"), (1, "conveyor_carriage")]);
    let bed = belt.shapes()[0].shape.as_cuboid().expect("a box");
    assert_close(&bed.half_extents, &Vec3::new(0.8, 0.15, 0.05), 1e-12, "bed");
}

/// A binary STL of the tetrahedron (0,0,0), (1,0,0), (0,1,0), (0,0,1); its header starts
/// with "solid", as many exporters write it, which naive readers take for ASCII.
fn tetrahedron_stl() -> Vec<u8> {
    let v = [
        [0.0f32, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
    ];
    let faces = [[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]];
    let mut bytes = Vec::new();
    let mut header = [b' '; 80];
    header[..11].copy_from_slice(b"solid tetra");
    bytes.extend_from_slice(&header);
    bytes.extend_from_slice(&(faces.len() as u32).to_le_bytes());
    for face in faces {
        bytes.extend_from_slice(&[0u8; 12]); // normal: readers recompute it
        for corner in face {
            for c in v[corner] {
                bytes.extend_from_slice(&c.to_le_bytes());
            }
        }
        bytes.extend_from_slice(&[0u8; 2]);
    }
    bytes
}

fn mesh_urdf(filename: &str, scale: &str) -> String {
    format!(
        r#"<?xml version="1.0"?>
<robot name="gripper">
  <link name="base"/>
  <link name="finger">
    <collision>
      <origin xyz="0 0 0.5" rpy="0 0 0"/>
      <geometry><mesh filename="{filename}" scale="{scale}"/></geometry>
    </collision>
  </link>
  <link name="tool">
    <collision>
      <origin xyz="0 0 0" rpy="0 0 0"/>
      <geometry><sphere radius="0.01"/></geometry>
    </collision>
  </link>
  <joint name="slide" type="prismatic">
    <parent link="base"/>
    <child link="finger"/>
    <axis xyz="0 0 2"/>
    <limit lower="0" upper="0.1" effort="1" velocity="1"/>
  </joint>
  <joint name="tool_joint" type="fixed">
    <parent link="finger"/>
    <child link="tool"/>
    <origin xyz="0.1 0 0" rpy="0 0 0"/>
  </joint>
</robot>"#
    )
}

fn hull_points(shape: &cellc_runtime::robot::LinkShape) -> Vec<Point> {
    let mut points = shape
        .shape
        .as_convex_polyhedron()
        .expect("a convex hull")
        .points()
        .to_vec();
    points.sort_by(|a, b| {
        a.coords
            .as_slice()
            .partial_cmp(b.coords.as_slice())
            .unwrap_or(std::cmp::Ordering::Equal)
    });
    points
}

#[test]
fn stl_meshes_load_as_scaled_convex_hulls() {
    let mut files = MemoryFiles::default();
    files.insert("cell/meshes/tetra.stl", tetrahedron_stl());
    let urdf = mesh_urdf("../meshes/tetra.stl", "2 2 2");
    let robot = Robot::from_urdf(&urdf, "cell/robots/gripper.urdf", "base", "finger", &files)
        .expect("the mesh loads");
    // The tool hangs off the finger through a fixed joint: it moves with frame 1 but is
    // not on the chain (the tip is the finger).
    let summary: Vec<(&str, usize)> = robot
        .shapes()
        .iter()
        .map(|s| (s.link.as_str(), s.frame))
        .collect();
    assert_eq!(summary, [("finger", 1), ("tool", 1)]);
    assert_close(
        &robot.shapes()[1].local.translation.vector,
        &Vec3::new(0.1, 0.0, 0.0),
        1e-12,
        "tool offset",
    );
    // The axis (0 0 2) is normalised.
    assert_close(&robot.axes()[0], &Vec3::z(), 1e-12, "axis");
    let points = hull_points(&robot.shapes()[0]);
    assert_eq!(
        points,
        [
            Point::new(0.0, 0.0, 0.0),
            Point::new(0.0, 0.0, 2.0),
            Point::new(0.0, 2.0, 0.0),
            Point::new(2.0, 0.0, 0.0)
        ]
    );
}

#[test]
fn ascii_stl_and_obj_meshes_load() {
    let ascii = "solid t\n".to_string()
        + &[
            [[0, 0, 0], [0, 1, 0], [1, 0, 0]],
            [[0, 0, 0], [1, 0, 0], [0, 0, 1]],
            [[0, 0, 0], [0, 0, 1], [0, 1, 0]],
            [[1, 0, 0], [0, 1, 0], [0, 0, 1]],
        ]
        .iter()
        .map(|f| {
            let vertices: String = f
                .iter()
                .map(|v| format!("      vertex {} {} {}\n", v[0], v[1], v[2]))
                .collect();
            format!("  facet normal 0 0 0\n    outer loop\n{vertices}    endloop\n  endfacet\n")
        })
        .collect::<String>()
        + "endsolid t\n";
    let obj =
        "# tetrahedron\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";
    let mut files = MemoryFiles::default();
    files.insert("tetra.stl", ascii.into_bytes());
    files.insert("tetra.obj", obj.as_bytes().to_vec());
    for name in ["tetra.stl", "tetra.obj"] {
        let robot = Robot::from_urdf(
            &mesh_urdf(name, "1 1 0.5"),
            "gripper.urdf",
            "base",
            "finger",
            &files,
        )
        .unwrap_or_else(|e| panic!("{name}: {e}"));
        let points = hull_points(&robot.shapes()[0]);
        assert_eq!(points.len(), 4, "{name}");
        assert!(
            points.contains(&Point::new(0.0, 0.0, 0.5)),
            "{name}: {points:?}"
        );
    }
}

#[test]
fn model_errors_are_reported() {
    let files = MemoryFiles::default();
    let lwr_text = shipped("kuka_lwr4.urdf");
    let load = |text: &str, base: &str, tip: &str| {
        Robot::from_urdf(text, "robots/r.urdf", base, tip, &files).map(|_| ())
    };
    assert_eq!(
        load(&lwr_text, "lwr_base_link", "lwr_hand"),
        Err(RobotError::Chain(ChainError::UnknownLink {
            link: "lwr_hand".to_string()
        }))
    );
    // Upside down: no chain leads from the flange to the base.
    assert_eq!(
        load(&lwr_text, "lwr_flange", "lwr_base_link"),
        Err(RobotError::Chain(ChainError::NoChain {
            base: "lwr_flange".to_string(),
            tip: "lwr_base_link".to_string()
        }))
    );
    assert!(matches!(
        load("<robot name='x'><link", "a", "b"),
        Err(RobotError::Parse(_))
    ));
    match load(
        &mesh_urdf("package://gripper/tetra.stl", "1 1 1"),
        "base",
        "finger",
    ) {
        Err(RobotError::Mesh { link, path, reason }) => {
            assert_eq!(link, "finger");
            assert_eq!(path, "package://gripper/tetra.stl");
            assert!(reason.to_string().contains("package://"), "{reason}");
        }
        other => panic!("expected a mesh error, got {other:?}"),
    }
    match load(&mesh_urdf("missing.stl", "1 1 1"), "base", "finger") {
        Err(RobotError::Mesh { path, .. }) => assert_eq!(path, "robots/missing.stl"),
        other => panic!("expected a mesh error, got {other:?}"),
    }
    let flat = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\n";
    let mut flat_files = MemoryFiles::default();
    flat_files.insert("robots/flat.obj", flat.as_bytes().to_vec());
    assert!(matches!(
        Robot::from_urdf(
            &mesh_urdf("flat.obj", "1 1 1"),
            "robots/r.urdf",
            "base",
            "finger",
            &flat_files
        ),
        Err(RobotError::Mesh { .. })
    ));
    // A zero axis is found when the whole file is checked, before any chain is walked.
    let text = mesh_urdf("x.stl", "1 1 1").replace("0 0 2", "0 0 0");
    assert_eq!(
        load(&text, "base", "finger"),
        Err(RobotError::Unsound(Problem::BadAxis {
            joint: "slide".to_string(),
            axis: [0.0; 3]
        }))
    );
}

#[test]
fn configurations_are_sampled_inside_the_limits() {
    let robot = lwr();
    let mut rng = ChaCha8Rng::seed_from_u64(2);
    for _ in 0..100 {
        assert!(robot.within_limits(&random_configuration(&robot, &mut rng)));
    }
    let mut q = vec![10.0, -10.0, f64::NAN, 0.0, 0.0, 0.0, 0.0];
    robot.clamp_to_limits(&mut q);
    assert!(robot.within_limits(&q));
    assert!(!robot.within_limits(&[0.0; 6]));
}
