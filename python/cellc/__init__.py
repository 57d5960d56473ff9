"""Python client of the cellc planning service (`cellc serve CELL`).

    from cellc import Client
    c = Client("http://127.0.0.1:7878")
    for name, placed in c.world().objects.items(): ...
    run = c.execute("ball", "bin in ws_right_bin")

Standard library only; Python 3.10 or later.
"""

from .client import CellcError, Client
from .types import (
    Arm,
    CellInfo,
    Diagnostic,
    EndEffector,
    Joint,
    Joints,
    ObjectInfo,
    Workspace,
)
from .types import Move, Placed, Plan, Pose, Run, State, Step, Trajectory, World

__all__ = [
    "Arm",
    "CellInfo",
    "EndEffector",
    "Joint",
    "ObjectInfo",
    "Workspace",
    "CellcError",
    "Client",
    "Diagnostic",
    "Joints",
    "Move",
    "Placed",
    "Plan",
    "Pose",
    "Run",
    "State",
    "Step",
    "Trajectory",
    "World",
]
