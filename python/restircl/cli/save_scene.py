"""`restircl save-scene`: a built-in scene written to a scene file (.npz)."""

from __future__ import annotations

import argparse

from .arguments import COUNT, load_scene


def add_parser(sub: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
    s = sub.add_parser("save-scene", help="write a built-in scene to a scene file (.npz)")
    s.add_argument("scene")
    s.add_argument("path")
    s.add_argument("--width", type=COUNT, default=None)
    s.add_argument("--height", type=COUNT, default=None)
    s.set_defaults(func=run)


def run(a: argparse.Namespace) -> int:
    scene = load_scene(a.scene, a.width, a.height)
    scene.save(a.path)
    print(f"wrote {a.path}")
    return 0
