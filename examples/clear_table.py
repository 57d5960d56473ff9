"""An example task planner on top of `cellc serve`: clears the Vito table.

    cargo run --release -- serve cells/vito.cell &          # prints "listening on URL"
    python3 examples/clear_table.py http://127.0.0.1:7878

It reads the world, chooses an order (the objects nearest the bin first, so that the
first moves free the way for the later ones), and sends each object off the table into
the bin; one the bin cannot hold goes to the right part of the table (where it stays if
it is there already). When a request
fails it replans: again with `clear` (what stands in the way is moved first), then with
other seeds. It prints what it did and the world at the end.
"""

from __future__ import annotations

import math
import sys

sys.path.insert(0, __file__.rsplit("/examples/", 1)[0] + "/python")

from cellc import CellcError, Client  # noqa: E402

BIN = (0.425, -0.6)  # the bin's middle on the table (cells/vito.cell)
GOALS = ["bin in ws_right_bin", "table in ws_right_table"]


def on_the_table(world) -> list[str]:
    """The objects resting on the table, nearest the bin first."""
    out = []
    for name, placed in world.objects.items():
        if placed.state is None or placed.pose is None:
            continue
        if placed.state.end_effector == "table":
            x, y, _ = placed.pose.position
            out.append((math.hypot(x - BIN[0], y - BIN[1]), name))
    return [name for _, name in sorted(out)]


def send_off(client: Client, name: str) -> str | None:
    """Tries each goal, plainly, then clearing the way, then with two more seeds; the goal
    reached, or None."""
    attempts = [(False, 0), (True, 0), (True, 1), (True, 2)]
    for goal in GOALS:
        placed = client.world().objects[name]
        if goal.startswith("table in ") and placed.state.workspace == goal.split()[-1]:
            print(f"  {name} stays where it is, in {placed.state.workspace}")
            return goal
        for clear, seed in attempts:
            try:
                run = client.execute(name, goal, clear=clear, seed=seed)
            except CellcError as e:
                print(f"  {name} -> {goal} (clear={clear}, seed={seed}): {e.code} {e}")
                # A goal the object cannot rest in is no use retrying.
                if e.code == "R0003":
                    break
                continue
            for move in run.moves:
                what = f" (out of the way of {move.clears})" if move.clears else ""
                strategy = move.plans[0].strategy if move.plans else "?"
                print(f"  {move.object}: {strategy}{what}, done={move.done}")
            return goal
    return None


def main(url: str) -> int:
    client = Client(url)
    world = client.world()
    order = on_the_table(world)
    print(f"on the table: {', '.join(order) or 'nothing'}")
    failed = []
    for name in order:
        print(f"{name}:")
        if send_off(client, name) is None:
            failed.append(name)
    world = client.world()
    print("world:")
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
