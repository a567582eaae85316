"""OpenCL device choice and the one cached context.

The choice is deterministic: an explicit argument, else the RESTIRCL_DEVICE environment variable, else the first
GPU in platform/device order, else the first CPU, else the first device of any type. A spec is either
"P:D" (platform index, device index as listed by `restircl devices`) or a case-insensitive substring of
"platform name / device name".

Without a spec, a device must also build a tiny kernel: the PoCL bundled in the pyopencl wheel (LLVM 14) fails every
build on CPUs newer than its LLVM ("unknown target CPU 'generic'", e.g. AMD Zen 5), while a system PoCL of the same
machine may work. Such a device is skipped with a warning naming it; an explicit spec is taken as it is.
"""

from __future__ import annotations

import os
import warnings
from dataclasses import dataclass

import pyopencl as cl

from .install_hint import install_hint

ENV_VAR = "RESTIRCL_DEVICE"

_PROBE_SOURCE = "__kernel void restircl_probe(__global float* a) { a[get_global_id(0)] = sqrt(a[get_global_id(0)]); }"
_NEWER_CPU_HINT = (
    "this OpenCL CPU driver's compiler does not know this CPU (the PoCL in the pyopencl wheel uses LLVM 14, older "
    "than e.g. AMD Zen 5); install a newer PoCL beside it: apt-get install pocl-opencl-icd (Debian/Ubuntu)"
)


class DeviceError(RuntimeError):
    """No OpenCL device could be found or the requested one does not exist."""


@dataclass(frozen=True)
class DeviceInfo:
    platform_index: int
    device_index: int
    platform_name: str
    device_name: str
    device_type: str

    @property
    def label(self) -> str:
        where = f"{self.platform_index}:{self.device_index}"
        return f"{where} {self.platform_name} / {self.device_name} ({self.device_type})"


def _type_name(device: cl.Device) -> str:
    t = device.type
    if t & cl.device_type.GPU:
        return "GPU"
    if t & cl.device_type.CPU:
        return "CPU"
    if t & cl.device_type.ACCELERATOR:
        return "ACCELERATOR"
    return "OTHER"


def list_devices() -> list[tuple[DeviceInfo, cl.Device]]:
    """Every OpenCL device of every platform, in platform/device order."""
    try:
        platforms = cl.get_platforms()
    except cl.Error as exc:  # no ICD loader or no platform at all
        raise DeviceError(f"no OpenCL platform found ({exc}); {install_hint()}") from exc
    out: list[tuple[DeviceInfo, cl.Device]] = []
    for pi, platform in enumerate(platforms):
        try:
            devices = platform.get_devices()
        except cl.Error:
            continue
        for di, dev in enumerate(devices):
            info = DeviceInfo(pi, di, platform.name.strip(), dev.name.strip(), _type_name(dev))
            out.append((info, dev))
    if not out:
        raise DeviceError(f"no OpenCL device found; {install_hint()}")
    return out


_PROBED: dict[int, str | None] = {}


def build_problem(device: cl.Device) -> str | None:
    """None if `device` builds and runs a tiny kernel, else why not, in one line (with a hint where one is known).
    Asked once per device and process."""
    key = device.int_ptr
    if key not in _PROBED:
        _PROBED[key] = _probe(device)
    return _PROBED[key]


def _probe(device: cl.Device) -> str | None:
    import numpy as np

    try:
        ctx = cl.Context([device])
        queue = cl.CommandQueue(ctx, device)
        prog = cl.Program(ctx, _PROBE_SOURCE).build()
        a = np.array([4.0, 9.0], np.float32)
        buf = cl.Buffer(ctx, cl.mem_flags.READ_WRITE | cl.mem_flags.COPY_HOST_PTR, hostbuf=a)
        prog.restircl_probe(queue, (2,), None, buf)
        cl.enqueue_copy(queue, a, buf)
        queue.finish()
    except (cl.Error, RuntimeError) as exc:
        text = str(exc)
        if "unknown target CPU" in text:
            return f"cannot build kernels: {_NEWER_CPU_HINT}"
        lines = [ln.strip() for ln in text.splitlines() if ln.strip()]
        return "cannot build kernels: " + (lines[-1] if lines else type(exc).__name__)
    if not np.allclose(a, [2.0, 3.0]):
        return f"a test kernel gave wrong results ({a.tolist()} for sqrt of [4, 9])"
    return None


def _first_that_builds(devices: list[tuple[DeviceInfo, cl.Device]]) -> tuple[DeviceInfo, cl.Device]:
    failed: list[str] = []
    for wanted in ("GPU", "CPU", None):
        for info, dev in devices:
            if wanted is not None and info.device_type != wanted:
                continue
            if wanted is None and info.device_type in ("GPU", "CPU"):
                continue
            problem = build_problem(dev)
            if problem is None:
                for line in failed:
                    warnings.warn(f"skipped OpenCL device {line}", RuntimeWarning, stacklevel=3)
                return info, dev
            failed.append(f"{info.label}: {problem}")
    listing = "\n  ".join(failed)
    raise DeviceError(f"no OpenCL device can build kernels; {install_hint()}:\n  {listing}")


def choose_device(spec: str | None = None) -> tuple[DeviceInfo, cl.Device]:
    """Pick a device: `spec`, else $RESTIRCL_DEVICE, else the first GPU, else the first CPU, that builds a kernel."""
    devices = list_devices()
    if spec is None:
        spec = os.environ.get(ENV_VAR) or None
    if spec is not None:
        spec = spec.strip()
        parts = spec.split(":")
        if len(parts) == 2 and all(p.strip().isdigit() for p in parts):
            pi, di = int(parts[0]), int(parts[1])
            for info, dev in devices:
                if info.platform_index == pi and info.device_index == di:
                    return info, dev
        else:
            needle = spec.lower()
            for info, dev in devices:
                if needle in f"{info.platform_name} / {info.device_name}".lower() or needle == info.device_type.lower():
                    return info, dev
        listing = "\n  ".join(info.label for info, _ in devices)
        raise DeviceError(f"no OpenCL device matches {spec!r}; available:\n  {listing}")
    return _first_that_builds(devices)


class Device:
    """An OpenCL context and in-order queue, either made here or handed in by a pyopencl script."""

    def __init__(
        self,
        spec: str | None = None,
        *,
        context: cl.Context | None = None,
        queue: cl.CommandQueue | None = None,
    ) -> None:
        if queue is not None:
            context = queue.context
        if context is not None:
            dev = context.devices[0]
            self.info = DeviceInfo(-1, -1, dev.platform.name.strip(), dev.name.strip(), _type_name(dev))
            self.device = dev
            self.context = context
            self.queue = queue if queue is not None else cl.CommandQueue(context, dev)
        else:
            self.info, self.device = choose_device(spec)
            self.context = cl.Context([self.device])
            self.queue = cl.CommandQueue(self.context, self.device)

    @property
    def label(self) -> str:
        return f"{self.info.platform_name} / {self.info.device_name} ({self.info.device_type})"


_CACHED: dict[str | None, Device] = {}


def get_device(spec: str | None = None) -> Device:
    """The cached Device for `spec` (None: the default choice, which honours $RESTIRCL_DEVICE)."""
    key = spec if spec is not None else os.environ.get(ENV_VAR) or None
    dev = _CACHED.get(key)
    if dev is None:
        dev = Device(key)
        _CACHED[key] = dev
    return dev
