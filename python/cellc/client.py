"""A client of `cellc serve`: the cell the service holds, its world, plans, execution in
the simulator, tasks and explanations, over HTTP with JSON (standard library only).

The service keeps its world in a store with a revision, one more for every write. Writes
may carry a precondition (`if_match=` the world's ETag, or `revision=`) and are refused
with `PreconditionFailed` when the world moved on; executions may carry an idempotency
key, so that sending one again (after a timeout, say) returns its first answer instead
of moving anything twice. After a crash during an execution the world is uncertain for
what it was moving: planning raises `WorldUncertain` until a client confirms where those
objects and arms are (`put_world`, or `patch_world` naming them).

Every other error the service reports is raised as `CellcError`, carrying the HTTP
status and the diagnostics (each with its code, documented in docs/diagnostics/CODE.md).
Transport failures (a timeout, a refused connection) are raised as the standard
library raises them (`TimeoutError`, `urllib.error.URLError`, `ConnectionError`).
"""

from __future__ import annotations

import http.client
import json
import re
import time
import urllib.error
import urllib.parse
import urllib.request
import uuid
from typing import Any, Iterable, Mapping

from .types import (
    CellInfo,
    ControllerGoals,
    Diagnostic,
    Execution,
    ExecutionSummary,
    Health,
    Interrupted,
    Plan,
    Run,
    World,
    diagnostics_of,
)


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


class PreconditionFailed(CellcError):
    """S0006 (412): the world is no longer at the revision the request was made against
    (`if_match` / `revision`), or it names another store's world. Nothing was written:
    read the world again and decide whether the request still holds."""


class WorldUncertain(CellcError):
    """S0007 (409): an execution was interrupted by a stop of the service, and planning
    from the world is refused until a client confirms where its objects and arms are.
    `objects` and `arms` name them; `interrupted` lists the executions (id, steps done,
    what each was moving), as the diagnostic says them."""

    def __init__(self, status: int, diagnostics: tuple[Diagnostic, ...]):
        super().__init__(status, diagnostics)
        first = diagnostics[0] if diagnostics else None
        objects, arms = _named(first.message) if first else ((), ())
        self.objects: tuple[str, ...] = objects
        self.arms: tuple[str, ...] = arms
        interrupted = []
        for note in first.notes if first else ():
            found = _INTERRUPTED.match(note)
            if found:
                moving_objects, moving_arms = _named(found["moving"])
                interrupted.append(
                    Interrupted(
                        int(found["execution"]), int(found["steps"]), moving_objects, moving_arms
                    )
                )
        self.interrupted: tuple[Interrupted, ...] = tuple(interrupted)


# The diagnostic's words (src/state.rs in the cellc repository: `names`, `uncertain_of`).
_NAME = re.compile(r"\b(object|arm) `((?:[^`\\]|\\.)*)`")
_INTERRUPTED = re.compile(
    r"execution (?P<execution>\d+) was interrupted after step (?P<steps>\d+); it was moving (?P<moving>.*)"
)


def _named(text: str) -> tuple[tuple[str, ...], tuple[str, ...]]:
    objects = [m[2] for m in _NAME.finditer(text) if m[1] == "object"]
    arms = [m[2] for m in _NAME.finditer(text) if m[1] == "arm"]
    return tuple(dict.fromkeys(objects)), tuple(dict.fromkeys(arms))


_ERRORS: dict[str, type[CellcError]] = {"S0006": PreconditionFailed, "S0007": WorldUncertain}

# What a retry under the same idempotency key may follow: the request may or may not
# have reached the service (`http.client.HTTPException` covers a connection closed
# before the answer came).
_TRANSPORT = (TimeoutError, ConnectionError, urllib.error.URLError, http.client.HTTPException)


def _error(status: int, document: Any) -> CellcError:
    diagnostics = diagnostics_of(document)
    code = diagnostics[0].code if diagnostics else ""
    return _ERRORS.get(code, CellcError)(status, diagnostics)


class _Answer:
    """A 2xx answer: its JSON document and its headers."""

    def __init__(self, document: Any, headers: Mapping[str, str]):
        self.document = document
        self.headers = headers

    @property
    def etag(self) -> str | None:
        return self.headers.get("ETag")

    @property
    def replayed(self) -> bool:
        return (self.headers.get("idempotent-replayed") or "").lower() == "true"


IfMatch = str | World | None
"""An `If-Match`: the ETag as `world()` gave it (`world.etag`), a `World` (its etag), or
`"*"` (any world the service has)."""

Key = str | bool | None
"""An `Idempotency-Key`: a string the caller keeps (to retry with), True for a fresh UUID,
None for none."""


class Client:
    """`Client("http://127.0.0.1:7878")`; `timeout` is seconds per request."""

    def __init__(self, url: str, timeout: float = 60.0):
        self.url = url.rstrip("/")
        self.timeout = timeout
        # The store the service keeps its world in, as last seen: `revision=` of
        # `put_world` and `patch_world` is a tag of this store.
        self._instance: str | None = None

    # --- transport -------------------------------------------------------------------

    def _send(
        self,
        method: str,
        path: str,
        body: Any = None,
        headers: Mapping[str, str] | None = None,
        content_type: str = "application/json",
    ) -> _Answer:
        data = None if body is None else json.dumps(body).encode()
        sent = dict(headers or {})
        if data is not None:
            sent["Content-Type"] = content_type
        request = urllib.request.Request(
            f"{self.url}/v1{path}", data=data, method=method, headers=sent
        )
        try:
            with urllib.request.urlopen(request, timeout=self.timeout) as response:
                return _Answer(json.loads(response.read() or b"null"), response.headers)
        except urllib.error.HTTPError as e:
            raw = e.read()
            try:
                document = json.loads(raw)
            except ValueError:
                document = None
            raise _error(e.code, document) from None

    def _call(self, method: str, path: str, body: Any = None) -> Any:
        """The JSON document of a request's answer."""
        return self._send(method, path, body).document

    def _retried(self, retries: int, send: Any) -> _Answer:
        """`send()`, sent again up to `retries` times when the transport fails (a timeout,
        a connection refused or closed), waiting 0.5 s, 1 s, 2 s... (at most 5 s) in between.
        A repeat that arrives while the first request still runs waits for it. Only for
        requests with an idempotency key: whether the first one ran is unknown, and the
        key makes the service answer a repeat with the first answer."""
        for attempt in range(retries + 1):
            try:
                return send()
            except _TRANSPORT:
                if attempt == retries:
                    raise
                time.sleep(min(0.5 * 2**attempt, 5.0))
        raise AssertionError("unreachable")

    def _seen(self, world: World | None) -> World | None:
        if world is not None and world.instance:
            self._instance = world.instance
        return world

    def _tag(self, if_match: IfMatch, revision: int | None) -> dict[str, str]:
        """The `If-Match` of a world write given either an ETag / world, or a revision of
        the store this client last saw (asked of `/health` when it saw none yet)."""
        if if_match is not None and revision is not None:
            raise ValueError("give `if_match` or `revision`, not both")
        if if_match is not None:
            return {"If-Match": _etag_of(if_match)}
        if revision is not None:
            if self._instance is None:
                self._instance = self.health().instance
            return {"If-Match": f'"{self._instance}-{int(revision)}"'}
        return {}

    @staticmethod
    def _request(object: str, to: str, from_: str | None, options: dict[str, Any]) -> dict[str, Any]:
        body: dict[str, Any] = {"object": object, "to": to}
        if from_ is not None:
            body["from"] = from_
        body["options"] = options
        return body

    def _run(
        self,
        path: str,
        body: dict[str, Any],
        revision: int | None,
        if_match: IfMatch,
        idempotency_key: Key,
        retries: int,
    ) -> Run:
        if revision is not None:
            body["revision"] = int(revision)
        headers: dict[str, str] = {}
        if if_match is not None:
            headers["If-Match"] = _etag_of(if_match)
        key = str(uuid.uuid4()) if idempotency_key is True else idempotency_key or None
        if key is not None:
            headers["Idempotency-Key"] = key
        elif retries:
            raise ValueError("retries need an idempotency key: without one a retry may move twice")
        answer = self._retried(retries, lambda: self._send("POST", path, body, headers))
        run = Run.parse(answer.document, answer.etag, answer.replayed)
        self._seen(run.world)
        return run

    # --- the service -----------------------------------------------------------------

    def health(self) -> Health:
        """What the service says of itself: its cell and version, the store and revision
        of its world, its durability and any interrupted execution."""
        health = Health.parse(self._call("GET", "/health"))
        self._instance = health.instance or self._instance
        return health

    def cell(self) -> CellInfo:
        """The cell: objects with their grasps and resting poses, end-effectors (movable or
        not), workspaces with their boxes, arms with joint names and limits."""
        return CellInfo.parse(self._call("GET", "/cell"))

    def world(self) -> World:
        """The world the service keeps, with its instance, revision, uncertainty and ETag."""
        answer = self._send("GET", "/world")
        return self._seen(World.parse(answer.document, answer.etag))

    def put_world(
        self,
        world: World | dict[str, Any],
        *,
        if_match: IfMatch = None,
        revision: int | None = None,
    ) -> World:
        """Replaces the world: a `World` (as `world()` gave it) or a world document
        (docs/world.md). With `if_match` (an ETag or a world read before) or `revision`,
        only if the world is still at that revision (`PreconditionFailed` otherwise). It
        confirms everything an interruption left uncertain. Returns the world as the
        service now has it, with its new revision."""
        document = world.document() if isinstance(world, World) else world
        answer = self._send("PUT", "/world", document, self._tag(if_match, revision))
        return self._seen(World.parse(answer.document, answer.etag))

    def set_world(self, world: World | dict[str, Any]) -> World:
        """`put_world` without a precondition (kept for earlier callers)."""
        return self.put_world(world)

    def patch_world(
        self,
        merge_patch: dict[str, Any] | None = None,
        *,
        operations: list[dict[str, Any]] | None = None,
        if_match: IfMatch = None,
        revision: int | None = None,
    ) -> World:
        """Changes part of the world document (docs/world.md): a JSON Merge Patch
        (`{"objects": {"ball": {"holder": "table", "at": [0.5, 0.3, 1.0]}}}`, RFC 7396) or
        JSON Patch `operations` (`[{"op": "replace", "path": "/objects/ball", "value":
        ...}]`, RFC 6902), checked like a whole world. It confirms the objects and arms it
        names. Preconditions as for `put_world`."""
        if (merge_patch is None) == (operations is None):
            raise ValueError("give either `merge_patch` or `operations`")
        if merge_patch is not None:
            body: Any = merge_patch
            kind = "application/merge-patch+json"
        else:
            body, kind = list(operations or ()), "application/json-patch+json"
        answer = self._send("PATCH", "/world", body, self._tag(if_match, revision), kind)
        return self._seen(World.parse(answer.document, answer.etag))

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
        velocity_scaling: float | None = None,
        acceleration_scaling: float | None = None,
        rate: float | None = None,
    ) -> list[Plan]:
        """Plans moving `object` to `to` (a placement as the cell language writes it:
        `"bin in ws_right_bin"`, `"table at (0.4, -0.3, 1.0)"`) in the current world, from
        where the world has it (or `from_`). The plans in order: with `clear`, those that
        move what is in the way first, the request's last. Nothing is executed.

        `velocity_scaling` and `acceleration_scaling` (in (0, 1], default 1) are the share
        of every joint's limits the motions use; `rate` (Hz, at most 1000) gives points
        every 1/rate seconds instead of at the time parameterisation's knots. A value out
        of range raises `CellcError` R0012 (400)."""
        options = _options(
            seed, motions, time_budget_ms, clear, velocity_scaling, acceleration_scaling, rate
        )
        return _plans(self._call("POST", "/plan", self._request(object, to, from_, options)))

    def follow_joint_trajectory(
        self,
        object: str,
        to: str,
        from_: str | None = None,
        *,
        seed: int | None = None,
        time_budget_ms: int | None = None,
        clear: bool = False,
        velocity_scaling: float | None = None,
        acceleration_scaling: float | None = None,
        rate: float | None = None,
    ) -> ControllerGoals:
        """Plans the move as `plan` does and returns its motions as
        `control_msgs/action/FollowJointTrajectory` goals: per plan, one goal per arm per
        step that moves, labelled with the step's index and the arm (`goal.message()` is
        the dict of the ROS message). Nothing is executed."""
        options = _options(
            seed, True, time_budget_ms, clear, velocity_scaling, acceleration_scaling, rate
        )
        body = self._request(object, to, from_, options)
        return ControllerGoals.parse(self._call("POST", "/plan/follow_joint_trajectory", body))

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
        velocity_scaling: float | None = None,
        acceleration_scaling: float | None = None,
        rate: float | None = None,
        revision: int | None = None,
        if_match: IfMatch = None,
        idempotency_key: Key = None,
        retries: int = 0,
    ) -> Run:
        """Plans the move as `plan` does (with the same timing options) and executes it in the simulator; the service's
        world is updated (also when execution fails: then `CellcError` is raised and
        `world()` tells where things are).

        `revision` / `if_match`: only if the world is still at that revision
        (`PreconditionFailed` otherwise, nothing moved). `idempotency_key`: a key (True
        makes a UUID) under which a repeat of this request answers the first outcome
        (`run.replayed`) instead of moving again; the same key with another request
        raises S0008. `retries`: with a key, how many times to send the request again when
        the transport fails (a timeout, say) - each repeat returns the first outcome if
        the first one did run."""
        options = _options(
            seed, motions, time_budget_ms, clear, velocity_scaling, acceleration_scaling, rate
        )
        body = self._request(object, to, from_, options)
        return self._run("/execute", body, revision, if_match, idempotency_key, retries)

    def task(
        self,
        moves: Iterable[tuple[str, str]],
        *,
        seed: int | None = None,
        motions: bool = True,
        time_budget_ms: int | None = None,
        clear: bool = False,
        velocity_scaling: float | None = None,
        acceleration_scaling: float | None = None,
        rate: float | None = None,
        revision: int | None = None,
        if_match: IfMatch = None,
        idempotency_key: Key = None,
        retries: int = 0,
    ) -> Run:
        """Moves `(object, to)` planned and executed one after the other in the world;
        timing options as for `plan`, preconditions, key and retries as for `execute`."""
        body = {
            "moves": [{"object": o, "to": t} for o, t in moves],
            "options": _options(
                seed, motions, time_budget_ms, clear, velocity_scaling, acceleration_scaling, rate
            ),
        }
        return self._run("/tasks", body, revision, if_match, idempotency_key, retries)

    def explain(self, object: str, to: str, from_: str | None = None) -> dict[str, Any]:
        """Why a move has no plan in the current world, as the structured explanation."""
        body = self._request(object, to, from_, _options(None, False, None, False))
        return self._call("POST", "/explain", body)

    def executions(self, limit: int | None = None) -> list[ExecutionSummary]:
        """The journal's newest executions first (`limit`: 1 to 200, the service's default
        50): what a client whose request timed out reads to learn whether it ran."""
        query = "" if limit is None else "?" + urllib.parse.urlencode({"limit": limit})
        document = self._call("GET", f"/executions{query}")
        return [ExecutionSummary.parse(e) for e in document.get("executions") or ()]

    def execution(self, id: int) -> Execution:
        """One execution of the journal with its steps and outcome (S0013 when the journal
        has no such id)."""
        return Execution.parse(self._call("GET", f"/executions/{int(id)}"))


def _etag_of(if_match: str | World) -> str:
    if isinstance(if_match, World):
        if if_match.etag is None:
            raise ValueError("this world carries no ETag (it was not read from the service)")
        return if_match.etag
    return if_match


def _options(
    seed: int | None,
    motions: bool,
    time_budget_ms: int | None,
    clear: bool,
    velocity_scaling: float | None = None,
    acceleration_scaling: float | None = None,
    rate: float | None = None,
) -> dict[str, Any]:
    """The request's `options`: only what was given, so the service's defaults apply to
    the rest (and the service, not the client, says what is out of range)."""
    options: dict[str, Any] = {"motions": motions, "clear": clear}
    given = {
        "seed": seed,
        "time_budget_ms": time_budget_ms,
        "velocity_scaling": velocity_scaling,
        "acceleration_scaling": acceleration_scaling,
        "rate": rate,
    }
    options.update({name: value for name, value in given.items() if value is not None})
    return options


def _plans(document: Any) -> list[Plan]:
    if isinstance(document, dict) and "plans" in document:
        return [Plan.parse(p) for p in document["plans"]]
    if isinstance(document, dict) and "steps" in document:
        return [Plan.parse(document)]
    if isinstance(document, list):
        return [Plan.parse(p) for p in document]
    raise CellcError(200, ())
