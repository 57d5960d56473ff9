//! The world a plan leaves, before anyone carries it out: what a caller that plans several
//! moves ahead plans the next one in (moving a blocking object away and then the object
//! it blocked, a task planner looking ahead).
//!
//! It is the world the simulator reports after executing the plan without a failure: the
//! arms that move where their last motion ends (or, in a plan without motions, at their
//! last command's configuration, where the simulator jumps them), the object in the
//! plan's last state. Executing a plan and reading the executor ([`crate::Cell::execute`])
//! stays the way to know the world as it really is.

use cellc_schema::{Artifact, Body};

use super::{Whereabouts, World};
use crate::plan::{Command, Plan};
use crate::scene::{Holder, Scene};

impl World {
    /// The world once `plan` (made in this world) has been carried out as planned: its
    /// object in the plan's last state (resting at the pose of its last exchange, or held,
    /// its pose then following its hand), every arm that acts at the end of its last
    /// motion, every other arm and object as it is.
    pub fn after(&self, artifact: &Artifact, scene: Option<&Scene>, plan: &Plan) -> World {
        let mut world = self.clone();
        let mut last_pose = None;
        for step in &plan.steps {
            match (&step.motion, scene) {
                (Some(trajectory), Some(scene)) => {
                    let Some(end) = trajectory.points.last().map(|p| &p.positions) else {
                        continue;
                    };
                    let mut offset = 0;
                    for &e in &trajectory.arms {
                        let n = match scene.holders.get(e.index()) {
                            Some(Holder::Arm { robot, .. }) => {
                                scene.robots.get(*robot).map_or(0, |r| r.n_joints())
                            }
                            _ => 0,
                        };
                        if let Some(q) = end.get(offset..offset + n) {
                            world.set_arm(e, q.to_vec());
                        }
                        offset += n;
                    }
                }
                _ => match &step.command {
                    Command::Move { configurations, .. }
                    | Command::Grasp { configurations, .. } => {
                        for (e, q) in configurations {
                            if world.arm(*e).is_some() {
                                world.set_arm(*e, q.clone());
                            }
                        }
                    }
                    Command::Ungrasp { .. } => {}
                },
            }
            if let Command::Grasp { object, .. } | Command::Move { object, .. } = &step.command {
                if object.is_some() {
                    last_pose = *object;
                }
            }
        }
        let Some(&state) = plan.states.last() else {
            return world;
        };
        if plan.steps.is_empty() {
            return world;
        }
        let rests = matches!(
            artifact
                .end_effectors
                .get(state.end_effector.index())
                .map(|e| &e.body),
            Some(Body::Surface { .. })
        );
        world.set_object(
            plan.object,
            Whereabouts::Placed {
                state,
                pose: if rests { last_pose } else { None },
            },
        );
        world
    }
}
