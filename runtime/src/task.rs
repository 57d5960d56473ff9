//! Tasks: several moves, planned (and executed) one after the other in one world.
//!
//! A task is a list of moves, each an object and where it must go. Each move is planned in
//! the world as the moves before it leave it: when only planning, the world a plan leaves
//! ([`World::after`]); when executing, the world the executor reports. A failing move
//! ends the task with its index, and the world is left as it really is: the moves before
//! it stay done. With `clear`, objects in a move's way are first moved to free resting
//! poses ([`Cell::plan_clearing`]); those moves are part of the move they clear for.

use cellc_schema::ObjectId;

use crate::cell::Cell;
use crate::execute::{ExecuteOptions, Execution, ExecutionError, SimulatorTolerance};
use crate::observe::{Observed, StepObserver};
use crate::plan::{Goal, Plan, PlanError, PlanOptions};
use crate::world::World;

/// How a task is planned and executed.
#[derive(Clone, Debug)]
pub struct TaskOptions {
    /// Planning options of every move (seed, motions, time budget of each plan).
    pub plan: PlanOptions,
    /// Move objects in a move's way to free resting poses first.
    pub clear: bool,
    /// Replans allowed per executed plan when a step fails.
    pub max_replans: u32,
    /// Make the motion of this step (0-based) of the task's first executed plan fail in
    /// the simulator: how recovery is tried out.
    pub fail_motion_at: Option<usize>,
}

impl Default for TaskOptions {
    fn default() -> Self {
        TaskOptions {
            plan: PlanOptions::default(),
            clear: false,
            max_replans: 5,
            fail_motion_at: None,
        }
    }
}

/// One plan of a task carried out in the simulator.
#[derive(Clone, Debug)]
pub struct Executed {
    /// The index of the move it belongs to.
    pub index: usize,
    /// The plan as made before execution.
    pub plan: Plan,
    /// For a plan that takes an object out of the way: the object of the move it clears.
    pub clears: Option<ObjectId>,
    /// How execution went: the plans executed (the first, then one per replan) and where
    /// the object ended; or why it stopped.
    pub result: Result<Execution, ExecutionError>,
    /// The simulator's log, one line per step.
    pub log: Vec<String>,
    /// Seconds of motion the simulator played, over every plan executed (the steps that
    /// failed take none).
    pub motion_time: f64,
}

/// Why a task stopped.
#[derive(Clone, Debug)]
pub enum TaskError {
    /// A move has no plan.
    Plan(PlanError),
    /// A plan's execution failed (its [`Executed`] is the last of the task's record).
    Execute(ExecutionError),
}

/// A task that stopped at a move.
#[derive(Clone, Debug)]
pub struct TaskFailure {
    /// The index of the move that failed.
    pub index: usize,
    /// Why.
    pub error: TaskError,
}

/// A task planned ahead: what [`Cell::plan_task`] gives.
#[derive(Clone, Debug)]
pub struct TaskPlans {
    /// Per move planned, its plans (those clearing its way first, then its own).
    pub plans: Vec<Vec<Plan>>,
    /// The world the last plan leaves.
    pub world: World,
    /// The move that has no plan, when one has none (the moves before it are planned).
    pub failure: Option<TaskFailure>,
}

/// A task carried out: what [`Cell::run_task`] gives.
#[derive(Clone, Debug)]
pub struct TaskRun {
    /// Every plan executed, in order (those clearing a move's way before it).
    pub record: Vec<Executed>,
    /// The move that failed, when one did (its execution, if it started, is the last
    /// record).
    pub failure: Option<TaskFailure>,
}

impl Cell {
    /// Plans every move of a task without executing anything, each in the world the plans
    /// before it leave ([`World::after`]): per move, its plans (those clearing its way
    /// first, with `clear`). `world` is where the task starts; the world after the last
    /// plan is returned too.
    ///
    /// Planning stops at the first move that has no plan ([`TaskPlans::failure`]).
    pub fn plan_task(
        &self,
        world: &World,
        moves: &[(ObjectId, Goal)],
        options: &TaskOptions,
    ) -> TaskPlans {
        let mut world = world.clone();
        let mut all = Vec::new();
        for (index, (object, goal)) in moves.iter().enumerate() {
            match self.plans_of_move(&world, *object, goal, options) {
                Ok(plans) => {
                    for plan in &plans {
                        world = self.world_after(&world, plan);
                    }
                    all.push(plans);
                }
                Err(e) => {
                    let failure = TaskFailure {
                        index,
                        error: TaskError::Plan(e),
                    };
                    return TaskPlans {
                        plans: all,
                        world,
                        failure: Some(failure),
                    };
                }
            }
        }
        TaskPlans {
            plans: all,
            world,
            failure: None,
        }
    }

    /// Plans and executes every move of a task in the kinematic simulator, one after the
    /// other, bringing `world` up to date from the simulator after each plan (whether it
    /// succeeded or not): the record of every plan executed, in order.
    ///
    /// The task stops at the first move that has no plan or whose execution fails
    /// ([`TaskRun::failure`]); `world` is then as the simulator left it.
    pub fn run_task(
        &self,
        world: &mut World,
        moves: &[(ObjectId, Goal)],
        options: &TaskOptions,
    ) -> TaskRun {
        self.run_task_observed(world, moves, options, None)
    }

    /// [`Cell::run_task`], with `observer` told of every step carried out and the world
    /// it left (clearing moves and replans included), before the next step starts.
    pub fn run_task_observed(
        &self,
        world: &mut World,
        moves: &[(ObjectId, Goal)],
        options: &TaskOptions,
        mut observer: Option<&mut dyn StepObserver>,
    ) -> TaskRun {
        let mut record: Vec<Executed> = Vec::new();
        for (index, (object, goal)) in moves.iter().enumerate() {
            let fail = |error| TaskFailure { index, error };
            let plans = match self.plans_of_move(world, *object, goal, options) {
                Ok(plans) => plans,
                Err(e) => {
                    return TaskRun {
                        record,
                        failure: Some(fail(TaskError::Plan(e))),
                    }
                }
            };
            let count = plans.len();
            let mut replanned = false;
            for (k, mut plan) in plans.into_iter().enumerate() {
                let clearing = k + 1 < count;
                if !clearing && replanned {
                    // A move out of the way needed a replan, so its object may stand
                    // elsewhere than this plan assumed: plan again in the world as it is.
                    plan = match self.plan_move(world, *object, goal, &options.plan) {
                        Ok(p) => p,
                        Err(e) => {
                            return TaskRun {
                                record,
                                failure: Some(fail(TaskError::Plan(e))),
                            }
                        }
                    };
                }
                let first = record.is_empty();
                let executed = self.simulate(world, plan, options, first, observer.as_deref_mut());
                replanned |= executed.result.as_ref().is_ok_and(|r| r.plans.len() > 1);
                let error = executed.result.as_ref().err().cloned();
                record.push(Executed {
                    index,
                    clears: clearing.then_some(*object),
                    ..executed
                });
                if let Some(e) = error {
                    return TaskRun {
                        record,
                        failure: Some(fail(TaskError::Execute(e))),
                    };
                }
            }
        }
        TaskRun {
            record,
            failure: None,
        }
    }

    /// A move's plans: its own, or with `clear` those that take objects out of its way
    /// first.
    fn plans_of_move(
        &self,
        world: &World,
        object: ObjectId,
        goal: &Goal,
        options: &TaskOptions,
    ) -> Result<Vec<Plan>, PlanError> {
        if options.clear {
            self.plan_clearing(world, object, goal, &options.plan)
        } else {
            self.plan_move(world, object, goal, &options.plan)
                .map(|p| vec![p])
        }
    }

    /// Executes one plan in a simulator of `world` and updates the world from it.
    fn simulate(
        &self,
        world: &mut World,
        plan: Plan,
        options: &TaskOptions,
        first: bool,
        observer: Option<&mut (dyn StepObserver + '_)>,
    ) -> Executed {
        let made = plan.clone();
        // An object let go above its surface by no more than the planner calls resting
        // falls onto it (the planner put it down there).
        let mut simulator = self
            .simulator(world, &plan)
            .with_tolerance(SimulatorTolerance {
                drop: options.plan.position_tolerance,
                ..SimulatorTolerance::default()
            });
        if let Some(step) = options.fail_motion_at.filter(|_| first) {
            simulator = simulator.fail_motion_at(step);
        }
        let execute = ExecuteOptions {
            max_replans: options.max_replans,
            plan: options.plan.clone(),
        };
        let result = match observer {
            Some(observer) => {
                let start = world.clone();
                let object = plan.object;
                let mut observed = Observed::new(&mut simulator, self, object, start, observer);
                self.execute(world, plan, &mut observed, &execute)
            }
            None => self.execute(world, plan, &mut simulator, &execute),
        };
        Executed {
            index: 0,
            plan: made,
            clears: None,
            result,
            log: simulator.log.clone(),
            motion_time: simulator.motion_time(),
        }
    }
}
