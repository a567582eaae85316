"""`restircl demo`: the built-in many_lights flythrough, rendered with ReSTIR + TAA into out/."""

from __future__ import annotations

import argparse
from pathlib import Path

from .. import scenes
from .arguments import COUNT, add_settings_args
from .render import render_scene


def add_parser(sub: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
    d = sub.add_parser("demo", help="render the built-in many_lights flythrough into out/",
                       description="Render several frames of the built-in many_lights scene (animated camera) "
                                   "with ReSTIR + TAA into --out as EXR (with AOVs) and PNG previews.")
    d.add_argument("--width", type=COUNT, default=640)
    d.add_argument("--height", type=COUNT, default=360)
    d.add_argument("--frames", type=COUNT, default=16)
    d.add_argument("--out", default="out")
    add_settings_args(d)
    d.set_defaults(func=run)


def run(a: argparse.Namespace) -> int:
    scene = scenes.many_lights(width=a.width, height=a.height, frames=a.frames)
    return render_scene(scene, a.settings, a.frames, Path(a.out), "animation", a.device)
