//! The runtime's seams seen from the request planner: another motion planner plugs into
//! `Planner` without editing it, and a request cancelled while its motions are planned
//! stops with `TimeBudget`, never with a plan or "unreachable".

use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::Arc;

use cellc_driver::fs_files::FsFiles;
use cellc_runtime::motion::{ChaCha8Rng, MotionError, MotionPlanner, MotionProblem, RrtConnect};
use cellc_runtime::plan::planner::Planner;
use cellc_runtime::plan::{PlanError, PlanOptions, Request, Trajectory};
use cellc_runtime::scene::{Scene, SceneScratch};
use cellc_runtime::Termination;
use cellc_schema::Artifact;

fn vito() -> (Artifact, Scene) {
    let built = cellc_driver::build(&FsFiles, "cells/vito.cell", &Default::default());
    assert!(
        built.compilation.diagnostics.is_empty(),
        "vito.cell is not clean"
    );
    let artifact = built.artifact.expect("vito builds");
    let scene = Scene::load(&artifact, &FsFiles).expect("scene loads");
    (artifact, scene)
}

/// The named request `name` of the artifact, with `options`.
fn request(a: &Artifact, name: &str, options: PlanOptions) -> Request {
    let r = a
        .requests
        .iter()
        .find(|r| r.name == name)
        .unwrap_or_else(|| panic!("request `{name}`"));
    cellc_runtime::plan::named_request(r, options)
}

/// RRT-Connect, counting the motions it is asked for and, if given a flag, raising it on
/// the first one (as another thread cancelling the request would).
struct Watched {
    inner: RrtConnect,
    calls: AtomicUsize,
    cancel: Option<Arc<AtomicBool>>,
}

impl MotionPlanner for Watched {
    fn solve(
        &self,
        problem: &MotionProblem<'_>,
        rng: &mut ChaCha8Rng,
        stop: &Termination,
        scratch: &mut SceneScratch,
    ) -> Result<Trajectory, MotionError> {
        self.calls.fetch_add(1, Ordering::Relaxed);
        if let Some(flag) = &self.cancel {
            flag.store(true, Ordering::Relaxed);
        }
        self.inner.solve(problem, rng, stop, scratch)
    }
}

fn motions(plan: &cellc_runtime::plan::Plan) -> Vec<Option<Trajectory>> {
    plan.steps.iter().map(|s| s.motion.clone()).collect()
}

#[test]
fn another_motion_planner_plugs_into_the_request_planner() {
    let (artifact, scene) = vito();
    let req = request(&artifact, "trash", PlanOptions::default());
    let default = Planner::new(&artifact, Some(&scene))
        .plan(&req)
        .expect("the default planner plans `trash`");
    let watched = Watched {
        inner: RrtConnect::default(),
        calls: AtomicUsize::new(0),
        cancel: None,
    };
    let planner = Planner::new(&artifact, Some(&scene)).with_motion_planner(&watched);
    let plan = planner.plan(&req).expect("the same planner, watched");
    let planned = plan.steps.iter().filter(|s| s.motion.is_some()).count();
    assert!(planned > 0);
    assert_eq!(watched.calls.load(Ordering::Relaxed), planned);
    assert_eq!(motions(&plan), motions(&default));
}

#[test]
fn a_request_cancelled_during_its_motions_runs_out_of_time() {
    let (artifact, scene) = vito();
    let flag = Arc::new(AtomicBool::new(false));
    let options = PlanOptions {
        cancel: Some(flag.clone()),
        ..PlanOptions::default()
    };
    let watched = Watched {
        inner: RrtConnect::default(),
        calls: AtomicUsize::new(0),
        cancel: Some(flag),
    };
    let planner = Planner::new(&artifact, Some(&scene)).with_motion_planner(&watched);
    match planner.plan(&request(&artifact, "trash", options)) {
        Err(PlanError::TimeBudget { searches: 1 }) => {}
        Err(other) => panic!("a cancelled request is out of time, not {other:?}"),
        Ok(_) => panic!("a cancelled request gives no plan"),
    }
    assert!(watched.calls.load(Ordering::Relaxed) >= 1);
}
