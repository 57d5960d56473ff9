"""Python client of the cellc planning service (`cellc serve CELL`).

    from cellc import Client
    c = Client("http://127.0.0.1:7878")
    world = c.world()                       # with .revision, .etag, .uncertain
    for name, placed in world.objects.items(): ...
    run = c.execute("ball", "bin in ws_right_bin", revision=world.revision,
                    idempotency_key=True, retries=2)
    goals = c.follow_joint_trajectory("ball", "bin in ws_right_bin", rate=250)

Standard library only; Python 3.10 or later.
"""

from .client import CellcError, Client, PreconditionFailed, WorldUncertain
from .types import (
    Arm,
    CellInfo,
    Diagnostic,
    EndEffector,
    Execution,
    ExecutionStep,
    ExecutionSummary,
    Health,
    Interrupted,
    Joint,
    Joints,
    ObjectInfo,
    Workspace,
)
from .types import Move, Placed, Plan, Point, Pose, Run, State, Step, Trajectory, World
from .types import (
    ControllerGoals,
    Duration,
    FollowJointTrajectoryGoal,
    JointTrajectory,
    JointTrajectoryPoint,
    PlanGoals,
    StepGoal,
)

__all__ = [
    "Arm",
    "CellInfo",
    "EndEffector",
    "Execution",
    "ExecutionStep",
    "ExecutionSummary",
    "Health",
    "Interrupted",
    "Joint",
    "ObjectInfo",
    "Workspace",
    "CellcError",
    "Client",
    "ControllerGoals",
    "Duration",
    "FollowJointTrajectoryGoal",
    "JointTrajectory",
    "JointTrajectoryPoint",
    "PlanGoals",
    "StepGoal",
    "Diagnostic",
    "Joints",
    "Move",
    "Placed",
    "Plan",
    "Pose",
    "PreconditionFailed",
    "Run",
    "State",
    "Step",
    "Point",
    "Trajectory",
    "World",
    "WorldUncertain",
]
