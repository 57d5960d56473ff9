//! The fixture shared by the motion tests and benchmarks: small geometric cells built as
//! artifact values (the runtime never depends on the compiler): LWR arms with SoftHand
//! solids, boxes as fixed surfaces, one cylinder.
#![allow(dead_code)]

use std::f64::consts::FRAC_PI_6;

use cellc_runtime::math::{iso_to_schema, Iso, Quat};
use cellc_runtime::robot::Robot;
use cellc_runtime::{FileError, Files};
use cellc_schema as schema;

/// Reads files from the repository (paths relative to the workspace root).
pub struct Repo;

impl Files for Repo {
    fn read(&self, path: &str) -> Result<Vec<u8>, FileError> {
        let full = format!("{}/../{path}", env!("CARGO_MANIFEST_DIR"));
        Ok(std::fs::read(full)?)
    }
}

pub const URDF: &str = "cells/robots/kuka_lwr4.urdf";

pub fn pose(x: f64, y: f64, z: f64, rpy: [f64; 3]) -> schema::Pose {
    iso_to_schema(&Iso::from_parts(
        nalgebra::Translation3::new(x, y, z),
        Quat::from_euler_angles(rpy[0], rpy[1], rpy[2]),
    ))
}

pub fn solid(shape: schema::Shape, at: schema::Pose) -> schema::Solid {
    schema::Solid { shape, pose: at }
}

/// The SoftHand's solids, as in `cells/robots/softhand.cell`.
pub fn softhand() -> schema::HolderKind {
    schema::HolderKind {
        name: "softhand".into(),
        class: schema::HolderClass::Hand,
        solids: vec![
            solid(
                schema::Shape::Cylinder {
                    radius: 0.035,
                    height: 0.02,
                },
                pose(0.0, 0.0, 0.01, [0.0; 3]),
            ),
            solid(
                schema::Shape::Box {
                    size: [0.09, 0.03, 0.10],
                },
                pose(0.0, 0.0, 0.07, [0.0; 3]),
            ),
            solid(
                schema::Shape::Box {
                    size: [0.085, 0.025, 0.085],
                },
                pose(0.0, 0.0, 0.1625, [0.0; 3]),
            ),
            solid(
                schema::Shape::Cylinder {
                    radius: 0.012,
                    height: 0.07,
                },
                pose(0.05, 0.0325, 0.0803, [-FRAC_PI_6, 0.0, 0.0]),
            ),
        ],
    }
}

/// A cell: upright LWR arms with SoftHands (`arms`: name, base position and yaw), fixed
/// boxes (`boxes`: name, min, max), and one cylinder `can` (radius 4 cm, height 30 cm).
pub fn artifact(
    arms: &[(&str, [f64; 4])],
    boxes: &[(&str, [f64; 3], [f64; 3])],
) -> schema::Artifact {
    let bytes = Repo.read(URDF).expect("the LWR URDF is in the repository");
    let sha = schema::sha256_hex(&bytes);
    let lwr = lwr();
    let (lower, upper) = lwr.limits();
    let joints = lwr
        .joint_names()
        .iter()
        .zip(lower.iter().zip(upper))
        .map(|(name, (&lo, &hi))| schema::Joint {
            name: name.clone(),
            prismatic: false,
            lower: lo.is_finite().then_some(lo),
            upper: hi.is_finite().then_some(hi),
            velocity: 1.0,
            acceleration: 2.0,
            jerk: None,
        })
        .collect();
    let mut end_effectors: Vec<schema::EndEffector> = arms
        .iter()
        .map(|(name, [x, y, z, yaw])| schema::EndEffector {
            name: (*name).into(),
            movable: true,
            kind: Some(0),
            body: schema::Body::Arm {
                robot: 0,
                base: pose(*x, *y, *z, [0.0, 0.0, *yaw]),
                home: vec![0.0; 7],
            },
            reach_boxes: Vec::new(),
            reaches: Vec::new(),
            span: 0,
        })
        .collect();
    end_effectors.extend(boxes.iter().map(|(name, min, max)| schema::EndEffector {
        name: (*name).into(),
        movable: false,
        kind: None,
        body: schema::Body::Surface {
            slab: schema::Aabb {
                min: *min,
                max: *max,
            },
            reach_height: 0.3,
        },
        reach_boxes: Vec::new(),
        reaches: Vec::new(),
        span: 0,
    }));
    schema::Artifact {
        format: schema::FORMAT.into(),
        format_version: schema::FORMAT_VERSION,
        compiler_version: "test".into(),
        cell: "motion".into(),
        sources: Vec::new(),
        weights: schema::Weights {
            move_weight: 1.0,
            transition_weight: 1.0,
        },
        robots: vec![schema::Robot {
            name: "lwr4".into(),
            urdf_path: URDF.into(),
            urdf_sha256: sha,
            meshes: Vec::new(),
            srdf: None,
            disabled_collisions: Vec::new(),
            base_link: "lwr_base_link".into(),
            tip_link: "lwr_flange".into(),
            joints,
            span: 0,
        }],
        holder_kinds: vec![softhand()],
        workspaces: Vec::new(),
        end_effectors,
        objects: vec![schema::Object {
            name: "can".into(),
            shape: Some(schema::Shape::Cylinder {
                radius: 0.04,
                height: 0.3,
            }),
            symmetries: Vec::new(),
            grasps: Vec::new(),
            transitions: Vec::new(),
            graph: schema::Graph::default(),
            span: 0,
        }],
        spans: Vec::new(),
        obstacles: Vec::new(),
        adjacency: None,
        allowed_contacts: Vec::new(),
        verification: None,
        requests: Vec::new(),
        world: Vec::new(),
        tasks: Vec::new(),
    }
}

/// The shipped KUKA LWR 4+ model.
pub fn lwr() -> Robot {
    let bytes = Repo.read(URDF).expect("the LWR URDF is in the repository");
    let text = String::from_utf8(bytes).expect("the URDF is UTF-8");
    Robot::from_urdf(&text, URDF, "lwr_base_link", "lwr_flange", &Repo).expect("the LWR loads")
}
