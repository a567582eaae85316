"""An opt-in log of what a run compiles, to find where a cold test run's time goes (tools/test_profile.py).

With $RESTIRCL_BUILD_LOG naming a file, one JSON line is appended per program build (clBuildProgram, or its fetch from
PoCL's disk cache) and per first launch of each kernel of a program in this process: PoCL compiles a kernel's
work-group function at that launch, not at the build (for the path and shading kernels most of a cold program's
seconds). The first launch then waits for the queue before and after it, to time it alone. Unset: nothing is
written and no launch waits.
"""

from __future__ import annotations

import hashlib
import json
import os
import time
from collections.abc import Callable

import pyopencl as cl

PATH = os.environ.get("RESTIRCL_BUILD_LOG") or None
_HASHES: dict[int, str] = {}  # id(program) -> its digest, for the lines of its kernels' launches
_LAUNCHED: set[tuple[int, str]] = set()


def _write(line: dict) -> None:
    line.update(t=round(time.time(), 2), pid=os.getpid())
    with open(PATH, "a") as f:  # type: ignore[arg-type]
        f.write(json.dumps(line) + "\n")


def log_build(program: cl.Program, options: list[str], text: str, seconds: float) -> None:
    """The program's digest (options and source), source size, seconds and -D options."""
    if PATH is None:
        return
    digest = hashlib.sha1(("\n".join(options) + "\n" + text).encode()).hexdigest()[:12]
    _HASHES[id(program)] = digest
    _write(
        {
            "hash": digest,
            "chars": len(text),
            "s": round(seconds, 3),
            "options": [o for o in options if o.startswith("-D")],
        }
    )


def launch(queue: cl.CommandQueue, program: cl.Program, name: str, enqueue: Callable[[], object]) -> None:
    """enqueue(), timed alone (and logged) where it is this process's first launch of kernel `name` of `program`."""
    key = (id(program), name)
    if PATH is None or key in _LAUNCHED:
        enqueue()
        return
    queue.finish()
    t0 = time.perf_counter()
    enqueue()
    queue.finish()
    _LAUNCHED.add(key)
    _write({"kernel": name, "hash": _HASHES.get(id(program), "?"), "s": round(time.perf_counter() - t0, 3)})
