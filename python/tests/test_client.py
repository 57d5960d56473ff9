"""The Python client against the real service: `cellc serve cells/vito.cell` started on a
free port (the binary from `CELLC_BIN`, or the workspace's `target/debug/cellc`, which
`cargo test --workspace` builds)."""

from __future__ import annotations

import subprocess
import sys

import pytest
from conftest import ROOT

from cellc import CellcError, World


def test_health_and_cell(client):
    assert client.health()["status"] == "ok"
    cell = client.cell()
    assert cell.cell == "vito"
    assert set(cell.objects) == {"cylinder", "pitcher", "colander", "ball"}
    assert "side" in cell.objects["cylinder"].grasps
    assert "standing" in cell.objects["cylinder"].resting_poses
    assert cell.end_effectors["left"].movable and not cell.end_effectors["table"].movable
    left = cell.arms["left"]
    assert [j.name for j in left.joints][0] == "lwr_a1_joint" and len(left.home) == 7
    assert all(j.lower < j.upper for j in left.joints)
    box = cell.workspaces["ws_left_right_table"].boxes[0]
    assert all(lo < hi for lo, hi in zip(*box))
    assert "clear_table" in cell.tasks


def test_the_world_is_the_cells(client):
    world = client.world()
    placed = {n for n, p in world.objects.items() if p.state is not None}
    assert placed == {"cylinder", "pitcher", "ball"}
    for arm in ("left", "right"):
        joints = world.arms[arm]
        assert len(joints.names) == len(joints.positions) == 7


def test_plan_names_every_joint_and_leaves_the_world(client):
    before = client.world()
    (plan,) = client.plan("ball", "bin in ws_right_bin")
    assert plan.object == "ball" and plan.holders[-1] == "bin"
    motions = [s.motion for s in plan.steps if s.motion]
    assert motions
    for m in motions:
        width = sum(len(names) for _, names in m.arms)
        assert all(len(p.positions) == width for p in m.points)
        assert all(len(p.velocities) == width for p in m.points)
        assert m.points[0].time_from_start == 0.0
        assert m.duration > 0.0
    assert client.world() == before


def test_execute_moves_the_object_and_keeps_the_world(client):
    run = client.execute("ball", "bin in ws_right_bin", motions=False)
    assert run.ok and run.moves[-1].done
    assert client.world().objects["ball"].state.end_effector == "bin"


def test_errors_carry_their_codes(client):
    with pytest.raises(CellcError) as e:
        client.plan("bal", "bin in ws_right_bin")
    assert e.value.code == "R0003" and 400 <= e.value.status < 500
    # Where the cylinder stands: refused, naming it.
    with pytest.raises(CellcError) as e:
        client.plan("ball", "table at (0.45, 0.45, 0.95)", motions=False)
    assert e.value.code == "R0010"
    assert "cylinder" in str(e.value)


def test_set_world_round_trips_and_refuses_bad_documents(client):
    world = client.world()
    moved = client.set_world(world.document())
    assert {n: p.state for n, p in moved.objects.items()} == {
        n: p.state for n, p in world.objects.items()
    }
    with pytest.raises(CellcError) as e:
        client.set_world({"objects": {"ball": {"holder": "tabel", "at": [0.4, 0.0, 0.95]}}})
    assert e.value.code == "R0009"
    assert isinstance(client.world(), World)


def test_a_task_clears_the_table(client):
    run = client.task(
        [
            ("ball", "bin in ws_right_bin"),
            ("cylinder", "bin in ws_right_bin"),
            ("pitcher", "table at (0.4, -0.3, 1.01)"),
        ],
        motions=False,
    )
    assert run.ok
    assert [m.object for m in run.moves] == ["ball", "cylinder", "pitcher"]
    world = client.world()
    assert world.objects["cylinder"].state.end_effector == "bin"
    assert world.objects["pitcher"].state.workspace == "ws_right_table"


def test_the_example_task_planner_clears_the_table(client):
    out = subprocess.run(
        [sys.executable, str(ROOT / "examples" / "clear_table.py"), client.url],
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert out.returncode == 0, out.stdout + out.stderr
    world = client.world()
    for name in ("ball", "cylinder"):
        assert world.objects[name].state.end_effector == "bin", out.stdout
    assert world.objects["pitcher"].state.workspace == "ws_right_table", out.stdout


def test_types_mirror_the_service_schema(client):
    """Every dataclass is held to the schema the service generates from its Rust types,
    field by field, and every document schema is either mirrored or said not to be."""
    import dataclasses

    from cellc.types import FROM_HEADERS, MIRRORS, NOT_MIRRORED

    schemas = client._call("GET", "/openapi.json")["components"]["schemas"]
    for cls, (name, renamed, not_kept) in MIRRORS.items():
        properties = set(schemas[name]["properties"])
        headers = FROM_HEADERS.get(cls, frozenset())
        fields = {renamed.get(f.name, f.name) for f in dataclasses.fields(cls)} - headers
        assert not headers & properties, (cls.__name__, headers & properties)
        assert fields == properties - not_kept, (cls.__name__, name, fields ^ (properties - not_kept))
        assert not_kept <= properties, (cls.__name__, not_kept - properties)
    mirrored = {name for name, _, _ in MIRRORS.values()}
    with_properties = {n for n, s in schemas.items() if "properties" in s}
    assert with_properties == mirrored | set(NOT_MIRRORED), with_properties ^ (mirrored | set(NOT_MIRRORED))
