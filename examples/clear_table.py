"""An example task planner on top of `cellc serve`: clears the Vito table, the way a
client that may time out, race another client or outlive a crash of the service must.

    cargo run --release -- serve cells/vito.cell &          # prints "listening on URL"
    python3 examples/clear_table.py http://127.0.0.1:7878

1. It reads the world with its revision and ETag.
2. If a stop of the service interrupted an execution, the world is uncertain for what
   that execution was moving, and the service refuses to plan from it. The example then
   confirms those objects and arms where the service last recorded them (a real cell
   would look with its cameras first), with a JSON Patch naming only them, sent under
   the ETag it read so that it overwrites no write it has not seen.
3. It executes the moves of the cell's `clear_table` task one by one, each under a fresh
   idempotency key and the revision it planned against. A request that times out is sent
   again with the same key: the service answers a repeat with the first outcome, so
   nothing moves twice. When the world moved on meanwhile (412), it reads it again and
   goes on from there; when a move fails, it tries again clearing the way, then with
   other seeds. A move whose object is already where it should be is skipped, so the
   example may be run again against a service that keeps its world.

It prints each move's execution and the revision it produced, and the world at the end.
"""

from __future__ import annotations

import math
import re
import sys
import uuid

sys.path.insert(0, __file__.rsplit("/examples/", 1)[0] + "/python")

from cellc import CellcError, Client, PreconditionFailed, World, WorldUncertain  # noqa: E402

# The `clear_table` task of cells/vito.cell (GET /v1/cell names a cell's tasks; their
# moves are the cell's text).
MOVES = [
    ("ball", "bin in ws_right_bin"),
    ("cylinder", "bin in ws_right_bin"),
    ("pitcher", "table at (0.4, -0.3, 1.01)"),
]
# Plainly, then clearing the way, then with two more seeds.
ATTEMPTS = [(False, 0), (True, 0), (True, 1), (True, 2)]
# How many times a request that timed out is sent again (with the same key).
RETRIES = 2


def already_there(world: World, name: str, goal: str) -> bool:
    """Whether the world has `name` where `goal` says (`HOLDER in WORKSPACE`, or
    `HOLDER at (x, y, z)` within a centimetre)."""
    placed = world.objects[name]
    if placed.state is None:
        return False
    inside = re.fullmatch(r"(\w+) in (\w+)", goal)
    if inside:
        return (placed.state.end_effector, placed.state.workspace) == inside.groups()
    at = re.fullmatch(r"(\w+) at \(([^)]*)\)", goal)
    if at and placed.pose is not None and placed.state.end_effector == at[1]:
        target = [float(v) for v in at[2].split(",")]
        return math.dist(placed.pose.position, target) < 0.01
    return False


def confirm(client: Client, world: World) -> World:
    """Confirms what interruptions left uncertain where the service recorded it, with one
    JSON Patch under the world's ETag; the world as the service then has it."""
    document = world.document()

    def pointer(name: str) -> str:  # RFC 6901
        return name.replace("~", "~0").replace("/", "~1")

    operations = [
        {"op": "replace", "path": f"/objects/{pointer(name)}", "value": document["objects"][name]}
        for name in world.uncertain_objects
    ] + [
        {"op": "replace", "path": f"/arms/{pointer(arm)}", "value": document["arms"][arm]}
        for arm in world.uncertain_arms
        if arm in document["arms"]
    ]
    for u in world.uncertain:
        print(
            f"execution {u.execution} was interrupted after step {u.steps_done}: "
            f"confirming objects {', '.join(u.objects) or '-'} and arms {', '.join(u.arms) or '-'}"
        )
    confirmed = client.patch_world(operations=operations, if_match=world)
    print(f"confirmed: revision {world.revision} -> {confirmed.revision}")
    return confirmed


def send(client: Client, world: World, name: str, goal: str) -> World | None:
    """Executes one move against `world`'s revision, retrying as the module says; the
    world after it, or None when every attempt failed."""
    for clear, seed in ATTEMPTS:
        # One logical request: one key, kept for its retries.
        key = str(uuid.uuid4())
        try:
            run = client.execute(
                name,
                goal,
                clear=clear,
                seed=seed,
                revision=world.revision,
                idempotency_key=key,
                retries=RETRIES,
            )
        except PreconditionFailed as e:
            # Another client wrote meanwhile: read the world and decide again.
            world = client.world()
            print(f"  {name}: {e.code}, the world is now at revision {world.revision}")
            if already_there(world, name, goal):
                return world
            continue
        except WorldUncertain:
            world = confirm(client, client.world())
            continue
        except CellcError as e:
            print(f"  {name} -> {goal} (clear={clear}, seed={seed}): {e}")
            # A failed execution may have moved things: plan the next attempt from now.
            world = client.world()
            continue
        for move in run.moves:
            why = f" (out of the way of {move.clears})" if move.clears else ""
            strategy = move.plans[0].strategy if move.plans else "?"
            print(f"  {move.object}: {strategy}{why}, done={move.done}")
        replay = " (the first answer, replayed)" if run.replayed else ""
        print(
            f"  {name} -> {goal}: execution {run.execution}, "
            f"revision {world.revision} -> {run.revision}{replay}"
        )
        return run.world or client.world()
    return None


def main(url: str) -> int:
    client = Client(url)
    world = client.world()
    print(f"world at revision {world.revision} (ETag {world.etag})")
    if world.uncertain:
        world = confirm(client, world)
    failed = []
    for name, goal in MOVES:
        print(f"{name}:")
        if already_there(world, name, goal):
            print(f"  {name} is already at {goal}")
            continue
        after = send(client, world, name, goal)
        if after is None:
            failed.append(name)
            world = client.world()
        else:
            world = after
    print(f"world at revision {world.revision}:")
    for name, placed in world.objects.items():
        where = "absent" if placed.state is None else (
            f"{placed.state.end_effector}.{placed.state.grasp} in {placed.state.workspace}"
        )
        print(f"  {name}: {where}")
    if failed:
        print(f"could not move: {', '.join(failed)}")
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1] if len(sys.argv) > 1 else "http://127.0.0.1:7878"))
