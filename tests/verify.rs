//! Build-time verification of arcs: every witness passes an independent re-check (joint
//! limits, forward kinematics back to the recorded object pose, the object inside the
//! arc's workspace, no collision), impossible arcs are pruned with the right reason,
//! results are the same for a seed, and the runtime's own diagnostics (W0006, R00xx) have
//! UI tests.

use cellc_driver::fs_files::FsFiles;
use cellc_driver::BuildOptions;
use cellc_runtime::math::{iso_from_schema, Iso, Point};
use cellc_runtime::scene::{Holder, ObjectPlacement, Scene, SceneScratch};
use cellc_runtime::verify::{verify, VerifyOptions};
use cellc_runtime::Files;
use cellc_schema::{
    ArcKind, Artifact, Body, Encoding, EndEffectorId, GraspId, Infeasibility, ObjectId,
};

/// The artifact of `path` as `cellc build --no-verify` gives it (with the runtime's
/// kinematics for `reach auto`).
fn build(path: &str) -> Artifact {
    cellc_driver::build(&FsFiles, path, &BuildOptions::unverified())
        .artifact
        .unwrap_or_else(|| panic!("{path} has errors"))
}

/// `path` built as `cellc build --seed SEED` builds it, with its scene.
fn verified(path: &str, seed: u64) -> (Artifact, Scene) {
    let options = BuildOptions {
        seed,
        ..BuildOptions::default()
    };
    let artifact = cellc_driver::build(&FsFiles, path, &options)
        .artifact
        .unwrap_or_else(|| panic!("{path} has errors"));
    let scene = Scene::load(&artifact, &FsFiles).expect("scene loads");
    (artifact, scene)
}

/// Every shipped cell that has arms.
fn geometric_cells() -> Vec<String> {
    let mut cells: Vec<String> = std::fs::read_dir("cells")
        .expect("cells/ exists")
        .filter_map(Result::ok)
        .map(|e| e.path().to_string_lossy().replace('\\', "/"))
        .filter(|p| p.ends_with(".cell"))
        // The paper-scale cell (25,100 arcs, half a minute of verification in release) is
        // verified once, in tests/vito.rs (its sizes, a witness on every arc, the
        // behaviours); verifying it for every seed and test here would cost CI many
        // minutes, and its arcs are of the kinds vito.cell's rechecks cover.
        .filter(|p| !p.ends_with("_full.cell"))
        .filter(|p| {
            build(p)
                .end_effectors
                .iter()
                .any(|e| matches!(e.body, Body::Arm { .. }))
        })
        .collect();
    cells.sort();
    cells
}

const POSITION_TOLERANCE: f64 = 1e-3;
const ROTATION_TOLERANCE: f64 = 1e-2;

/// Re-checks one witness from scratch: the configurations are within limits, forward
/// kinematics puts the object where the witness says with the arc's grasps, the object's
/// centre is in the arc's workspace, and the whole state is collision-free.
fn recheck(
    artifact: &Artifact,
    scene: &Scene,
    object: usize,
    arc: &cellc_schema::Arc,
) -> Result<(), String> {
    let obj = &artifact.objects[object];
    let witness = &obj.graph.witnesses[arc.witness.ok_or("no witness")? as usize];
    let object_pose = iso_from_schema(&witness.object);
    let from = obj.graph.nodes[arc.from as usize];
    let to = obj.graph.nodes[arc.to as usize];
    let grasp = |g: GraspId| {
        obj.grasps[g.index()]
            .pose
            .as_ref()
            .map(iso_from_schema)
            .unwrap_or_else(Iso::identity)
    };
    let center = Point::from(object_pose.translation.vector);
    if !scene.workspaces[to.workspace.index()]
        .iter()
        .any(|b| cellc_runtime::math::contains_point(b, &center))
    {
        return Err(format!(
            "object centre {center} is outside workspace {}",
            to.workspace
        ));
    }
    let mut arms: Vec<(EndEffectorId, &[f64])> = Vec::new();
    for config in &witness.configurations {
        let Holder::Arm { robot, base, .. } = &scene.holders[config.end_effector.index()] else {
            return Err("a configuration of something that is not an arm".into());
        };
        let robot = &scene.robots[*robot];
        if !robot.within_limits(&config.joints) {
            return Err(format!("joints outside limits: {:?}", config.joints));
        }
        // The held node's grasp for this arm.
        let g = if config.end_effector == to.end_effector {
            to.grasp
        } else {
            from.grasp
        };
        // Up to a symmetry of the object: a symmetric object held in a turned grasp is the
        // same placement.
        let through_arm = robot.tip_pose(base, &config.joints) * grasp(g);
        let relative = object_pose.inverse() * through_arm;
        let turn = cellc_schema::symmetry::residual(&relative.rotation, &obj.symmetries);
        if relative.translation.vector.norm() > POSITION_TOLERANCE || turn > ROTATION_TOLERANCE {
            return Err(format!(
                "arm {} does not hold the object where the witness says",
                config.end_effector
            ));
        }
        arms.push((config.end_effector, &config.joints));
    }
    let surface = [from, to].into_iter().find(|n| {
        matches!(
            scene.holders[n.end_effector.index()],
            Holder::Surface { .. }
        )
    });
    let placement = match (arc.kind, surface) {
        (ArcKind::Transition, Some(s)) => {
            let Holder::Surface { slab, .. } = &scene.holders[s.end_effector.index()] else {
                unreachable!()
            };
            // Resting: on the top face, in the resting pose up to a turn about the vertical.
            let rest = grasp(s.grasp);
            let height = object_pose.translation.vector.z - slab.maxs.z;
            if (height - rest.translation.vector.z).abs() > POSITION_TOLERANCE {
                return Err(format!(
                    "object is {height} m above the surface, its resting pose says {}",
                    rest.translation.vector.z
                ));
            }
            ObjectPlacement::Resting {
                on: s.end_effector,
                pose: object_pose,
                by: arms.first().map(|a| a.0),
            }
        }
        (ArcKind::Transition, None) => ObjectPlacement::Handoff {
            a: arms[0].0,
            grasp_a: grasp(if arms[0].0 == to.end_effector {
                to.grasp
            } else {
                from.grasp
            }),
            b: arms[1].0,
        },
        (ArcKind::Move, _) => ObjectPlacement::Held {
            by: to.end_effector,
            grasp: grasp(to.grasp),
        },
    };
    let mut scratch = SceneScratch::default();
    match scene.collision(&arms, ObjectId(object as u32), placement, &[], &mut scratch) {
        Ok(None) => Ok(()),
        Ok(Some((a, b))) => Err(format!("{a} collides with {b}")),
        Err(e) => Err(format!("query failed: {e:?}")),
    }
}

#[test]
fn every_witness_of_every_shipped_geometric_cell_passes_a_recheck() {
    let cells = geometric_cells();
    assert!(!cells.is_empty(), "no shipped cell has arms");
    for cell in cells {
        let (artifact, scene) = verified(&cell, 0);
        let verification = artifact.verification.as_ref().expect("verified");
        let mut rechecked = 0;
        for (o, object) in artifact.objects.iter().enumerate() {
            for arc in &object.graph.arcs {
                if arc.witness.is_some() {
                    recheck(&artifact, &scene, o, arc)
                        .unwrap_or_else(|e| panic!("{cell}, {}: {e}", object.name));
                    rechecked += 1;
                }
            }
            // Every arc between geometric holders was decided: kept with a witness or pruned.
            for arc in &object.graph.arcs {
                let holders = [arc.from, arc.to]
                    .map(|n| &scene.holders[object.graph.nodes[n as usize].end_effector.index()]);
                let geometric = holders.iter().any(|h| matches!(h, Holder::Arm { .. }));
                assert!(
                    !geometric || arc.witness.is_some(),
                    "{cell}: an arc kept without a witness"
                );
            }
        }
        assert!(rechecked > 0, "{cell}: nothing was verified");
        assert_eq!(
            verification.n_checked as usize,
            rechecked + verification.n_pruned as usize
        );
    }
}

#[test]
fn an_impossible_handoff_is_pruned_with_its_reason() {
    let (artifact, _) = verified("tests/data/verify/far_arms.cell", 0);
    let ball = &artifact.objects[0];
    assert!(
        ball.graph.arcs.is_empty(),
        "an arc survived: {:?}",
        ball.graph.arcs
    );
    assert_eq!(ball.graph.pruned.len(), 2);
    for pruned in &ball.graph.pruned {
        match &pruned.reason {
            Infeasibility::NoClosedChain { position_error, .. } => {
                assert!(
                    *position_error > 1.0,
                    "3 m apart, the hands stay far apart: {position_error}"
                )
            }
            other => panic!("wrong reason: {other:?}"),
        }
    }
}

/// A transition between two grasps of one arm (kept by the compiler, with W0004) is
/// refused at verification with its reason, never kept without a witness; the other arcs
/// are verified as usual.
#[test]
fn a_regrasp_within_one_hand_is_refused_not_kept() {
    let (artifact, scene) = verified("tests/ui/runtime/W0006_same_hand_regrasp.cell", 0);
    let cylinder = &artifact.objects[0];
    let graph = &cylinder.graph;
    let same_hand = |arc: &cellc_schema::Arc| {
        arc.kind == ArcKind::Transition
            && graph.nodes[arc.from as usize].end_effector
                == graph.nodes[arc.to as usize].end_effector
    };
    assert!(!graph.arcs.iter().any(same_hand), "a regrasp was kept");
    let refused: Vec<_> = graph.pruned.iter().filter(|p| same_hand(&p.arc)).collect();
    assert_eq!(refused.len(), 2, "both directions are refused");
    for pruned in refused {
        match &pruned.reason {
            Infeasibility::NoPlacement { detail } => assert!(
                detail.contains("cannot pass the object to itself"),
                "{detail}"
            ),
            other => panic!("wrong reason: {other:?}"),
        }
    }
    assert!(!graph.arcs.is_empty(), "the arcs through the table remain");
    for arc in &graph.arcs {
        recheck(&artifact, &scene, 0, arc).unwrap_or_else(|e| panic!("{e}"));
    }
}

#[test]
fn the_same_seed_gives_the_same_artifact() {
    for cell in geometric_cells() {
        let (a, _) = verified(&cell, 7);
        let (b, _) = verified(&cell, 7);
        assert_eq!(
            a.to_bytes(Encoding::Binary),
            b.to_bytes(Encoding::Binary),
            "{cell}"
        );
    }
}

/// UI tests of verification and scene loading: `tests/ui/runtime/CODE_what.cell` is
/// built and verified; a file whose name says `stale` has its URDF changed after the
/// build. The produced codes must be exactly the one in the file name.
#[test]
fn runtime_ui() {
    let mut checked = 0;
    insta::glob!("ui/runtime/*.cell", |path| {
        let name = path.file_name().unwrap().to_string_lossy().to_string();
        let code = name.split('_').next().unwrap_or_default().to_string();
        let relative = format!("tests/ui/runtime/{name}");
        // The scene is loaded first (a stale case against its URDF edited after the
        // build), as `cellc plan` loads it even for a cell without arms; a scene that
        // loads is built as `cellc build` builds it (the scene as a whole first, then
        // every arc unless the scene is wrong whatever the arc).
        struct Changed;
        impl Files for Changed {
            fn read(&self, path: &str) -> Result<Vec<u8>, cellc_runtime::FileError> {
                let mut bytes = FsFiles.read(path)?;
                if path.ends_with(".urdf") {
                    bytes.extend_from_slice(b"\n<!-- edited after the build -->\n");
                }
                Ok(bytes)
            }
        }
        let files: &dyn Files = if name.contains("stale") {
            &Changed
        } else {
            &FsFiles
        };
        let compiled = cellc_driver::build(&FsFiles, &relative, &BuildOptions::unverified());
        let artifact = compiled
            .artifact
            .unwrap_or_else(|| panic!("{name} must compile"));
        let (compilation, diagnostics) = match Scene::load(&artifact, files) {
            Err(e) => (
                compiled.compilation,
                vec![cellc_driver::verify_report::scene_error_at(
                    &e,
                    &artifact.robots,
                    &artifact.spans,
                )],
            ),
            Ok(_) => {
                let built = cellc_driver::build(&FsFiles, &relative, &Default::default());
                let compiled = built.compilation.diagnostics.len();
                let found = built.diagnostics[compiled..].to_vec();
                (built.compilation, found)
            }
        };
        let codes: Vec<&str> = diagnostics.iter().map(|d| d.code.as_str()).collect();
        assert!(
            !codes.is_empty() && codes.iter().all(|c| *c == code),
            "{name}: {codes:?}"
        );
        let source = std::fs::read_to_string(path).unwrap_or_default();
        let rendered = cellc::render::human(
            &diagnostics,
            &compilation.sources,
            cellc::render::Color::Never,
        );
        insta::assert_snapshot!(format!("{source}\n----- diagnostics -----\n{rendered}"));
        checked += 1;
    });
    assert!(checked >= 3);
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig { cases: 4, ..Default::default() })]

    /// Whatever the seed, every witness is collision-free, within limits and consistent.
    #[test]
    fn witnesses_hold_for_any_seed(seed in proptest::prelude::any::<u64>()) {
        for cell in geometric_cells() {
            let (artifact, scene) = verified(&cell, seed);
            for (o, object) in artifact.objects.iter().enumerate() {
                for arc in object.graph.arcs.iter().filter(|a| a.witness.is_some()) {
                    let checked = recheck(&artifact, &scene, o, arc);
                    proptest::prop_assert!(checked.is_ok(), "{cell} seed {seed}: {:?}", checked);
                }
            }
        }
    }
}

/// Two hands with the same grasp and no symmetry turn to tell them apart occupy one place:
/// the handoff is refused for the two hands' solids, before (and instead of) the closed
/// chain that the symmetric ball of `far_arms.cell` fails on.
#[test]
fn two_hands_in_one_place_are_refused_for_their_overlap() {
    let (artifact, _) = verified("tests/data/verify/far_arms_one_turn.cell", 0);
    let ball = &artifact.objects[0];
    assert!(ball.graph.arcs.is_empty(), "{:?}", ball.graph.arcs);
    assert_eq!(ball.graph.pruned.len(), 2);
    for pruned in &ball.graph.pruned {
        match &pruned.reason {
            Infeasibility::Collision { a, b } => {
                assert_eq!(
                    (a.as_str(), b.as_str()),
                    ("left/softhand", "right/softhand")
                )
            }
            other => panic!("wrong reason: {other:?}"),
        }
    }
}

/// Grasp pairs of two families that are one closed chain share its solves: the side
/// family turned every 45° about the block's axis makes 64 handoff pairs but 8 chains
/// (what matters is how far apart the two members are turned). Most pairs put the two
/// palms into each other and are refused before any IK (`verify/hands.rs`); the pairs
/// that reach the solver each needed a solve of their own before, and now at most 8
/// chains are solved per position tried, fewer than the checks kept. The witnesses found
/// so pass the recheck as every other does.
#[test]
fn grasp_pairs_that_are_one_closed_chain_share_its_solves() {
    let mut artifact = build("tests/data/verify/side_family.cell");
    let scene = Scene::load(&artifact, &FsFiles).expect("scene loads");
    let options = VerifyOptions::default();
    let report = verify(&mut artifact, &scene, &options, &|_, _| {});
    let block = &artifact.objects[0];
    for arc in &block.graph.arcs {
        recheck(&artifact, &scene, 0, arc).unwrap_or_else(|e| panic!("{e}"));
    }
    // Both directions of a handoff are one check.
    let kept_checks = block.graph.arcs.len() as u64 / 2;
    assert!(kept_checks >= 4 && report.n_pruned > 0, "{report:?}");
    assert!(report.n_chains > 0, "{report:?}");
    assert!(
        report.n_chains < kept_checks,
        "{report:?}, {kept_checks} checks kept"
    );
    assert!(
        report.n_chains <= 8 * u64::from(options.placements),
        "{report:?}"
    );
}
