"""Scene lights and emissive triangles -> packed device Light records (opencl/types.h), with Blender's units.

Conversions (measured against Cycles, docs/units.md): point/spot of power P: intensity I = P / (4 pi) per colour
channel; with radius r > 0 the emitter has radiance I / (pi r^2) and is a sphere (soft_falloff off) or, Blender's
default soft falloff, a disk of radius r facing the shading point (irradiance I cos / (d^2 + r^2)); the spot cone
only masks (smoothstep blend), it does not concentrate power. Area light of power P and area A: radiance
P / (pi A), one-sided, emitting along the light's local -Z. Sun of strength S (W/m^2) and angular diameter theta:
radiance S / (pi sin^2(theta / 2)) inside its cone, so that the irradiance at normal incidence is S; S itself
when theta = 0. Emissive material: radiance colour * strength, two-sided.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from . import layouts as L
from .scene import Scene

LUMINANCE = np.array([0.2126, 0.7152, 0.0722])
TYPE_NAMES = {
    L.LIGHT_TRIANGLE: "triangle", L.LIGHT_QUAD: "quad", L.LIGHT_DISK: "disk",
    L.LIGHT_SPHERE: "sphere", L.LIGHT_SPOT: "spot", L.LIGHT_SUN: "sun",
}


@dataclass
class DeviceLights:
    records: np.ndarray  # layouts.LIGHT
    power: np.ndarray  # (N,) coarse importance of each light (luminance-weighted power, W)
    types: np.ndarray  # (N,) LIGHT_* codes
    source: np.ndarray  # (N,) index into scene.lights, or -1 - triangle index for emissive triangles

    def __len__(self) -> int:
        return len(self.records)

    @property
    def type_set(self) -> set[int]:
        return {int(t) for t in np.unique(self.types)}


def _unit(v: np.ndarray) -> np.ndarray:
    n = np.linalg.norm(v)
    return v / n if n > 0 else v


def scene_lights(scene: Scene, frame: int, world=None) -> DeviceLights:
    """Device light records for `frame`: the scene's lights first (in order), then emissive triangles."""
    if world is None:
        world = scene.world_triangles(frame)
    recs: list[np.ndarray] = []
    power: list[float] = []
    types: list[int] = []
    source: list[int] = []
    bounds_r = _scene_radius(world)
    for idx, lt in enumerate(scene.lights):
        m = Scene.at(lt.transforms, frame)
        col = np.asarray(lt.color, dtype=np.float64)
        p_w = lt.power_at(frame)
        r = np.zeros(16)
        flags = 0
        pos = m[:3, 3]
        if lt.type in ("point", "spot"):
            intensity = col * p_w / (4.0 * math.pi)
            radius = float(lt.radius)
            le = intensity / (math.pi * radius * radius) if radius > 0 else intensity
            r[0:3] = pos
            r[7] = radius
            flags = L.LIGHT_FLAG_SOFT_FALLOFF if (lt.soft_falloff and radius > 0) else 0
            if lt.type == "spot":
                t = L.LIGHT_SPOT
                r[4:7] = _unit(-m[:3, 2])
                cos_half = math.cos(lt.spot_size / 2.0)
                r[8] = cos_half
                r[9] = (1.0 - cos_half) * lt.spot_blend
                imp = float(LUMINANCE @ intensity) * 2.0 * math.pi * (1.0 - cos_half)
            else:
                t = L.LIGHT_SPHERE
                imp = float(LUMINANCE @ intensity) * 4.0 * math.pi
            r[12:15] = le
        elif lt.type == "sun":
            t = L.LIGHT_SUN
            r[4:7] = _unit(m[:3, 2])  # towards the sun: the light shines along its -Z
            half = lt.angle / 2.0
            omc = 2.0 * math.sin(half / 2.0) ** 2  # 1 - cos(half), exact for tiny angles
            r[8] = math.cos(half)
            r[9] = omc
            sin2 = math.sin(half) ** 2
            r[12:15] = col * p_w / (math.pi * sin2) if omc > 0 else col * p_w
            imp = float(LUMINANCE @ (col * p_w)) * math.pi * bounds_r * bounds_r
        else:  # area
            ux = m[:3, 0] * lt.size
            vy = m[:3, 1] * (lt.size_y if lt.shape in ("RECTANGLE", "ELLIPSE") else lt.size)
            if lt.shape in ("SQUARE", "RECTANGLE"):
                t = L.LIGHT_QUAD
                r[0:3] = pos - 0.5 * ux - 0.5 * vy
                r[4:7] = vy  # cross(vy, ux) points along local -Z: the emitting side
                r[8:11] = ux
                area = float(np.linalg.norm(np.cross(ux, vy)))
            else:
                t = L.LIGHT_DISK
                r[0:3] = pos
                r[4:7] = 0.5 * vy
                r[8:11] = 0.5 * ux
                area = math.pi * 0.25 * float(np.linalg.norm(np.cross(ux, vy)))
            r[11] = area
            le = col * p_w / (math.pi * area)
            r[12:15] = le
            imp = float(LUMINANCE @ le) * area * math.pi
        rec = r.astype(np.float32)
        rec[3] = np.int32(t).view(np.float32)
        rec[15] = np.int32(flags).view(np.float32)
        recs.append(rec)
        power.append(imp)
        types.append(t)
        source.append(idx)
    # emissive triangles
    rad = np.array([m.radiance for m in scene.materials]).reshape(-1, 3) if scene.materials else np.zeros((0, 3))
    n_tri_lights = 0
    tri_recs = np.zeros((0, 16), np.float32)
    tri_power = np.zeros(0)
    tri_src = np.zeros(0, np.int64)
    if len(world) and len(rad):
        le = rad[world.material]
        emissive = np.nonzero(np.any(le > 0, axis=1))[0]
        n_tri_lights = len(emissive)
        if n_tri_lights:
            v0 = world.v0[emissive]
            e1 = world.v1[emissive] - v0
            e2 = world.v2[emissive] - v0
            area = 0.5 * np.linalg.norm(np.cross(e1, e2), axis=1)
            tri_recs = np.zeros((n_tri_lights, 16), np.float32)
            tri_recs[:, 0:3] = v0
            tri_recs[:, 4:7] = e1
            tri_recs[:, 8:11] = e2
            tri_recs[:, 11] = area
            tri_recs[:, 12:15] = le[emissive]
            tri_recs[:, 3] = np.int32(L.LIGHT_TRIANGLE).view(np.float32)
            tri_recs[:, 15] = np.int32(L.LIGHT_FLAG_TWO_SIDED).view(np.float32)
            tri_power = (le[emissive] @ LUMINANCE) * area * math.pi * 2.0
            tri_src = -1 - emissive
    all_recs = np.concatenate([np.array(recs, np.float32).reshape(-1, 16), tri_recs]) if recs else tri_recs
    records = np.zeros(len(all_recs), L.LIGHT)
    records.view(np.float32).reshape(-1, 16)[:] = all_recs
    return DeviceLights(
        records,
        np.concatenate([np.array(power, np.float64), tri_power]),
        np.concatenate([np.array(types, np.int64), np.full(n_tri_lights, L.LIGHT_TRIANGLE, np.int64)]),
        np.concatenate([np.array(source, np.int64), tri_src]),
    )


def _scene_radius(world) -> float:
    if len(world) == 0:
        return 1.0
    pts = np.concatenate([world.v0, world.v1, world.v2])
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    return max(0.5 * float(np.linalg.norm(hi - lo)), 1e-3)
