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


def test_a_rate_gives_points_one_period_apart(client):
    (plan,) = client.plan("ball", "bin in ws_right_bin", rate=250)
    motions = [s.motion for s in plan.steps if s.motion]
    assert motions
    for m in motions:
        times = [p.time_from_start for p in m.points]
        gaps = [b - a for a, b in zip(times, times[1:])]
        # Every point 4 ms after the one before, the last (the goal, at rest) at the end.
        assert all(abs(g - 0.004) < 1e-9 for g in gaps[:-1]), gaps
        assert 0.0 < gaps[-1] <= 0.004 + 1e-9


def test_scalings_slow_the_motions_down(client):
    (fast,) = client.plan("ball", "bin in ws_right_bin")
    (slow,) = client.plan("ball", "bin in ws_right_bin", velocity_scaling=0.5, acceleration_scaling=0.25)
    for a, b in zip(fast.steps, slow.steps):
        assert (a.motion is None) == (b.motion is None)
        if a.motion:
            assert b.motion.duration > 1.5 * a.motion.duration
    # Every point's velocities within half of each joint's limit.
    arms = client.cell().arms
    checked = 0
    for step in slow.steps:
        if step.motion:
            joints = [j for arm, _ in step.motion.arms for j in arms[arm].joints]
            for p in step.motion.points:
                for v, j in zip(p.velocities, joints, strict=True):
                    assert abs(v) <= 0.5 * j.velocity * (1 + 1e-6)
                    checked += 1
    assert checked


def test_options_out_of_range_are_refused_with_their_code(client):
    for options in ({"velocity_scaling": 0.0}, {"acceleration_scaling": 1.5}, {"rate": 5000.0}):
        with pytest.raises(CellcError) as e:
            client.plan("ball", "bin in ws_right_bin", **options)
        assert e.value.code == "R0012" and e.value.status == 400
        (name,) = options
        assert f"`{name}`" in str(e.value)


def test_follow_joint_trajectory_goals_are_the_plans_motions(client):
    (plan,) = client.plan("cylinder", "right in ws_left_right_table", rate=100)
    answer = client.follow_joint_trajectory("cylinder", "right in ws_left_right_table", rate=100)
    (goals,) = answer.plans
    arms = client.cell().arms
    expected = [
        (i, arm, names)
        for i, s in enumerate(plan.steps)
        if s.motion
        for arm, names in s.motion.arms
    ]
    assert [(g.step, g.arm, g.goal.trajectory.joint_names) for g in goals.goals] == expected
    assert goals.request == "request" and goals.object == "cylinder"
    for g in goals.goals:
        motion = plan.steps[g.step].motion
        names = [n for _, n in motion.arms]
        start = sum(len(n) for n in names[: [a for a, _ in motion.arms].index(g.arm)])
        width = len(g.goal.trajectory.joint_names)
        assert g.goal.trajectory.joint_names == tuple(j.name for j in arms[g.arm].joints)
        points = g.goal.trajectory.points
        assert len(points) == len(motion.points)
        for p, q in zip(points, motion.points):
            assert 0 <= p.time_from_start.nanosec < 1_000_000_000
            assert abs(p.time_from_start.seconds - q.time_from_start) <= 1.5e-9
            assert p.positions == q.positions[start : start + width]
            assert p.velocities == q.velocities[start : start + width]
            assert p.accelerations == q.accelerations[start : start + width]
        nanoseconds = [p.time_from_start.sec * 10**9 + p.time_from_start.nanosec for p in points]
        assert all(a < b for a, b in zip(nanoseconds, nanoseconds[1:]))
        message = g.goal.message()
        assert set(message["trajectory"]) == {"joint_names", "points"}
        assert set(message["trajectory"]["points"][0]["time_from_start"]) == {"sec", "nanosec"}
