"""A client of `cellc serve`: the cell the service holds, its world, plans, execution in
the simulator, tasks and explanations, over HTTP with JSON (standard library only).

Every error the service reports is raised as `CellcError`, carrying the HTTP status and
the diagnostics (each with its code, documented in docs/diagnostics/CODE.md).
"""

from __future__ import annotations

import json
import urllib.error
import urllib.request
from typing import Any, Iterable

from .types import CellInfo, Diagnostic, Plan, Run, World, diagnostics_of


class CellcError(Exception):
    """The service refused a request: `status` is the HTTP status, `diagnostics` what it
    said, `code` the first diagnostic's code."""

    def __init__(self, status: int, diagnostics: tuple[Diagnostic, ...]):
        self.status = status
        self.diagnostics = diagnostics
        first = diagnostics[0] if diagnostics else None
        self.code = first.code if first else ""
        text = f"{first.code}: {first.message}" if first else f"HTTP {status}"
        if first and first.help:
            text += f" (help: {first.help})"
        super().__init__(text)


class Client:
    """`Client("http://127.0.0.1:7878")`; `timeout` is seconds per request."""

    def __init__(self, url: str, timeout: float = 60.0):
        self.url = url.rstrip("/")
        self.timeout = timeout

    # --- transport -------------------------------------------------------------------

    def _call(self, method: str, path: str, body: Any = None) -> Any:
        data = None if body is None else json.dumps(body).encode()
        request = urllib.request.Request(
            f"{self.url}/v1{path}",
            data=data,
            method=method,
            headers={"Content-Type": "application/json"} if data is not None else {},
        )
        try:
            with urllib.request.urlopen(request, timeout=self.timeout) as response:
                return json.loads(response.read() or b"null")
        except urllib.error.HTTPError as e:
            raw = e.read()
            try:
                document = json.loads(raw)
            except ValueError:
                document = None
            raise CellcError(e.code, diagnostics_of(document)) from None

    @staticmethod
    def _request(
        object: str,
        to: str,
        from_: str | None,
        seed: int | None,
        motions: bool,
        time_budget_ms: int | None,
        clear: bool,
    ) -> dict[str, Any]:
        body: dict[str, Any] = {"object": object, "to": to}
        if from_ is not None:
            body["from"] = from_
        options: dict[str, Any] = {"motions": motions, "clear": clear}
        if seed is not None:
            options["seed"] = seed
        if time_budget_ms is not None:
            options["time_budget_ms"] = time_budget_ms
        body["options"] = options
        return body

    # --- the service -----------------------------------------------------------------

    def health(self) -> dict[str, Any]:
        """What the service says of itself (its cell, its version)."""
        return self._call("GET", "/health")

    def cell(self) -> CellInfo:
        """The cell: objects with their grasps and resting poses, end-effectors (movable or
        not), workspaces with their boxes, arms with joint names and limits."""
        return CellInfo.parse(self._call("GET", "/cell"))

    def world(self) -> World:
        """The world the service keeps."""
        return World.parse(self._call("GET", "/world"))

    def set_world(self, world: World | dict[str, Any]) -> World:
        """Replaces the world: a `World` (as `world()` gave it) or a world document
        (docs/world.md). Returns the world as the service now has it."""
        document = world.document() if isinstance(world, World) else world
        answer = self._call("PUT", "/world", document)
        return World.parse(answer) if isinstance(answer, dict) and "objects" in answer else self.world()

    def plan(
        self,
        object: str,
        to: str,
        from_: str | None = None,
        *,
        seed: int | None = None,
        motions: bool = True,
        time_budget_ms: int | None = None,
        clear: bool = False,
    ) -> list[Plan]:
        """Plans moving `object` to `to` (a placement as the cell language writes it:
        `"bin in ws_right_bin"`, `"table at (0.4, -0.3, 1.0)"`) in the current world, from
        where the world has it (or `from_`). The plans in order: with `clear`, those that
        move what is in the way first, the request's last. Nothing is executed."""
        body = self._request(object, to, from_, seed, motions, time_budget_ms, clear)
        return _plans(self._call("POST", "/plan", body))

    def execute(
        self,
        object: str,
        to: str,
        from_: str | None = None,
        *,
        seed: int | None = None,
        motions: bool = True,
        time_budget_ms: int | None = None,
        clear: bool = False,
    ) -> Run:
        """Plans the move as `plan` does and executes it in the simulator; the service's
        world is updated (also when execution fails: then `CellcError` is raised and
        `world()` tells where things are)."""
        body = self._request(object, to, from_, seed, motions, time_budget_ms, clear)
        return Run.parse(self._call("POST", "/execute", body))

    def task(
        self,
        moves: Iterable[tuple[str, str]],
        *,
        seed: int | None = None,
        motions: bool = True,
        time_budget_ms: int | None = None,
        clear: bool = False,
    ) -> Run:
        """Moves `(object, to)` planned and executed one after the other in the world."""
        options: dict[str, Any] = {"motions": motions, "clear": clear}
        if seed is not None:
            options["seed"] = seed
        if time_budget_ms is not None:
            options["time_budget_ms"] = time_budget_ms
        body = {"moves": [{"object": o, "to": t} for o, t in moves], "options": options}
        return Run.parse(self._call("POST", "/tasks", body))

    def explain(self, object: str, to: str, from_: str | None = None) -> dict[str, Any]:
        """Why a move has no plan in the current world, as the structured explanation."""
        body = self._request(object, to, from_, None, False, None, False)
        return self._call("POST", "/explain", body)


def _plans(document: Any) -> list[Plan]:
    if isinstance(document, dict) and "plans" in document:
        return [Plan.parse(p) for p in document["plans"]]
    if isinstance(document, dict) and "steps" in document:
        return [Plan.parse(document)]
    if isinstance(document, list):
        return [Plan.parse(p) for p in document]
    raise CellcError(200, ())
