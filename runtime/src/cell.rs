//! The front door: a loaded cell that plans, executes and explains move requests.
//!
//! A task planner embeds the runtime through [`Cell`] alone: load an artifact's bytes
//! (with a [`Files`] that supplies the robot models and meshes it names), resolve names to
//! typed ids once, then plan, execute and explain with ids. The building blocks behind it
//! (kinematics, collision, motion planning, verification) stay reachable for benches and
//! tools, but nothing here needs them.

use cellc_schema::partial::{Partial, Parts};
use cellc_schema::sections::{Sections, Source};
use cellc_schema::{
    Artifact, Body, EndEffectorId, GraspId, ObjectId, ReadError, WorkspaceId, WorldDocument,
};

use crate::execute::{ExecuteOptions, Execution, ExecutionError, Executor, Simulator};
use crate::explain::{Explanation, NoStates};
use crate::plan::planner::Planner;
use crate::plan::search::SearchGraph;
use crate::plan::{
    names, Goal, GoalByName, LocateError, PlacementByName, Plan, PlanError, PlanOptions, Request,
    Unreachable,
};
use crate::scene::{Scene, SceneError};
use crate::verify::{Checked, VerifyOptions};
use crate::world::{Whereabouts, World, WorldError};
use crate::Files;

/// Why an artifact could not be loaded.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum LoadError {
    /// The bytes are not a readable artifact (not one, an old format, damaged).
    Artifact(ReadError),
    /// The robot models, meshes or collision world could not be built.
    Scene(SceneError),
}

impl std::fmt::Display for LoadError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            LoadError::Artifact(e) => e.fmt(f),
            LoadError::Scene(e) => e.fmt(f),
        }
    }
}

impl std::error::Error for LoadError {}

/// A cell ready to answer move requests: the artifact, its geometry (when it has arms)
/// and the search graphs of the objects whose graphs are read, built once.
///
/// A cell loaded from a sectioned binary may hold only some objects' graphs
/// ([`Cell::load_objects`]): the others have no states, so a request on one of them finds
/// no start, and [`Cell::parts`] says what was read.
pub struct Cell {
    partial: Partial,
    scene: Option<Scene>,
    search: Vec<SearchGraph>,
}

impl Cell {
    /// Loads an artifact from its bytes (JSON or binary), every object's graph; robot
    /// models and meshes are read through `files`, relative paths as the artifact records
    /// them.
    pub fn load(bytes: &[u8], files: &dyn Files) -> Result<Cell, LoadError> {
        let (artifact, _) = Artifact::from_bytes(bytes).map_err(LoadError::Artifact)?;
        Cell::from_artifact(artifact, files)
    }

    /// Makes an artifact already in memory ready to plan (e.g. one just compiled). It is
    /// validated as one read from bytes is, so no caller can hand the planner an index it
    /// did not check.
    pub fn from_artifact(artifact: Artifact, files: &dyn Files) -> Result<Cell, LoadError> {
        let partial = Partial::whole(artifact).map_err(LoadError::Artifact)?;
        Cell::from_partial(partial, files)
    }

    /// Loads from a sectioned binary the core and, of each object in `objects`, the
    /// `parts` of its graph; the other objects' graphs stay unread (empty), so the load
    /// reads in proportion to what the objects named need. Each part read is validated
    /// on its own ([`cellc_schema::validate::graph`]).
    ///
    /// # Errors
    /// As [`Cell::load`], for the sections read only: damage in a section not read is
    /// not seen.
    pub fn load_objects(
        sections: &Sections<impl Source>,
        objects: &[ObjectId],
        parts: Parts,
        files: &dyn Files,
    ) -> Result<Cell, LoadError> {
        let mut partial = Partial::open(sections).map_err(LoadError::Artifact)?;
        for &o in objects {
            partial
                .read(sections, o, parts)
                .map_err(LoadError::Artifact)?;
        }
        Cell::from_partial(partial, files)
    }

    /// A validated (partly read) artifact made ready to plan: its scene loaded when it has
    /// arms, the search graphs of the objects whose graphs are read built.
    pub fn from_partial(partial: Partial, files: &dyn Files) -> Result<Cell, LoadError> {
        let artifact = partial.artifact();
        let has_arms = artifact
            .end_effectors
            .iter()
            .any(|e| matches!(e.body, Body::Arm { .. }));
        let scene = if has_arms {
            Some(Scene::load(artifact, files).map_err(LoadError::Scene)?)
        } else {
            None
        };
        let search = SearchGraph::for_artifact(artifact);
        Ok(Cell {
            partial,
            scene,
            search,
        })
    }

    /// Reads more `parts` of object `o`'s graph from `sections`, the file the cell was
    /// loaded from (e.g. its pruned arcs, to explain an unreachable goal), and validates
    /// them; what was read already is not read again.
    ///
    /// # Errors
    /// As [`Cell::load_objects`]; on an error the cell is as it was.
    pub fn read_parts(
        &mut self,
        sections: &Sections<impl Source>,
        o: ObjectId,
        parts: Parts,
    ) -> Result<(), LoadError> {
        let had = self.partial.parts(o);
        self.partial
            .read(sections, o, parts)
            .map_err(LoadError::Artifact)?;
        if !had.graph && self.partial.parts(o).graph {
            if let (Some(slot), Some(object)) = (
                self.search.get_mut(o.index()),
                self.partial.artifact().objects.get(o.index()),
            ) {
                *slot = SearchGraph::new(&object.graph);
            }
        }
        Ok(())
    }

    /// The parts of object `o`'s graph this cell holds.
    pub fn parts(&self, o: ObjectId) -> Parts {
        self.partial.parts(o)
    }

    /// Checks the scene as a whole and then every arc kinematically (when the artifact
    /// was built without), keeping witnesses and pruned arcs, as `cellc build` does: a
    /// scene wrong whatever the arc (a permanent contact, a colliding home) leaves the
    /// arcs as they were and says so in [`Checked::preflight`]. `None` for a cell without
    /// arms (nothing to check).
    pub fn verify(&mut self, options: &VerifyOptions) -> Option<Checked> {
        let scene = self.scene.as_ref()?;
        let checked = crate::verify::check_and_verify(
            self.partial.artifact_mut(),
            scene,
            options,
            &|_, _| {},
        );
        self.search = SearchGraph::for_artifact(self.partial.artifact());
        Some(checked)
    }

    /// The artifact.
    pub fn artifact(&self) -> &Artifact {
        self.partial.artifact()
    }

    /// The geometry, for cells with arms.
    pub fn scene(&self) -> Option<&Scene> {
        self.scene.as_ref()
    }

    /// The object named `name`.
    pub fn object(&self, name: &str) -> Result<ObjectId, LocateError> {
        names::object(self.partial.artifact(), name)
    }

    /// The end-effector named `name`.
    pub fn end_effector(&self, name: &str) -> Result<EndEffectorId, LocateError> {
        names::end_effector(self.partial.artifact(), name)
    }

    /// The workspace named `name`.
    pub fn workspace(&self, name: &str) -> Result<WorkspaceId, LocateError> {
        names::workspace(self.partial.artifact(), name)
    }

    /// The grasp of `object` named `name` that `holder` can hold.
    pub fn grasp(
        &self,
        object: ObjectId,
        holder: EndEffectorId,
        name: &str,
    ) -> Result<GraspId, LocateError> {
        names::grasp(self.partial.artifact(), object, holder, name)
    }

    /// A request given with names: "move `object` from `start` to `goal`".
    pub fn request(
        &self,
        object: &str,
        start: &PlacementByName,
        goal: &GoalByName,
        options: PlanOptions,
    ) -> Result<Request, LocateError> {
        let object = self.object(object)?;
        Ok(Request {
            object,
            start: names::placement(self.partial.artifact(), object, start)?,
            goal: names::goal(self.partial.artifact(), object, goal)?,
            options,
        })
    }

    /// The request the cell declares under `name` (`request NAME: ...`), or `None`.
    pub fn named_request(&self, name: &str, options: PlanOptions) -> Option<Request> {
        let named = self
            .partial
            .artifact()
            .requests
            .iter()
            .find(|r| r.name == name)?;
        Some(crate::plan::named_request(named, options))
    }

    /// Plans a request in `world`: the request's object is put where the request's start
    /// says (its hand's arm moved to hold it there, [`Cell::request_world`]), everything
    /// else stays where `world` has it. In [`Cell::home_world`] the request meets no other
    /// object.
    ///
    /// Every method that plans, simulates or executes takes the world it works in, so
    /// there is one way to say where things are: [`Cell::home_world`],
    /// [`Cell::initial_world`] (the cell's declared world), [`Cell::world`] (a world
    /// document) or a world kept from an earlier execution.
    ///
    /// # Errors
    /// See [`PlanError`]; [`PlanError::World`] when the start's hand cannot hold the object
    /// there.
    pub fn plan(&self, world: &World, request: &Request) -> Result<Plan, PlanError> {
        let world = self.request_world(world, request)?;
        self.plan_move(&world, request.object, &request.goal, &request.options)
    }

    /// Every arm at home and no object placed: the world of a request that meets no
    /// other object.
    pub fn home_world(&self) -> World {
        World::at_home(self.partial.artifact(), self.scene.as_ref())
    }

    /// `world` with the request's object at its start ([`World::for_request`]): the world
    /// [`Cell::plan`] plans the request's plan in, so where its simulator starts and the
    /// world its execution brings up to date.
    ///
    /// # Errors
    /// [`PlanError::World`] when the start's hand cannot hold the object there.
    pub fn request_world(&self, world: &World, request: &Request) -> Result<World, PlanError> {
        world
            .for_request(
                self.partial.artifact(),
                self.scene.as_ref(),
                request.object,
                &request.start,
                &request.options,
            )
            .map_err(|e| match e {
                // A start that names nothing or matches no state is the request's error,
                // as when it is located for planning.
                WorldError::Name(error) | WorldError::Placement { error, .. } => {
                    PlanError::Locate(error)
                }
                e => PlanError::World(e),
            })
    }

    /// The world the cell declares (`world { ... }`): arms at home, the objects where it
    /// puts them, the others absent.
    ///
    /// # Errors
    /// A declared placement that matches no state of its object's graph.
    pub fn initial_world(&self, options: &PlanOptions) -> Result<World, WorldError> {
        World::initial(self.partial.artifact(), self.scene.as_ref(), options)
    }

    /// The world a world document describes (`docs/world.md`).
    ///
    /// # Errors
    /// The first unknown name, joint out of limits or placement that matches no state.
    pub fn world(
        &self,
        document: &WorldDocument,
        options: &PlanOptions,
    ) -> Result<World, WorldError> {
        World::from_document(
            self.partial.artifact(),
            self.scene.as_ref(),
            document,
            options,
        )
    }

    /// `world` as a world document (every arm and every object, by name): what a store
    /// keeps, and [`Cell::world`] reads back to the same world.
    pub fn world_document(&self, world: &World) -> WorldDocument {
        world.to_document(self.partial.artifact(), self.scene.as_ref())
    }

    /// Plans moving `object` to `goal` from where it is in `world`, with the arms where
    /// they stand and every other object in the way where it is.
    pub fn plan_move(
        &self,
        world: &World,
        object: ObjectId,
        goal: &Goal,
        options: &PlanOptions,
    ) -> Result<Plan, PlanError> {
        self.planner().plan_move(world, object, goal, options)
    }

    /// Plans moving `object` to `goal` in `world` as [`Cell::plan_move`] does, and when
    /// other objects are in the way (one stands at the goal, or they block every way
    /// there), moves them to free resting poses first: the plans in the order to carry
    /// them out, the request's last, each made in the world the ones before leave. See
    /// [`Planner::plan_clearing`].
    ///
    /// ```rust,ignore
    /// for plan in cell.plan_clearing(&world, object, &goal, &options)? {
    ///     let mut simulator = cell.simulator(&world, &plan);
    ///     cell.execute(&mut world, plan, &mut simulator, &ExecuteOptions::default())?;
    /// }
    /// ```
    pub fn plan_clearing(
        &self,
        world: &World,
        object: ObjectId,
        goal: &Goal,
        options: &PlanOptions,
    ) -> Result<Vec<Plan>, PlanError> {
        self.planner().plan_clearing(world, object, goal, options)
    }

    /// The world once `plan` (made in `world`) has been carried out as planned, without
    /// carrying it out ([`World::after`]).
    pub fn world_after(&self, world: &World, plan: &Plan) -> World {
        world.after(self.partial.artifact(), self.scene.as_ref(), plan)
    }

    /// A kinematic simulator of the cell as `world` has it, for `plan` (planned in that
    /// world): the arms where the world has them, the object where the plan starts. For
    /// a request's plan that world is [`Cell::request_world`].
    pub fn simulator(&self, world: &World, plan: &Plan) -> Simulator<'_> {
        Simulator::with_arms(
            self.partial.artifact(),
            self.scene.as_ref(),
            plan.object,
            plan.states[0],
            plan.start_pose,
            world.arms().to_vec(),
        )
    }

    /// Executes a plan made in `world` on `executor`, replanning from where the object is
    /// when a step fails (the plan carries its goal), and brings the world up to date
    /// with what the executor reports, whether the execution succeeds or not: the arms
    /// where they stopped, the object where it is (the objects moved so far stay moved).
    pub fn execute(
        &self,
        world: &mut World,
        plan: Plan,
        executor: &mut dyn Executor,
        options: &ExecuteOptions,
    ) -> Result<Execution, ExecutionError> {
        let object = plan.object;
        let result = self.planner().execute(plan, executor, options);
        self.observe(world, object, executor);
        result
    }

    /// Brings `world` up to date with what `executor` reports of `object` and the arms:
    /// the arms where they stand, the object where it is (its pose kept only when it
    /// rests on a surface; a held one follows its hand).
    pub(crate) fn observe(&self, world: &mut World, object: ObjectId, executor: &dyn Executor) {
        for (e, q) in executor.arms().into_iter().enumerate() {
            if let Some(q) = q {
                world.set_arm(EndEffectorId(e as u32), q);
            }
        }
        let observed = executor.object_state();
        let rests = matches!(
            self.partial
                .artifact()
                .end_effectors
                .get(observed.state.end_effector.index())
                .map(|e| &e.body),
            Some(Body::Surface { .. })
        );
        world.set_object(
            object,
            Whereabouts::Placed {
                state: observed.state,
                pose: if rests { observed.pose } else { None },
            },
        );
    }

    /// The moves of the task the cell declares under `name`, in order: each object and
    /// where it must go.
    pub fn task(&self, name: &str) -> Option<Vec<(ObjectId, Goal)>> {
        let task = self
            .partial
            .artifact()
            .tasks
            .iter()
            .find(|t| t.name == name)?;
        Some(
            task.steps
                .iter()
                .map(|s| (s.object, Goal::Placement(crate::plan::placement_of(&s.to))))
                .collect(),
        )
    }

    /// Why a request has no plan: the two sides, the cut, and checked suggestions; an
    /// error when the request's start or goals are not states of the object's graph.
    pub fn explain(&self, unreachable: &Unreachable) -> Result<Explanation, NoStates> {
        crate::explain::explain(self.partial.artifact(), unreachable)
    }

    /// The planner over this cell (internal: shares the search graphs built at load).
    pub fn planner(&self) -> Planner<'_> {
        Planner::with_search(self.partial.artifact(), self.scene.as_ref(), &self.search)
    }
}
