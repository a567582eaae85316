"""Test set-up: the kernel cache directory kept between runs, the OpenCL device, the session's cache of exhaustive
reference renders, small helpers."""

from __future__ import annotations

import os
import shutil
import sys
import tempfile
import time
from pathlib import Path

CACHE_ENV = "RESTIRCL_TEST_KERNEL_CACHE"
CACHE_KEEP_DAYS = 14


def _prune(cache: Path, days: float) -> None:
    """Remove the PoCL cache entries (cache/XX/HASH/, each with a last_accessed file PoCL touches on every use) not
    used for `days`: every edit of a kernel source leaves the old programs' entries behind."""
    cutoff = time.time() - days * 86400
    for entry in cache.glob("*/*"):
        stamp = entry / "last_accessed"
        try:
            if entry.is_dir() and stamp.is_file() and stamp.stat().st_mtime < cutoff:
                shutil.rmtree(entry, ignore_errors=True)
        except OSError:  # another run removed it first
            pass


def _kernel_cache() -> str:
    """Most of a cold run's time is PoCL compiling the kernels' variants (some 270 programs, each built once and
    shared by the xdist workers through this folder); their binaries are kept between runs. PoCL keys an entry by the
    whole source (headers inlined, core/source_inline.py), the build options and the device and PoCL build, so an
    edited kernel or another driver gets a new entry, never a stale binary. $RESTIRCL_TEST_KERNEL_CACHE names the
    folder; "fresh" gives every run an empty one (a CI machine's first run: every variant compiled)."""
    wanted = os.environ.get(CACHE_ENV, "")
    if wanted == "fresh":
        return tempfile.mkdtemp(prefix="restircl-test-cache-")
    base = Path(os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache")
    folder = Path(wanted) if wanted else base / "restircl" / "test-kernels"
    folder.mkdir(parents=True, exist_ok=True)
    _prune(folder / "pocl", CACHE_KEEP_DAYS)
    return str(folder)


_FRESH_CACHE: str | None = None  # the empty folder this process made for a "fresh" run, removed at its end
if "POCL_CACHE_DIR" not in os.environ:  # set by the user, or by the process that started this xdist worker
    _CACHE = _kernel_cache()
    if os.environ.get(CACHE_ENV, "") == "fresh":
        _FRESH_CACHE = _CACHE
    os.environ.setdefault("POCL_CACHE_DIR", os.path.join(_CACHE, "pocl"))
    os.environ.setdefault("PYOPENCL_CACHE_DIR", os.path.join(_CACHE, "pyopencl"))

import numpy as np  # noqa: E402
import pytest  # noqa: E402


@pytest.fixture(scope="session")
def device():
    from restircl import get_device

    return get_device()


@pytest.fixture(scope="session")
def reference_samples(device, tmp_path_factory):
    """reference_samples(scene, settings, frames): the per-frame samples of helpers.collect, computed once per
    pytest session. Several test files compare against the same exhaustive render of the same test scene (at
    8192 frames a few seconds each on 2 cores); the key is everything the render depends on: the scene file's
    digest, the settings, the frame count and the device. The arrays are shared: read-only."""
    from restircl.eval.report.reference import scene_digest

    from .helpers import collect

    digest_dir = tmp_path_factory.mktemp("reference_digests")
    cache: dict[tuple[str, str, int, str], np.ndarray] = {}

    def get(scene, settings, frames: int) -> np.ndarray:
        key = (scene_digest(scene, digest_dir), repr(settings), int(frames), device.label)
        if key not in cache:
            samples = collect(scene, settings, frames, device)
            samples.flags.writeable = False
            cache[key] = samples
        return cache[key]

    return get


@pytest.hookimpl(hookwrapper=True)
def pytest_runtest_protocol(item, nextitem):
    """With $RESTIRCL_BUILD_LOG set (core/program.py logs each program build there), also one line per test: its
    worker, start and end, and the CPU seconds of this process (PoCL's threads included) and of its finished
    children, so that tools/test_profile.py can tell a test's kernel builds from its renders."""
    path = os.environ.get("RESTIRCL_BUILD_LOG")
    if not path:
        yield
        return
    import json
    import resource

    t0, cpu0 = time.time(), time.process_time()
    kids0 = resource.getrusage(resource.RUSAGE_CHILDREN)
    yield
    kids1 = resource.getrusage(resource.RUSAGE_CHILDREN)
    line = {
        "test": item.nodeid,
        "pid": os.getpid(),
        "t0": round(t0, 2),
        "t1": round(time.time(), 2),
        "cpu": round(time.process_time() - cpu0, 2),
        "children_cpu": round(kids1.ru_utime + kids1.ru_stime - kids0.ru_utime - kids0.ru_stime, 2),
    }
    with open(path, "a") as f:
        f.write(json.dumps(line) + "\n")


_EXIT: dict[str, int] = {}


def pytest_sessionfinish(session, exitstatus):
    """Keep the exit status for pytest_unconfigure; a "fresh" run's kernel cache (a few hundred MiB in the temporary
    folder) goes with the process that made it (the xdist workers inherit its path and make none of their own)."""
    _EXIT["status"] = int(exitstatus)
    if _FRESH_CACHE is not None:
        shutil.rmtree(_FRESH_CACHE, ignore_errors=True)


@pytest.hookimpl(trylast=True)
def pytest_unconfigure(config):
    """bpy 4.2 as a Python module (not Blender itself) segfaults in its exit handler while a RenderEngine subclass
    with a method is still registered, unregistered or not (a six-line script shows it; bpy 5.0.1 and 5.3.0 do
    not): once pytest has reported, end the process before that handler runs, with pytest's own exit status."""
    bpy = sys.modules.get("bpy")
    if bpy is None or tuple(bpy.app.version) >= (5, 0, 0) or "status" not in _EXIT:
        return
    sys.stdout.flush()
    sys.stderr.flush()
    os._exit(_EXIT["status"])
