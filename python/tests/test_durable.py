"""The client against the service's durable world: revisions and ETags, preconditions,
idempotency keys and retries, the journal, and an uncertain world after a SIGKILL during
a task (docs/service.md)."""

from __future__ import annotations

import re
import subprocess
import sys
import threading
import time
import uuid

import pytest
from conftest import ROOT, Server

from cellc import CellcError, Client, PreconditionFailed, WorldUncertain

BALL = ("ball", "bin in ws_right_bin")
TASK = [("cylinder", "bin in ws_right_bin"), ("pitcher", "table at (0.4, -0.3, 1.01)")]


def where(world):
    return {n: (p.state, p.pose) for n, p in world.objects.items()}


def states(world):
    return {n: p.state for n, p in world.objects.items()}


def test_revisions_follow_the_answers(client):
    before = client.world()
    assert before.revision is not None and before.instance
    assert before.etag == f'"{before.instance}-{before.revision}"'
    health = client.health()
    assert (health.instance, health.revision, health.durability) == (
        before.instance,
        before.revision,
        "memory",
    )
    assert health["status"] == "ok" and health.interrupted == ()

    run = client.execute(*BALL, motions=False)
    assert run.ok and run.execution is not None and not run.replayed
    # One revision per recorded step at least: the run's own number is where the world is.
    assert run.revision > before.revision
    after = client.world()
    assert after.revision == run.revision
    assert after.etag == f'"{after.instance}-{run.revision}"'
    assert after.objects["ball"].state.end_effector == "bin"

    # Each write starts from the last answer's revision and says the one it produced.
    put = client.put_world(after, if_match=after)
    assert put.revision == run.revision + 1 and put.etag != after.etag
    patched = client.patch_world({"objects": {"ball": "absent"}}, revision=put.revision)
    assert patched.revision == put.revision + 1
    assert patched.objects["ball"].state is None
    assert client.world().revision == patched.revision

    # The journal says the same numbers.
    (latest,) = client.executions(1)
    assert (latest.id, latest.status, latest.base, latest.result) == (
        run.execution,
        "succeeded",
        before.revision,
        run.revision,
    )
    one = client.execution(run.execution)
    assert one.steps and one.steps[-1].revision <= run.revision
    assert [s.index for s in one.steps] == list(range(1, len(one.steps) + 1))
    assert one.run().execution == run.execution
    with pytest.raises(CellcError) as e:
        client.execution(run.execution + 1000)
    assert (e.value.code, e.value.status) == ("S0013", 404)


def test_a_stale_precondition_changes_nothing(client):
    stale = client.world()
    current = client.put_world(stale, if_match=stale)
    assert current.revision == stale.revision + 1

    moved = stale.document()
    moved["objects"]["ball"] = "absent"
    with pytest.raises(PreconditionFailed) as e:
        client.put_world(moved, if_match=stale)
    assert (e.value.code, e.value.status) == ("S0006", 412)
    with pytest.raises(PreconditionFailed):
        client.put_world(moved, revision=stale.revision)
    with pytest.raises(PreconditionFailed):
        client.patch_world(operations=[{"op": "remove", "path": "/objects/ball"}], if_match=stale)
    with pytest.raises(PreconditionFailed):
        client.execute(*BALL, motions=False, revision=stale.revision)
    with pytest.raises(PreconditionFailed):
        client.task([BALL], motions=False, if_match=stale.etag)

    now = client.world()
    assert now.revision == current.revision
    assert where(now) == where(current)
    assert client.executions() == []
    # The current revision is taken.
    run = client.execute(*BALL, motions=False, if_match=now)
    assert run.ok and run.revision > now.revision


def test_a_repeated_key_returns_the_first_answer_and_moves_nothing(client):
    key = str(uuid.uuid4())
    first = client.execute(*BALL, motions=False, idempotency_key=key)
    assert first.ok and not first.replayed
    world = client.world()
    again = client.execute(*BALL, motions=False, idempotency_key=key)
    assert again.replayed and again.execution == first.execution
    assert again.revision == first.revision
    now = client.world()
    assert now.revision == world.revision and where(now) == where(world)
    assert [e.id for e in client.executions()] == [first.execution]

    # The same key for another request: refused, and nothing moves.
    with pytest.raises(CellcError) as e:
        client.execute("cylinder", "bin in ws_right_bin", motions=False, idempotency_key=key)
    assert not isinstance(e.value, (PreconditionFailed, WorldUncertain))
    assert (e.value.code, e.value.status) == ("S0008", 422)
    assert client.world().revision == world.revision

    # A generated key is one key per call.
    one = client.task([("cylinder", "bin in ws_right_bin")], motions=False, idempotency_key=True)
    other = client.execute("cylinder", "bin in ws_right_bin", motions=False, idempotency_key=True)
    assert not one.replayed and not other.replayed and one.execution != other.execution


def test_retries_need_a_key():
    # Refused before anything is sent: no service listens there.
    with pytest.raises(ValueError):
        Client("http://127.0.0.1:9").execute(*BALL, retries=2)


def moves_printed(stdout: str) -> list[tuple[int, int]]:
    return [(int(a), int(b)) for a, b in re.findall(r"revision (\d+) -> (\d+)", stdout)]


def run_example(url: str) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, str(ROOT / "examples" / "clear_table.py"), url],
        capture_output=True,
        text=True,
        timeout=600,
    )


def test_the_example_clears_the_table_revision_by_revision(client):
    start = client.world().revision
    out = run_example(client.url)
    assert out.returncode == 0, out.stdout + out.stderr
    revisions = moves_printed(out.stdout)
    assert len(revisions) == 3, out.stdout
    # Each move planned against the revision the one before produced.
    assert revisions[0][0] == start
    assert all(a < b for a, b in revisions)
    assert all(revisions[i][1] == revisions[i + 1][0] for i in range(2)), out.stdout
    world = client.world()
    assert world.revision == revisions[-1][1]
    for name in ("ball", "cylinder"):
        assert world.objects[name].state.end_effector == "bin", out.stdout
    assert world.objects["pitcher"].state.workspace == "ws_right_table", out.stdout
    # Again: nothing left to do, nothing moves.
    out = run_example(client.url)
    assert out.returncode == 0 and moves_printed(out.stdout) == [], out.stdout
    assert client.world().revision == world.revision


def test_an_interrupted_task_leaves_the_world_uncertain_until_confirmed(tmp_path):
    state = str(tmp_path / "vito.state.sqlite")
    server = Server("--sim-pace", "1", "--state", state)
    try:
        client = Client(server.url, timeout=120)
        start = client.world()
        assert client.health().durability == "file"

        # A timeout is retried under the same key: the first execution's answer comes
        # back, and it ran once.
        impatient = Client(server.url, timeout=1.0)
        key = str(uuid.uuid4())
        run = impatient.execute(*BALL, idempotency_key=key, retries=30)
        assert run.replayed and run.ok
        assert [(e.id, e.key) for e in client.executions()] == [(run.execution, key)]
        assert client.world().revision == run.revision

        # A task sent, and the service killed once it has recorded a step of it.
        task_key = str(uuid.uuid4())
        answered = []
        sender = threading.Thread(
            target=lambda: answered.append(
                _quietly(lambda: client.task(TASK, idempotency_key=task_key))
            ),
            daemon=True,
        )
        sender.start()
        deadline = time.monotonic() + 300  # planning in a debug build under load is slow
        while client.world().revision == run.revision:
            assert time.monotonic() < deadline, "the task recorded no step"
            time.sleep(0.05)
        server.kill()
        sender.join(timeout=60)
        assert answered and isinstance(answered[0], Exception), answered
    finally:
        server.stop()

    server = Server("--sim-pace", "1", "--state", state)
    try:
        client = Client(server.url, timeout=120)
        recovered = client.world()
        assert recovered.instance == start.instance and recovered.revision > run.revision
        (interrupted,) = recovered.uncertain
        assert interrupted.objects == ("cylinder", "pitcher")
        assert interrupted.arms == ("left", "right")
        assert interrupted.steps_done >= 1
        assert client.health().interrupted == recovered.uncertain
        # The ball's move was acknowledged before: it is still in the bin.
        assert recovered.objects["ball"].state.end_effector == "bin"

        with pytest.raises(WorldUncertain) as e:
            client.plan(*BALL)
        assert (e.value.code, e.value.status) == ("S0007", 409)
        assert e.value.objects == ("cylinder", "pitcher") and e.value.arms == ("left", "right")
        assert e.value.interrupted == recovered.uncertain
        with pytest.raises(WorldUncertain):
            client.execute("cylinder", "bin in ws_right_bin", idempotency_key=True)
        # The interrupted task's key says so rather than running it again.
        with pytest.raises(CellcError) as e:
            client.task(TASK, idempotency_key=task_key)
        assert (e.value.code, e.value.status) == ("S0012", 409)

        # A patch confirms what it names, and only that.
        document = recovered.document()
        partly = client.patch_world(
            operations=[
                {"op": "replace", "path": "/objects/cylinder", "value": document["objects"]["cylinder"]}
            ],
            if_match=recovered,
        )
        assert partly.uncertain_objects == ("pitcher",)
        with pytest.raises(WorldUncertain) as e:
            client.plan(*BALL)
        assert e.value.objects == ("pitcher",) and e.value.arms == ("left", "right")

        # A PUT confirms everything; planning works again from that world.
        confirmed = client.put_world(partly, if_match=partly)
        assert confirmed.uncertain == () and confirmed.revision == partly.revision + 1
        assert states(confirmed) == states(recovered)
        assert client.health().interrupted == ()
        assert client.plan("cylinder", "bin in ws_right_bin", motions=False)
    finally:
        server.stop()


def test_the_example_confirms_an_uncertain_world(tmp_path):
    state = str(tmp_path / "vito.state.sqlite")
    server = Server("--sim-pace", "1", "--state", state)
    try:
        client = Client(server.url, timeout=120)
        start = client.world().revision
        sender = threading.Thread(
            target=lambda: _quietly(lambda: client.task([BALL])), daemon=True
        )
        sender.start()
        deadline = time.monotonic() + 300  # planning in a debug build under load is slow
        while client.world().revision == start:
            assert time.monotonic() < deadline, "the task recorded no step"
            time.sleep(0.05)
        server.kill()
        sender.join(timeout=60)
    finally:
        server.stop()
    server = Server("--state", state)
    try:
        assert Client(server.url).world().uncertain
        out = run_example(server.url)
        assert out.returncode == 0, out.stdout + out.stderr
        assert "execution 1 was interrupted after step" in out.stdout, out.stdout
        assert "confirming objects ball and arms left, right" in out.stdout, out.stdout
        world = Client(server.url).world()
        assert world.uncertain == ()
        assert world.objects["pitcher"].state.workspace == "ws_right_table", out.stdout
    finally:
        server.stop()


def _quietly(call):
    """`call()`'s answer, or the exception it raised (a killed service's, here)."""
    try:
        return call()
    except Exception as e:  # noqa: BLE001 - the test looks at what it was
        return e
