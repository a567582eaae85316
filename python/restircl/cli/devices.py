"""`restircl devices`: the OpenCL devices, why any of them cannot build the kernels, and the one chosen."""

from __future__ import annotations

import argparse

from ..core.device import build_problem, get_device, list_devices


def add_parser(sub: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
    v = sub.add_parser("devices", help="list OpenCL devices and the one chosen")
    v.add_argument("--device", default=None)
    v.set_defaults(func=run)


def run(a: argparse.Namespace) -> int:
    for info, dev in list_devices():
        problem = build_problem(dev)
        print(info.label if problem is None else f"{info.label}: {problem}")
    dev = get_device(a.device)
    print(f"chosen: {dev.label}")
    return 0
