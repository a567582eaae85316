"""Blender lights -> restircl.Light, in Blender's units converted as Cycles does (docs/units.md): lights keep
Blender's power (W) or sun strength (W/m^2), with what Blender layers on top of it folded in (colour
temperature, exposure, the 'normalize' switch, a light node tree's Emission strength)."""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np

from ..compat import uses_nodes, visible_camera
from ..light_groups import object_group
from .convert import matrix, rgb
from .linking import read_linking
from .motion import Frames, fill_gaps, instance_key, transforms
from .report import ExportError

BLENDER_SPREAD_FULL = math.pi - 1e-4


class LightReader:
    """The lights of the current frame (`read`), then their matrices and power at the other frames (`sample`)."""

    def __init__(self, frames: Frames, warn: Callable[[str], None]):
        self.frames = frames
        self.warn = warn
        self._params: list[dict] = []  # restircl.Light keyword arguments at the current frame
        self._tracks: list[list] = []  # light-to-world matrix per sampled frame
        self._powers: list[list[float]] = []  # power per sampled frame (0 where the light is not there)
        self._by_key: dict[tuple, int] = {}

    def read(self, inst) -> None:
        ob = inst.object
        m = matrix(inst.matrix_world)
        params = light_params(ob.data, np.linalg.norm(m[:3, :3], axis=0), self.warn, ob.name)
        params["visible_camera"] = visible_camera(ob)
        params["linking"] = read_linking(ob)
        params["lightgroup"] = object_group(ob)
        self._by_key[instance_key(inst)] = len(self._params)
        self._params.append(params)
        self._tracks.append(self.frames.track(m))
        self._powers.append(self.frames.track(params["power"], fill=0.0))

    def sample(self, inst, k: int) -> None:
        ob = inst.object
        i = self._by_key.get(instance_key(inst))
        if i is None:
            self.warn(f"light {ob.name!r} is not there at frame {self.frames.current}; not rendered")
            return
        m = matrix(inst.matrix_world)
        self._tracks[i][k] = m
        # warnings were given at the current frame
        p = light_params(ob.data, np.linalg.norm(m[:3, :3], axis=0), lambda _m: None, ob.name)
        self._powers[i][k] = p["power"]

    def build(self) -> list:
        """restircl.Light per light; an animated power becomes its peak times a per-frame factor."""
        import restircl

        light_fields = set(getattr(restircl.Light, "__dataclass_fields__", {}))
        soft_lights = []
        negative: list[str] = []
        lights = []
        for params, track, powers in zip(self._params, self._tracks, self._powers, strict=True):
            fill_gaps(track)
            params = dict(params)
            soft = params.pop("soft_falloff", None)
            if soft is not None and "soft_falloff" in light_fields:
                params["soft_falloff"] = soft
            elif soft:
                soft_lights.append(params["name"])
            if "visible_camera" not in light_fields:  # a restircl from before lights were seen
                params.pop("visible_camera")
            if params["linking"] is None:
                params.pop("linking")
            p = np.asarray(powers, dtype=np.float64)
            if np.any(p < 0):
                # Cycles subtracts such light; a RIS target is a luminance >= 0, so it cannot be resampled
                negative.append(params["name"])
                p = np.maximum(p, 0.0)
                if not np.any(p > 0):
                    continue
                params["power"] = max(float(params["power"]), 0.0)
            if len(p) > 1 and not np.all(p == p[0]):
                peak = float(np.max(np.abs(p)))
                params["power"] = peak
                params["power_per_frame"] = p / peak if peak > 0 else np.zeros_like(p)
            lights.append(restircl.Light(transforms=transforms(track), **params))
        if negative:
            self.warn(f"light(s) {', '.join(repr(n) for n in negative[:5])}: negative strength (subtracted "
                      "light) is not rendered; left out where negative")
        if soft_lights:
            self.warn(f"light(s) {', '.join(repr(n) for n in soft_lights[:5])}: 'Soft Falloff' is rendered as a "
                      "physical sphere light (turn Soft Falloff off to match Cycles near the light)")
        return lights


def light_params(ld, scale: np.ndarray, warn: Callable[[str], None], name: str) -> dict:
    """restircl.Light keyword arguments (without transforms) for a Blender light datablock."""
    colour = np.array(rgb(ld.color))
    if getattr(ld, "use_temperature", False):
        colour = colour * np.array(rgb(ld.temperature_color))
    power = float(ld.energy) * 2.0 ** float(getattr(ld, "exposure", 0.0))
    if uses_nodes(ld):
        factor = _light_node_factor(ld.node_tree, warn, name)
        colour = colour * factor[0]
        power *= factor[1]
    kind = ld.type
    params: dict = {"name": name}
    if kind in ("POINT", "SPOT"):
        params["type"] = kind.lower()
        params["radius"] = float(ld.shadow_soft_size)
        if kind == "SPOT":
            params["spot_size"] = float(ld.spot_size)
            params["spot_blend"] = float(ld.spot_blend)
            if getattr(ld, "use_square", False):
                warn(f"light {name!r}: square spot cones are rendered round")
        r = params["radius"]
        if not getattr(ld, "normalize", True):
            power *= 4.0 * math.pi * r * r if r > 0 else 4.0
        params["soft_falloff"] = bool(getattr(ld, "use_soft_falloff", False))
    elif kind == "SUN":
        params["type"] = "sun"
        params["angle"] = float(ld.angle)
        if not getattr(ld, "normalize", True):
            power *= math.pi * math.sin(float(ld.angle) / 2.0) ** 2
    elif kind == "AREA":
        params["type"] = "area"
        params["shape"] = ld.shape
        params["size"] = float(ld.size)
        params["size_y"] = float(ld.size_y) if ld.shape in ("RECTANGLE", "ELLIPSE") else float(ld.size)
        if float(getattr(ld, "spread", math.pi)) < BLENDER_SPREAD_FULL:
            warn(f"light {name!r}: area light spread below 180 degrees is rendered as 180 degrees")
        if not getattr(ld, "normalize", True):
            sx, sy = params["size"] * scale[0], params["size_y"] * scale[1]
            area = sx * sy * (math.pi / 4.0 if ld.shape in ("DISK", "ELLIPSE") else 1.0)
            power *= area
    else:
        raise ExportError(f"light {name!r}: unknown light type {kind!r}")
    params["color"] = rgb(colour)
    params["power"] = power
    return params


def _light_node_factor(tree, warn: Callable[[str], None], name: str) -> tuple[np.ndarray, float]:
    """(colour, strength) of the Emission node feeding a light's node tree output."""
    out = None
    for node in tree.nodes:
        if node.bl_idname == "ShaderNodeOutputLight" and getattr(node, "is_active_output", True):
            out = node
            break
    if out is None or not out.inputs["Surface"].is_linked:
        return np.ones(3), 1.0
    src = out.inputs["Surface"].links[0].from_node
    if src.bl_idname != "ShaderNodeEmission":
        warn(f"light {name!r}: light node {src.bl_label!r} is not supported; ignored")
        return np.ones(3), 1.0
    col, strength = src.inputs["Color"], src.inputs["Strength"]
    if col.is_linked or strength.is_linked:
        warn(f"light {name!r}: textured light nodes are not supported; their unlinked values are used")
    return np.array(rgb(col.default_value)), float(strength.default_value)
