"""`restircl demo`: the built-in many_lights flythrough, rendered with ReSTIR + TAA and 2 bounces of light into
out/."""

from __future__ import annotations

import argparse
from pathlib import Path

from .. import scenes
from .arguments import COUNT, add_settings_args
from .render import render_scene

#: the demo shows light that bounces: the floor lit by the lamps' light off the objects, the metal reflecting the room
DEMO_LIGHT_PATHS = {"max_bounces": 2, "diffuse_bounces": 2, "glossy_bounces": 2}


def add_parser(sub: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
    d = sub.add_parser("demo", help="render the built-in many_lights flythrough into out/",
                       description="Render several frames of the built-in many_lights scene (animated camera) "
                                   "with ReSTIR + TAA and 2 bounces of light (--max-bounces) into --out as EXR "
                                   "(with AOVs) and PNG previews.")
    d.add_argument("--width", type=COUNT, default=640)
    d.add_argument("--height", type=COUNT, default=360)
    d.add_argument("--frames", type=COUNT, default=16)
    d.add_argument("--out", default="out")
    add_settings_args(d)
    d.set_defaults(func=run, **DEMO_LIGHT_PATHS)


def run(a: argparse.Namespace) -> int:
    scene = scenes.many_lights(width=a.width, height=a.height, frames=a.frames)
    return render_scene(scene, a.settings, a.frames, Path(a.out), "animation", a.device)
