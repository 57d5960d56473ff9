"""Starting the real service for the tests: `cellc serve cells/vito.cell` on a free port,
the binary from `CELLC_BIN` or the workspace's `target/debug/cellc`."""

from __future__ import annotations

import os
import pathlib
import subprocess
import sys

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "python"))


def binary() -> str:
    path = os.environ.get("CELLC_BIN") or str(ROOT / "target" / "debug" / "cellc")
    if not pathlib.Path(path).exists():
        pytest.fail(f"no cellc binary at {path}: run `cargo build` first or set CELLC_BIN")
    return path


class Server:
    """A running `cellc serve cells/vito.cell ARGS...`, its URL once it listens."""

    def __init__(self, *args: str):
        self.process = subprocess.Popen(
            [binary(), "serve", "cells/vito.cell", "--addr", "127.0.0.1:0", *args],
            cwd=ROOT,
            stdout=subprocess.PIPE,
            stderr=subprocess.DEVNULL,
            text=True,
        )
        # Before it listens the service may print events (a recovery); the URL is last.
        self.events: list[str] = []
        for line in self.process.stdout:
            if line.startswith("listening on "):
                self.url = line.split()[-1]
                return
            self.events.append(line)
        raise AssertionError(f"the service stopped before listening: {self.events}")

    def kill(self) -> None:
        """SIGKILL: no chance to finish anything."""
        self.process.kill()
        self.process.wait(timeout=30)

    def stop(self) -> None:
        if self.process.poll() is None:
            self.process.terminate()
            assert self.process.wait(timeout=30) == 0


@pytest.fixture()
def client():
    """A client of a fresh in-memory service, stopped after the test."""
    from cellc import Client

    server = Server("--ephemeral")
    try:
        yield Client(server.url, timeout=120)
    finally:
        server.stop()
