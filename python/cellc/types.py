"""The service's JSON as typed values.

Every document the service sends is parsed here, once, into frozen dataclasses: names are
the cell's names, lengths are metres, angles radians, rotations unit quaternions
(x, y, z, w), and every joint value comes with its URDF joint name.
"""

from __future__ import annotations

from dataclasses import dataclass, field, fields
from typing import Any


@dataclass(frozen=True)
class Diagnostic:
    """One diagnostic: a code (documented in docs/diagnostics/CODE.md), what is wrong,
    and how to fix it."""

    code: str
    severity: str
    message: str
    help: str | None = None
    notes: tuple[str, ...] = ()

    @staticmethod
    def parse(d: dict[str, Any]) -> "Diagnostic":
        return Diagnostic(
            code=str(d.get("code", "")),
            severity=str(d.get("severity", "error")),
            message=str(d.get("message", "")),
            help=d.get("help"),
            notes=tuple(d.get("notes") or ()),
        )


def diagnostics_of(document: Any) -> tuple[Diagnostic, ...]:
    """The diagnostics of a response document (any shape the service sends)."""
    if not isinstance(document, dict):
        return ()
    return tuple(Diagnostic.parse(d) for d in document.get("diagnostics") or ())


@dataclass(frozen=True)
class Pose:
    """A pose in the cell: position in metres, rotation as a unit quaternion (x, y, z, w)."""

    position: tuple[float, float, float]
    rotation: tuple[float, float, float, float]

    @staticmethod
    def parse(d: dict[str, Any] | None) -> "Pose | None":
        if not d:
            return None
        p, r = d["position"], d["rotation"]
        return Pose((p[0], p[1], p[2]), (r[0], r[1], r[2], r[3]))


@dataclass(frozen=True)
class Joints:
    """One arm's joints: URDF joint names and their values, in the same order."""

    arm: str
    names: tuple[str, ...]
    positions: tuple[float, ...]

    @staticmethod
    def parse(d: dict[str, Any]) -> "Joints":
        return Joints(str(d["arm"]), tuple(d["joints"]), tuple(d["positions"]))

    def as_dict(self) -> dict[str, float]:
        """Joint name -> value, as a world document writes an arm."""
        return dict(zip(self.names, self.positions))


@dataclass(frozen=True)
class State:
    """A state of an object's graph: who holds it, with which grasp, in which workspace."""

    end_effector: str
    grasp: str
    workspace: str

    @staticmethod
    def parse(d: dict[str, Any] | None) -> "State | None":
        if not d:
            return None
        return State(str(d["end_effector"]), str(d["grasp"]), str(d["workspace"]))


@dataclass(frozen=True)
class Point:
    """A trajectory point as a joint-trajectory controller takes it: seconds from the
    step's start, and every moving arm's joints' positions, velocities and accelerations
    in the trajectory's `arms` order."""

    time_from_start: float
    positions: tuple[float, ...]
    velocities: tuple[float, ...]
    accelerations: tuple[float, ...]

    @staticmethod
    def parse(d: dict[str, Any]) -> "Point":
        return Point(
            float(d["time_from_start"]),
            tuple(d["positions"]),
            tuple(d["velocities"]),
            tuple(d["accelerations"]),
        )


@dataclass(frozen=True)
class Trajectory:
    """A joint motion: the arms that move (each with its joint names) and its points."""

    arms: tuple[tuple[str, tuple[str, ...]], ...]
    points: tuple[Point, ...]

    @staticmethod
    def parse(d: dict[str, Any] | None) -> "Trajectory | None":
        if not d:
            return None
        return Trajectory(
            tuple((str(a["arm"]), tuple(a["joints"])) for a in d["arms"]),
            tuple(Point.parse(p) for p in d["points"]),
        )

    @property
    def duration(self) -> float:
        return self.points[-1].time_from_start if self.points else 0.0


@dataclass(frozen=True)
class Duration:
    """`builtin_interfaces/Duration`: whole seconds and nanoseconds (0 to 999 999 999)."""

    sec: int
    nanosec: int

    @staticmethod
    def parse(d: dict[str, Any]) -> "Duration":
        return Duration(int(d["sec"]), int(d["nanosec"]))

    @property
    def seconds(self) -> float:
        return self.sec + self.nanosec * 1e-9


@dataclass(frozen=True)
class JointTrajectoryPoint:
    """`trajectory_msgs/JointTrajectoryPoint`: one arm's joints at `time_from_start`."""

    positions: tuple[float, ...]
    velocities: tuple[float, ...]
    accelerations: tuple[float, ...]
    time_from_start: Duration

    @staticmethod
    def parse(d: dict[str, Any]) -> "JointTrajectoryPoint":
        return JointTrajectoryPoint(
            tuple(d["positions"]),
            tuple(d["velocities"]),
            tuple(d["accelerations"]),
            Duration.parse(d["time_from_start"]),
        )


@dataclass(frozen=True)
class JointTrajectory:
    """`trajectory_msgs/JointTrajectory`: one arm's URDF joint names and its points."""

    joint_names: tuple[str, ...]
    points: tuple[JointTrajectoryPoint, ...]

    @staticmethod
    def parse(d: dict[str, Any]) -> "JointTrajectory":
        return JointTrajectory(
            tuple(d["joint_names"]), tuple(JointTrajectoryPoint.parse(p) for p in d["points"])
        )


@dataclass(frozen=True)
class FollowJointTrajectoryGoal:
    """The goal of a `control_msgs/action/FollowJointTrajectory` action: `message()` is
    the dict to fill a ROS 2 goal with (`rosidl_runtime_py.set_message_fields`)."""

    trajectory: JointTrajectory

    @staticmethod
    def parse(d: dict[str, Any]) -> "FollowJointTrajectoryGoal":
        return FollowJointTrajectoryGoal(JointTrajectory.parse(d["trajectory"]))

    def message(self) -> dict[str, Any]:
        return {
            "trajectory": {
                "joint_names": list(self.trajectory.joint_names),
                "points": [
                    {
                        "positions": list(p.positions),
                        "velocities": list(p.velocities),
                        "accelerations": list(p.accelerations),
                        "time_from_start": {
                            "sec": p.time_from_start.sec,
                            "nanosec": p.time_from_start.nanosec,
                        },
                    }
                    for p in self.trajectory.points
                ],
            }
        }


@dataclass(frozen=True)
class StepGoal:
    """The goal of one arm in one step of a plan: `step` indexes the plan's `steps` (0 for
    the first); the goals of one step are sent together, each to its arm's controller."""

    step: int
    arm: str
    goal: FollowJointTrajectoryGoal

    @staticmethod
    def parse(d: dict[str, Any]) -> "StepGoal":
        return StepGoal(int(d["step"]), str(d["arm"]), FollowJointTrajectoryGoal.parse(d["goal"]))


@dataclass(frozen=True)
class PlanGoals:
    """A plan's motions as controller goals, in the order of its steps."""

    request: str
    object: str
    goals: tuple[StepGoal, ...]

    @staticmethod
    def parse(d: dict[str, Any]) -> "PlanGoals":
        return PlanGoals(
            str(d["request"]), str(d["object"]), tuple(StepGoal.parse(g) for g in d["goals"])
        )


@dataclass(frozen=True)
class ControllerGoals:
    """What `POST /v1/plan/follow_joint_trajectory` answers: the goals of every plan, in
    the order to carry them out (with `clear`, those moving what is in the way first)."""

    plans: tuple[PlanGoals, ...]

    @staticmethod
    def parse(d: dict[str, Any]) -> "ControllerGoals":
        return ControllerGoals(tuple(PlanGoals.parse(p) for p in d.get("plans") or ()))


@dataclass(frozen=True)
class Step:
    """One command of a plan: `move`, `grasp` or `ungrasp`."""

    command: str
    end_effector: str
    grasp: str | None
    workspace: str
    object: Pose | None
    configurations: tuple[Joints, ...]
    motion: Trajectory | None

    @staticmethod
    def parse(d: dict[str, Any]) -> "Step":
        return Step(
            command=str(d["command"]),
            end_effector=str(d["end_effector"]),
            grasp=d.get("grasp"),
            workspace=str(d["workspace"]),
            object=Pose.parse(d.get("object")),
            configurations=tuple(Joints.parse(c) for c in d.get("configurations") or ()),
            motion=Trajectory.parse(d.get("motion")),
        )


@dataclass(frozen=True)
class Plan:
    """A plan of one object's move: its state path, its commands, and the world's objects
    it went round."""

    request: str
    object: str
    strategy: str
    cost: float
    backtracks: int
    holders: tuple[str, ...]
    states: tuple[State, ...]
    steps: tuple[Step, ...]
    detours: tuple[dict[str, Any], ...] = ()

    @staticmethod
    def parse(d: dict[str, Any]) -> "Plan":
        return Plan(
            request=str(d.get("request", "")),
            object=str(d["object"]),
            strategy=str(d["strategy"]),
            cost=float(d["cost"]),
            backtracks=int(d.get("backtracks", 0)),
            holders=tuple(d.get("holders") or ()),
            states=tuple(s for s in (State.parse(x) for x in d["states"]) if s),
            steps=tuple(Step.parse(s) for s in d["steps"]),
            detours=tuple(d.get("detours") or ()),
        )


@dataclass(frozen=True)
class Placed:
    """Where one object is: its state and pose, or `state` None when it is absent."""

    object: str
    state: State | None
    pose: Pose | None


@dataclass(frozen=True)
class Interrupted:
    """An execution a stop of the service interrupted: its journal id, the steps it had
    recorded, and the objects and arms that are uncertain until a client confirms them
    (`Client.put_world` confirms everything, `Client.patch_world` what it names)."""

    execution: int
    steps_done: int
    objects: tuple[str, ...]
    arms: tuple[str, ...]

    @staticmethod
    def parse(d: dict[str, Any]) -> "Interrupted":
        return Interrupted(
            execution=int(d["execution"]),
            steps_done=int(d.get("steps_done", 0)),
            objects=tuple(d.get("objects") or ()),
            arms=tuple(d.get("arms") or ()),
        )


@dataclass(frozen=True)
class World:
    """The world: every object's whereabouts and every arm's joints. A world the service
    keeps also says which store holds it (`instance`), its `revision` there (one more for
    every write), what interruptions left `uncertain`, and its `etag` (the `ETag` header,
    `"INSTANCE-REVISION"`, to send back as `if_match`). Worlds inside plan answers and
    from the command line are kept nowhere: those four are then None / empty."""

    objects: dict[str, Placed] = field(default_factory=dict)
    arms: dict[str, Joints] = field(default_factory=dict)
    instance: str | None = None
    revision: int | None = None
    uncertain: tuple[Interrupted, ...] = ()
    etag: str | None = None

    @staticmethod
    def parse(d: dict[str, Any], etag: str | None = None) -> "World":
        objects = {}
        for o in d.get("objects") or ():
            name = str(o["object"])
            objects[name] = Placed(name, State.parse(o.get("state")), Pose.parse(o.get("pose")))
        arms = {str(a["arm"]): Joints.parse(a) for a in d.get("arms") or ()}
        revision = d.get("revision")
        instance = d.get("instance")
        if etag is None and instance is not None and revision is not None:
            # The service's tag is documented as exactly this (docs/service.md); a world
            # read from a run answer or a replay, which carry no header, gets it too.
            etag = f'"{instance}-{revision}"'
        return World(
            objects,
            arms,
            instance=instance,
            revision=None if revision is None else int(revision),
            uncertain=tuple(Interrupted.parse(u) for u in d.get("uncertain") or ()),
            etag=etag,
        )

    @property
    def uncertain_objects(self) -> tuple[str, ...]:
        """Every object some interruption left uncertain, each once."""
        return tuple(dict.fromkeys(o for u in self.uncertain for o in u.objects))

    @property
    def uncertain_arms(self) -> tuple[str, ...]:
        """Every arm some interruption left uncertain, each once."""
        return tuple(dict.fromkeys(a for u in self.uncertain for a in u.arms))

    def document(self) -> dict[str, Any]:
        """The world document (docs/world.md) that puts the cell back in this world:
        resting objects at their poses, held ones in their hands, the arms' joints."""
        objects: dict[str, Any] = {}
        for name, placed in self.objects.items():
            if placed.state is None:
                objects[name] = "absent"
                continue
            entry: dict[str, Any] = {
                "holder": placed.state.end_effector,
                "grasp": placed.state.grasp,
            }
            if placed.state.end_effector in self.arms:
                entry["workspace"] = placed.state.workspace
            elif placed.pose is not None:
                x, y, z, w = placed.pose.rotation
                entry["at"] = list(placed.pose.position)
                entry["quat"] = [w, x, y, z]
            else:
                entry["workspace"] = placed.state.workspace
            objects[name] = entry
        return {
            "arms": {arm: j.as_dict() for arm, j in self.arms.items()},
            "objects": objects,
        }


@dataclass(frozen=True)
class Move:
    """One plan carried out in the simulator: the plans executed (the first, then one per
    replan), the simulator's log and clock (`motion_time`, seconds of motion played),
    and where the object ended."""

    object: str
    clears: str | None
    plans: tuple[Plan, ...]
    log: tuple[str, ...]
    motion_time: float
    done: bool
    final_state: State | None
    final_pose: Pose | None
    position_error: float | None
    rotation_error: float | None

    @staticmethod
    def parse(d: dict[str, Any]) -> "Move":
        return Move(
            object=str(d["object"]),
            clears=d.get("clears"),
            plans=tuple(Plan.parse(p) for p in d.get("plans") or ()),
            log=tuple(d.get("log") or ()),
            motion_time=float(d.get("motion_time") or 0.0),
            done=bool(d.get("done")),
            final_state=State.parse(d.get("final_state")),
            final_pose=Pose.parse(d.get("final_pose")),
            position_error=d.get("position_error"),
            rotation_error=d.get("rotation_error"),
        )


@dataclass(frozen=True)
class Run:
    """Moves carried out: each one's record, and the world at the end. From the service,
    `execution` is the run's id in its journal (`Client.execution(id)`), the world carries
    the revision the run produced, and `replayed` is True when the answer is the stored
    first answer of an earlier request with the same idempotency key (nothing moved
    this time)."""

    ok: bool
    moves: tuple[Move, ...]
    world: World | None
    diagnostics: tuple[Diagnostic, ...]
    execution: int | None = None
    replayed: bool = False

    @staticmethod
    def parse(d: dict[str, Any], etag: str | None = None, replayed: bool = False) -> "Run":
        execution = d.get("execution")
        return Run(
            ok=bool(d.get("ok", True)),
            moves=tuple(Move.parse(m) for m in d.get("moves") or ()),
            world=World.parse(d["world"], etag) if d.get("world") else None,
            diagnostics=diagnostics_of(d),
            execution=None if execution is None else int(execution),
            replayed=replayed,
        )

    @property
    def revision(self) -> int | None:
        """The world revision the run left (None outside the service)."""
        return self.world.revision if self.world else None


@dataclass(frozen=True)
class Joint:
    """A joint of an arm's chain: URDF name, limits (None for a continuous joint),
    whether it slides (metres) rather than turns (radians), and the velocity,
    acceleration and jerk (None: no jerk limit) it is timed with, per second."""

    name: str
    lower: float | None
    upper: float | None
    prismatic: bool
    velocity: float = 0.0
    acceleration: float = 0.0
    jerk: float | None = None


@dataclass(frozen=True)
class Arm:
    """An arm: its robot, its chain's joints base to tip, and its home."""

    name: str
    robot: str
    joints: tuple[Joint, ...]
    home: tuple[float, ...]


@dataclass(frozen=True)
class EndEffector:
    """A hand (movable) or a fixed surface, and the workspaces it reaches."""

    name: str
    movable: bool
    kind: str | None
    body: str
    reaches: tuple[str, ...]


@dataclass(frozen=True)
class Workspace:
    """A workspace and its boxes (each (min, max) corners, metres)."""

    name: str
    label: str | None
    derived: bool
    boxes: tuple[tuple[tuple[float, ...], tuple[float, ...]], ...]


@dataclass(frozen=True)
class ObjectInfo:
    """An object: its grasps and resting poses by name, and the size of its graph."""

    name: str
    grasps: tuple[str, ...]
    resting_poses: tuple[str, ...]
    states: int
    arcs: int


@dataclass(frozen=True)
class CellInfo:
    """What `GET /v1/cell` says of the cell the service holds."""

    cell: str
    objects: dict[str, ObjectInfo]
    end_effectors: dict[str, EndEffector]
    workspaces: dict[str, Workspace]
    arms: dict[str, Arm]
    requests: tuple[str, ...]
    tasks: tuple[str, ...]

    @staticmethod
    def parse(d: dict[str, Any]) -> "CellInfo":
        def names(items: Any) -> tuple[str, ...]:
            return tuple(i["name"] if isinstance(i, dict) else str(i) for i in items or ())

        def count(v: Any) -> int:
            return len(v) if isinstance(v, list) else int(v or 0)

        return CellInfo(
            cell=str(d.get("cell", "")),
            objects={
                o["name"]: ObjectInfo(
                    o["name"],
                    names(o.get("grasps")),
                    names(o.get("resting_poses")),
                    count(o.get("states")),
                    count(o.get("arcs")),
                )
                for o in d.get("objects") or ()
            },
            end_effectors={
                e["name"]: EndEffector(
                    e["name"],
                    bool(e.get("movable")),
                    e.get("kind"),
                    str(e.get("body", "")),
                    tuple(e.get("reaches") or ()),
                )
                for e in d.get("end_effectors") or ()
            },
            workspaces={
                w["name"]: Workspace(
                    w["name"],
                    w.get("label"),
                    bool(w.get("derived")),
                    tuple((tuple(b["min"]), tuple(b["max"])) for b in w.get("boxes") or ()),
                )
                for w in d.get("workspaces") or ()
            },
            arms={
                a["name"]: Arm(
                    a["name"],
                    str(a.get("robot", "")),
                    tuple(
                        Joint(
                            j["name"],
                            j.get("lower"),
                            j.get("upper"),
                            bool(j.get("prismatic")),
                            float(j.get("velocity", 0.0)),
                            float(j.get("acceleration", 0.0)),
                            j.get("jerk"),
                        )
                        for j in a.get("joints") or ()
                    ),
                    tuple(a.get("home") or ()),
                )
                for a in d.get("arms") or ()
            },
            requests=names(d.get("requests")),
            tasks=names(d.get("tasks")),
        )


@dataclass(frozen=True)
class Health:
    """What `GET /v1/health` says: the cell and version, the store the world is kept in
    (`instance`) and its `revision`, `durability` (`"file"`: a state file, `"memory"`:
    `--ephemeral`, nothing survives a stop), and the executions a stop `interrupted`
    whose objects and arms are still uncertain. `health["status"]` still works, for
    callers of the time when `Client.health` gave a dict."""

    status: str
    cell: str
    version: str
    instance: str
    revision: int
    durability: str
    interrupted: tuple[Interrupted, ...]

    @staticmethod
    def parse(d: dict[str, Any]) -> "Health":
        return Health(
            status=str(d.get("status", "")),
            cell=str(d.get("cell", "")),
            version=str(d.get("version", "")),
            instance=str(d.get("instance", "")),
            revision=int(d.get("revision", 0)),
            durability=str(d.get("durability", "")),
            interrupted=tuple(Interrupted.parse(u) for u in d.get("interrupted") or ()),
        )

    def __getitem__(self, name: str) -> Any:
        if name not in {f.name for f in fields(self)}:
            raise KeyError(name)
        return getattr(self, name)


@dataclass(frozen=True)
class ExecutionSummary:
    """One execution of the service's journal: its `id`, the idempotency `key` it was sent
    with, its `status` (`running`, `succeeded`, `failed`, `cancelled`, `interrupted`), the
    revision it started from (`base`) and the one its end left (`result`, None while
    running or interrupted), the steps it recorded, the objects and arms it moves, when it
    started and ended (ms since the Unix epoch) and what was asked (`intent`:
    `{"endpoint": ..., "request": ...}`)."""

    id: int
    key: str | None
    status: str
    base: int
    result: int | None
    steps_done: int
    objects: tuple[str, ...]
    arms: tuple[str, ...]
    started_ms: int
    finished_ms: int | None
    intent: dict[str, Any]

    @staticmethod
    def fields_of(d: dict[str, Any]) -> dict[str, Any]:
        result = d.get("result")
        finished = d.get("finished_ms")
        return dict(
            id=int(d["id"]),
            key=d.get("key"),
            status=str(d["status"]),
            base=int(d.get("base", 0)),
            result=None if result is None else int(result),
            steps_done=int(d.get("steps_done", 0)),
            objects=tuple(d.get("objects") or ()),
            arms=tuple(d.get("arms") or ()),
            started_ms=int(d.get("started_ms", 0)),
            finished_ms=None if finished is None else int(finished),
            intent=d.get("intent") if isinstance(d.get("intent"), dict) else {},
        )

    @staticmethod
    def parse(d: dict[str, Any]) -> "ExecutionSummary":
        return ExecutionSummary(**ExecutionSummary.fields_of(d))


@dataclass(frozen=True)
class ExecutionStep:
    """One recorded step of an execution: its index (1 for the first), the world revision
    it left, and what the executor reported (`{"object": ..., "step": <plan step>}`)."""

    index: int
    revision: int
    report: Any

    @staticmethod
    def parse(d: dict[str, Any]) -> "ExecutionStep":
        return ExecutionStep(int(d["index"]), int(d["revision"]), d.get("report"))


@dataclass(frozen=True)
class Execution(ExecutionSummary):
    """One execution with its recorded steps and, once it ended, the answer it was given
    (`outcome`: `{"status": HTTP status, "body": run document}`; `run()` parses it)."""

    steps: tuple[ExecutionStep, ...] = ()
    outcome: dict[str, Any] | None = None

    @staticmethod
    def parse(d: dict[str, Any]) -> "Execution":
        outcome = d.get("outcome")
        return Execution(
            **ExecutionSummary.fields_of(d),
            steps=tuple(ExecutionStep.parse(s) for s in d.get("steps") or ()),
            outcome=outcome if isinstance(outcome, dict) else None,
        )

    def run(self) -> Run | None:
        """The run document the execution was answered with, or None before it ended."""
        if self.outcome is None or not isinstance(self.outcome.get("body"), dict):
            return None
        return Run.parse(self.outcome["body"])


# --- the schema these types mirror ----------------------------------------------------
#
# The documents are defined once, as Rust types (driver/src/document in the cellc
# repository), and the service's OpenAPI document (`GET /v1/openapi.json`) carries their
# schemas. Each class above mirrors one schema, field by field: `MIRRORS` names it, the
# fields whose JSON property has another name, and the properties deliberately not kept.
# python/tests/test_client.py holds the table to the live schema, so a field added,
# renamed or removed in Rust fails that test until the class follows.

MIRRORS: dict[type, tuple[str, dict[str, str], frozenset[str]]] = {
    Diagnostic: ("Diagnostic", {}, frozenset({"file", "line", "column", "span", "labels"})),
    Pose: ("Pose", {}, frozenset()),
    Joints: ("Joints", {"names": "joints"}, frozenset()),
    State: ("State", {}, frozenset()),
    Trajectory: ("Trajectory", {}, frozenset()),
    Point: ("Point", {}, frozenset()),
    Step: ("Step", {}, frozenset()),
    Plan: ("Plan", {}, frozenset()),
    Placed: ("Placed", {}, frozenset()),
    World: ("World", {}, frozenset()),
    Interrupted: ("Interrupted", {}, frozenset()),
    Move: ("Move", {}, frozenset()),
    Run: ("Run", {}, frozenset({"version", "kind", "plans", "errors", "warnings"})),
    Health: ("Health", {}, frozenset()),
    ExecutionSummary: ("ExecutionSummary", {}, frozenset()),
    ExecutionStep: ("ExecutionStep", {}, frozenset()),
    Execution: ("Execution", {}, frozenset()),
    Joint: ("Joint", {}, frozenset()),
    Arm: ("Arm", {}, frozenset()),
    EndEffector: ("EndEffector", {}, frozenset()),
    Workspace: ("Workspace", {}, frozenset()),
    ObjectInfo: ("Object", {}, frozenset()),
    CellInfo: ("Cell", {}, frozenset()),
    Duration: ("Duration", {}, frozenset()),
    JointTrajectoryPoint: ("JointTrajectoryPoint", {}, frozenset()),
    JointTrajectory: ("JointTrajectory", {}, frozenset()),
    FollowJointTrajectoryGoal: ("FollowJointTrajectoryGoal", {}, frozenset()),
    StepGoal: ("StepGoal", {}, frozenset()),
    PlanGoals: ("PlanGoals", {}, frozenset()),
    ControllerGoals: ("ControllerGoals", {}, frozenset()),
}

# Fields a class has that its schema does not, because the client reads them from the
# answer's headers rather than its body: the `ETag`, and `idempotent-replayed`.
FROM_HEADERS: dict[type, frozenset[str]] = {
    World: frozenset({"etag"}),
    Run: frozenset({"replayed"}),
}

# Schemas with properties that no class mirrors, and how the client gives them instead.
NOT_MIRRORED: dict[str, str] = {
    "Report": "read through `diagnostics_of`",
    "Label": "not kept (a diagnostic's place is for the command line)",
    "Span": "not kept",
    "Detour": "kept as a dict in `Plan.detours`",
    "ArmJoints": "kept as (arm, joints) in `Trajectory.arms`",
    "Grasp": "kept by name in `ObjectInfo`",
    "Box3": "kept as (min, max) in `Workspace.boxes`",
    "Executions": "returned as a list of `ExecutionSummary` by `Client.executions`",
    "Explanation": "returned as a dict by `Client.explain`",
    "CutEntry": "part of the explanation's dict",
    "Suggestion": "part of the explanation's dict",
    "Pruned": "part of the explanation's dict",
    "MoveRequest": "written by `Client.plan`, `execute`, `explain`",
    "TaskRequest": "written by `Client.task`",
    "WorldDocument": "written by `World.document` for `Client.set_world`",
    "PlacedEntry": "part of the dict `World.document` writes",
    "TaskMove": "written by `Client.task`",
    "Options": "written from the methods' keyword arguments",
}
