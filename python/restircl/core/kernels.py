"""The kernels of a built program, launched with their arguments given by name.

Each kernel's parameter names are read once from its `__kernel` declaration in opencl/**/*.cl, so a launch that
misses, misspells or adds an argument fails with an error naming the kernel and the argument (KernelArgumentError)
instead of pyopencl's count or type error, and the order of a kernel's parameters is its source's business alone.
"""

from __future__ import annotations

import re
from collections.abc import Mapping
from functools import cache
from pathlib import Path

import pyopencl as cl

from . import build_log
from .device import Device
from .program import film_program, host_kernel_defines, opencl_dir, side_program
from .side_programs import SIDE_PROGRAMS

# work-items per work-group: 64 in 1D, 8x8 in 2D (docs/measurements/benchmarks.md: PoCL's own pick was slower)
LOCAL_ITEMS = 64

_KERNEL = re.compile(r"__kernel\s+void\s+(\w+)\s*\(([^)]*)\)")
_COMMENT = re.compile(r"/\*.*?\*/|//[^\n]*", re.S)


class KernelArgumentError(TypeError):
    """A launch's arguments do not match the kernel's declared parameters."""


def local_size(dims: int, max_items: int) -> tuple[int, ...]:
    """The local size of a launch: LOCAL_ITEMS work-items (8x8 in 2D), or the largest power of two within
    max_items, the kernel's limit on the device (CL_KERNEL_WORK_GROUP_SIZE: a GPU may allow fewer to a kernel that
    uses many registers or much private memory, as the BVH stacks do)."""
    n = LOCAL_ITEMS
    while n > 1 and n > max_items:
        n //= 2
    if dims == 1:
        return (n,)
    x = 1
    while x * x < n:
        x *= 2
    return (x, n // x)


def parse_kernel_parameters(source: str) -> dict[str, tuple[str, ...]]:
    """kernel name -> its parameter names, in order, from every `__kernel void name(...)` in `source`."""
    out: dict[str, tuple[str, ...]] = {}
    for name, params in _KERNEL.findall(_COMMENT.sub(" ", source)):
        out[name] = tuple(re.findall(r"(\w+)\s*$", p.strip())[0] for p in params.split(",") if p.strip())
    return out


@cache
def _declared_in(directory: Path) -> dict[str, tuple[str, ...]]:
    out: dict[str, tuple[str, ...]] = {}
    for path in sorted(directory.rglob("*.cl")):
        out.update(parse_kernel_parameters(path.read_text()))
    return out


def declared_parameters() -> dict[str, tuple[str, ...]]:
    """kernel name -> parameter names of every kernel in opencl/**/*.cl (read once per process)."""
    return _declared_in(opencl_dir())


class Kernels:
    """The kernels of one program on one device, with their work-group limits: by default every kernel declared in
    opencl/**/*.cl that this build has (a feature flag may leave a pass out), so a new stage's kernel needs no list
    of its own; the kernels of the device's film program (core/program.py film_program), which no flag changes and
    every renderer shares; and, given the feature `flags` of `program`, the side programs' kernels
    (core/side_programs.py), each built with the flags it reads at its first launch, so that a render that does not
    run it (a still runs no TAA) does not build it. k and program_of hold the kernels built so far; parameters and
    max_local name every kernel (max_local None until its kernel is built)."""

    def __init__(
        self,
        device: Device,
        program: cl.Program,
        names: tuple[str, ...] | None = None,
        flags: Mapping[str, int | float | bool | str] | None = None,
    ) -> None:
        self.device = device
        self.program = program
        # the main program's defines, taken now: a test's defines (eval/probe_defines.py) may be gone at a first launch
        self.defines = {**host_kernel_defines(), **flags} if flags is not None else {}
        declared = declared_parameters()
        film = film_program(device)
        self.program_of = {
            name: prog
            for prog in (program, film)
            for name in prog.get_info(cl.program_info.KERNEL_NAMES).split(";")
            if name in declared and (names is None or name in names)
        }
        self.side_of = {
            name: side
            for side in (SIDE_PROGRAMS if flags is not None else ())
            for name in side.kernels
            if names is None or name in names
        }
        self.parameters = {name: declared[name] for name in declared if name in self.program_of or name in self.side_of}
        self.k: dict[str, cl.Kernel] = {}
        self.max_local: dict[str, int | None] = dict.fromkeys(self.parameters)
        for name in self.program_of:
            self._make(name)

    def _make(self, name: str) -> cl.Kernel:
        """The kernel `name`, its program built first where it is a side program's."""
        if name not in self.program_of:
            self.program_of[name] = side_program(self.device, self.side_of[name], self.defines)
        kernel = self.k[name] = cl.Kernel(self.program_of[name], name)
        if self.max_local[name] is None:  # unless set already (a test of smaller work-groups sets every kernel's)
            self.max_local[name] = int(
                kernel.get_work_group_info(cl.kernel_work_group_info.WORK_GROUP_SIZE, self.device.device)
            )
        return kernel

    def kernel(self, name: str) -> cl.Kernel:
        """The kernel `name`, built at this first call where it is a side program's."""
        kernel = self.k.get(name)
        return kernel if kernel is not None else self._make(name)

    def check(self, name: str, args: dict) -> list:
        """The argument values of kernel `name` in declaration order; KernelArgumentError unless `args` names each
        of its parameters exactly once."""
        if name not in self.parameters:
            raise KernelArgumentError(f"no kernel named {name!r} (kernels: {', '.join(self.parameters)})")
        params = self.parameters[name]
        missing = [p for p in params if p not in args]
        unknown = [a for a in args if a not in params]
        if missing or unknown:
            parts = [
                f"missing {', '.join(missing)}" if missing else "",
                f"unknown {', '.join(unknown)}" if unknown else "",
            ]
            raise KernelArgumentError(
                f"kernel {name}: {'; '.join(p for p in parts if p)} argument(s) (it takes {', '.join(params)})"
            )
        return [args[p] for p in params]

    def launch(self, name: str, size: tuple[int, ...], **args) -> None:
        """Launch with a fixed local size (64 or 8x8, smaller only where the device allows the kernel fewer
        work-items: local_size), the global size padded to a multiple of it (OpenCL 1.2): every kernel returns
        early outside the image. PoCL's own choice was 25-40 % slower (docs/measurements/benchmarks.md)."""
        values = self.check(name, args)
        kernel = self.kernel(name)
        kernel.set_args(*values)
        local = local_size(len(size), int(self.max_local[name]))  # type: ignore[arg-type]
        padded = tuple(-(-n // m) * m for n, m in zip(size, local, strict=True))
        if build_log.PATH is None:
            cl.enqueue_nd_range_kernel(self.device.queue, kernel, padded, local)
        else:
            build_log.launch(
                self.device.queue,
                self.program_of[name],
                name,
                lambda: cl.enqueue_nd_range_kernel(self.device.queue, kernel, padded, local),
            )
