"""Test set-up: a per-run kernel cache directory (fast and clean), the OpenCL device, small helpers."""

from __future__ import annotations

import os
import sys
import tempfile

_CACHE = tempfile.mkdtemp(prefix="restircl-test-cache-")
os.environ.setdefault("POCL_CACHE_DIR", os.path.join(_CACHE, "pocl"))
os.environ.setdefault("PYOPENCL_CACHE_DIR", os.path.join(_CACHE, "pyopencl"))

import pytest  # noqa: E402


@pytest.fixture(scope="session")
def device():
    from restircl.device import get_device

    return get_device()


_EXIT: dict[str, int] = {}


def pytest_sessionfinish(session, exitstatus):
    _EXIT["status"] = int(exitstatus)


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
