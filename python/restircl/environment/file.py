"""The environment in the scene file (scene/file.py, version 3): its scalar fields in the JSON header, its image,
rotation and strength_per_frame as arrays; a path is stored as the path (the file is read when the scene renders)."""

from __future__ import annotations

import numpy as np

from .world import Environment

ARRAYS = ("image", "rotation", "strength_per_frame")


def write_environment(env: Environment | None, arrays: dict[str, np.ndarray]) -> dict | None:
    """The header entry of `env` (None without one); its arrays go into `arrays` as world_<field>."""
    if env is None:
        return None
    for name in ARRAYS:
        value = getattr(env, name)
        if value is not None:
            arrays[f"world_{name}"] = np.asarray(value)
    entry = {"name": env.name, "color": list(map(float, env.color)), "strength": float(env.strength),
             "path": env.path, "visible_camera": bool(env.visible_camera), "lightgroup": env.lightgroup}
    if env.interpolation != "Closest":  # a map read texel by texel keeps the bytes (and cache keys) it had
        entry["interpolation"] = env.interpolation
    return entry


def read_environment(entry: dict | None, data: dict[str, np.ndarray]) -> Environment | None:
    if entry is None:
        return None
    d = dict(entry)
    d["color"] = tuple(d["color"])
    return Environment(**d, **{name: data.get(f"world_{name}") for name in ARRAYS})
