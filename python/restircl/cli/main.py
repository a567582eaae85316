"""The `restircl` command line: demo, render, devices, bench, report, compare, save-scene, stress (and
`python -m restircl`).

Each sub-command is a module of this package with its parser (`add_parser`) and its body (`run`); the commands
that run the evaluation tools (restircl.eval) import them inside `run`, so that starting the command line loads
none of them."""

from __future__ import annotations

import argparse
import sys

from ..core.device import DeviceError
from ..core.program import KernelBuildError
from ..scene.errors import SceneError
from ..settings.spec import SettingError, flag_of
from ..settings.table import Settings
from . import bench, compare, demo, devices, render, report, save_scene, stress
from .arguments import settings_from_args

#: the sub-commands in the order of `restircl --help`
COMMANDS = (demo, render, devices, bench, report, compare, save_scene, stress)


def build_parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(prog="restircl", description=__doc__.split("\n\n")[0])
    sub = p.add_subparsers(dest="command", required=True)
    for command in COMMANDS:
        command.add_parser(sub)
    return p


def main(argv: list[str] | None = None) -> int:
    args = build_parser().parse_args(argv)
    sub = getattr(args, "settings_parser", None)
    if sub is not None:  # a setting out of range together with another one: an argparse error too
        try:
            args.settings = settings_from_args(args)
        except SettingError as exc:
            sub.error(f"argument {'/'.join(flag_of(Settings, n) for n in exc.names)}: {exc}")
    try:
        return int(args.func(args) or 0)
    except (DeviceError, KernelBuildError, SceneError, ValueError) as exc:
        print(f"restircl: error: {exc}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("restircl: interrupted", file=sys.stderr)
        return 130


if __name__ == "__main__":
    sys.exit(main())
