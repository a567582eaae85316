"""Test set-up: a per-run kernel cache directory (fast and clean), the OpenCL device, small helpers."""

from __future__ import annotations

import os
import tempfile

_CACHE = tempfile.mkdtemp(prefix="restircl-test-cache-")
os.environ.setdefault("POCL_CACHE_DIR", os.path.join(_CACHE, "pocl"))
os.environ.setdefault("PYOPENCL_CACHE_DIR", os.path.join(_CACHE, "pyopencl"))

import pytest  # noqa: E402


@pytest.fixture(scope="session")
def device():
    from restircl.device import get_device

    return get_device()
