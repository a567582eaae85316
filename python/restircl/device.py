"""OpenCL device choice and the one cached context.

The choice is deterministic: an explicit argument, else the RESTIRCL_DEVICE environment variable, else the first
GPU in platform/device order, else the first CPU, else the first device of any type. A spec is either
"P:D" (platform index, device index as listed by `restircl devices`) or a case-insensitive substring of
"platform name / device name".
"""

from __future__ import annotations

import os
from dataclasses import dataclass

import pyopencl as cl

ENV_VAR = "RESTIRCL_DEVICE"


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
        raise DeviceError(
            f"no OpenCL platform found ({exc}); install PoCL: pip install 'pyopencl[pocl]' "
            "or apt-get install pocl-opencl-icd"
        ) from exc
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
        raise DeviceError(
            "no OpenCL device found; install PoCL: pip install 'pyopencl[pocl]' or apt-get install pocl-opencl-icd"
        )
    return out


def choose_device(spec: str | None = None) -> tuple[DeviceInfo, cl.Device]:
    """Pick a device: `spec`, else $RESTIRCL_DEVICE, else the first GPU, else the first CPU."""
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
    for wanted in ("GPU", "CPU"):
        for info, dev in devices:
            if info.device_type == wanted:
                return info, dev
    return devices[0]


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
