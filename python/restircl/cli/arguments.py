"""What the sub-commands share on the command line: the number types of their options, the options of every
setting (read from the settings table) and a scene named by a built-in name or a file."""

from __future__ import annotations

import argparse
from pathlib import Path

from .. import scenes
from ..scene.errors import SceneError
from ..scene.scene import Scene
from ..settings.spec import Range, add_arguments, from_arguments
from ..settings.table import Settings

COUNT = Range(int, 1).parse  # sizes, frame counts: 0 or less is a mistake, not "the default"
POSITIVE = Range(float, 0, min_open=True, finite=True)  # seconds, error targets
SECONDS = POSITIVE.parse
BOUNCES = Range(int, 0, 1024).parse  # Light Paths' bounce counts, as the settings table bounds them


def load_scene(spec: str, width: int | None, height: int | None, frames: int | None = None) -> Scene:
    """A built-in scene name or a scene file (.npz), with the resolution overridden if given."""
    if spec in scenes.BUILTIN:
        kwargs = {}
        if width:
            kwargs["width"] = width
        if height:
            kwargs["height"] = height
        if frames and spec == "many_lights":
            kwargs["frames"] = frames
        return scenes.builtin(spec, **kwargs)
    path = Path(spec)
    if not path.exists():
        raise SceneError(f"{spec!r} is neither a built-in scene ({', '.join(scenes.BUILTIN)}) nor a file")
    scene = Scene.load(path)
    if scene.camera is not None:
        if width:
            scene.camera.width = width
        if height:
            scene.camera.height = height
    return scene


def add_settings_args(p: argparse.ArgumentParser) -> None:
    """One option per Settings field (the table in settings/table.py), and --device."""
    add_arguments(p.add_argument_group("rendering method and its parameters"), Settings)
    p.add_argument("--device", default=None, help="OpenCL device: 'P:D' or a name substring (default: "
                   "$RESTIRCL_DEVICE, else the first GPU, else the first CPU)")
    p.set_defaults(settings_parser=p)


def settings_from_args(a: argparse.Namespace) -> Settings:
    return from_arguments(Settings, a).validate()
