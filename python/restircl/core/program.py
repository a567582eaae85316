"""Building the OpenCL program from opencl/ with -D feature flags, and caching it.

Compiled binaries are cached twice: in this process (one Program per context and flag set) and on disk by
pyopencl/PoCL (PYOPENCL_CACHE_DIR, POCL_CACHE_DIR). Fast/finite math flags are never used: they delete the
isnan/isinf guards the kernels rely on.
"""

from __future__ import annotations

import re
import time
import warnings
from collections.abc import Mapping
from importlib import resources
from pathlib import Path

import pyopencl as cl

from ..bvh import packets as bvh_packets
from ..settings.table import kernel_defines
from . import build_log
from .device import Device
from .side_programs import SideProgram
from .source_inline import inline_includes

MAIN_SOURCE = "restircl.cl"
# The kernels whose code reads no feature flag (a still's sums): one program per device, shared by every renderer,
# instead of a compile of each in every feature variant of MAIN_SOURCE (docs/measurements/benchmarks.md)
FILM_SOURCE = "film/film.cl"
# Denormals flushed to zero: on x86 CPUs a float op on a denormal operand takes a microcode assist, and our records
# keep integers in the w lanes of float4s (light type and flags, primitive ids), which the float3 arithmetic of
# their xyz carries along in the vector registers as denormals. Measured with PoCL 3.0 on this 2-core VM,
# many_lights 640x360, ReSTIR unbiased: 264 -> 187 ms per frame. No quantity we compute is near 1e-38 (the stress
# suite's smallest powers and areas are 1e-6 and 1e-8); GPUs flush at full speed too.
BASE_OPTIONS = ("-cl-std=CL1.2", "-cl-denorms-are-zero")
FORBIDDEN_OPTIONS = ("-cl-fast-relaxed-math", "-cl-finite-math-only", "-cl-unsafe-math-optimizations")


class KernelBuildError(RuntimeError):
    """The OpenCL compiler rejected the program. The message holds the log and the first file:line."""

    def __init__(self, message: str, log: str, location: str | None) -> None:
        super().__init__(message)
        self.log = log
        self.location = location


def opencl_dir() -> Path:
    """Directory holding the OpenCL sources: restircl/opencl when installed, ../../opencl in a source tree."""
    here = Path(__file__).resolve().parents[1]  # the restircl package
    for path in (here / "opencl", here.parents[1] / "opencl"):
        if (path / MAIN_SOURCE).is_file():
            return path
    try:  # an editable install maps the package elsewhere
        path = Path(str(resources.files("restircl.opencl")))
        if (path / MAIN_SOURCE).is_file():
            return path
    except (ModuleNotFoundError, TypeError):
        pass
    raise FileNotFoundError(f"OpenCL sources ({MAIN_SOURCE}) not found next to {here}")


def format_options(flags: Mapping[str, int | float | bool | str]) -> list[str]:
    """-D options for a flag dict; False/None flags are left out, True becomes 1."""
    opts: list[str] = []
    for name in sorted(flags):
        value = flags[name]
        if value is None or value is False:
            continue
        if value is True:
            value = 1
        opts.append(f"-D{name}={value}")
    return opts


_LOCATION = re.compile(r"([\w./\\-]+\.(?:cl|h)):(\d+):(\d+)")

_PROGRAMS: dict[tuple[int, tuple[str, ...], str], cl.Program] = {}


def build_program(
    device: Device,
    flags: Mapping[str, int | float | bool | str] | None = None,
    source: str | None = None,
    extra_options: tuple[str, ...] = (),
    main: str = MAIN_SOURCE,
    host_defines: bool = True,
) -> cl.Program:
    """Build (or fetch from the cache) the program for `flags`. `main` is the file under opencl/ to build; `source`
    replaces its text. host_defines: with the array limits of the settings table and the BVH layout (False for a
    program that reads neither, so that its build does not depend on them)."""
    src_dir = opencl_dir()
    text = source if source is not None else (src_dir / main).read_text()
    # the array limits the kernels share with validate() come from the settings table; no -I: the headers are
    # written into the source (source_inline.py), as drivers split options at the spaces of an install path
    host = format_options(host_kernel_defines()) if host_defines else []
    options = [
        *BASE_OPTIONS,
        *host,
        *format_options(flags or {}),
        *extra_options,
    ]
    for opt in options:
        if opt in FORBIDDEN_OPTIONS:
            raise ValueError(f"{opt} deletes the NaN/Inf guards and is not allowed")
    key = (id(device.context), tuple(options), text)
    prog = _PROGRAMS.get(key)
    if prog is not None:
        return prog
    name = main if source is None else "program.cl"
    start = time.perf_counter()
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", cl.CompilerWarning)
            prog = cl.Program(device.context, inline_includes(text, name, src_dir)).build(options=options)
    except cl.RuntimeError as exc:
        log = str(exc)
        m = _LOCATION.search(log)
        location = f"{m.group(1)}:{m.group(2)}" if m else None
        where = f" at {location}" if location else ""
        raise KernelBuildError(
            f"OpenCL build failed{where} on {device.label} with options {' '.join(options)}:\n{log}", log, location
        ) from exc
    build_log.log_build(prog, options, text, time.perf_counter() - start)
    _PROGRAMS[key] = prog
    return prog


def host_kernel_defines() -> dict[str, int | float | bool | str]:
    """The defines every renderer build takes besides the feature flags: the array limits the kernels share with
    validate() (the settings table, with a test's or probe's additions: eval/probe_defines.py) and the BVH layout."""
    return {**kernel_defines(), **bvh_packets.defines()}


def side_program(device: Device, side: SideProgram, defines: Mapping[str, int | float | bool | str]) -> cl.Program:
    """The side program `side` (core/side_programs.py) of a main program built with `defines` (its feature flags and
    host_kernel_defines() then): built with those it reads, so that every variant alike in those shares one build."""
    return build_program(device, side.defines(defines), main=side.source, host_defines=False)


def film_program(device: Device) -> cl.Program:
    """The film program (FILM_SOURCE) of `device`: built once per context, as its text takes no flags."""
    return build_program(device, main=FILM_SOURCE, host_defines=False)
