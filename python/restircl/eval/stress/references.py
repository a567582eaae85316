"""References of the stress suite (eval/stress/suite.py): direct light computed analytically on the host in float64 at
the renderer's own G-buffer points, the exhaustive `reference` method averaged over batches, or an exact zero."""

from __future__ import annotations

import math
import time
from dataclasses import dataclass

import numpy as np

from ...lights.device_lights import scene_lights
from ...lights.record import LUMINANCE
from ...lights.registry import groups, type_of
from ...render.pipeline import Renderer
from ...settings.table import Settings
from .cases import Case


def analytic_direct(pos: np.ndarray, normal: np.ndarray, records: np.ndarray, block: int = 1_000_000) -> np.ndarray:
    """Unshadowed direct irradiance-weighted radiance sum_l Le_l * (projected solid angle or cos/d^2) at points
    pos (P, 3) with unit normals (P, 3), for the device light records (N,) layouts.LIGHT, in float64: multiply
    by albedo / pi for the reflected radiance. Each type gives its lights' closed form (LightType.analytic,
    lights/<type>.py), in blocks of about `block` (point, light) pairs; raises lights.light_type.NotAnalytic for
    what they do not cover."""
    x = np.asarray(pos, np.float64)
    n = np.asarray(normal, np.float64)
    lanes = records.view(np.float32).reshape(-1, 16).astype(np.float64)
    kinds = records.view(np.int32).reshape(-1, 16)[:, 3]
    flags = records.view(np.int32).reshape(-1, 16)[:, 15]
    out = np.zeros((len(x), 3))
    for t, sel in groups(kinds) if len(kinds) else ():
        rows = np.arange(len(kinds))[sel]
        step = max(1, block // 8)  # lights per block, then as many points as fit in `block` pairs
        for l0 in range(0, len(rows), step):
            ls = rows[l0 : l0 + step]
            p_step = max(1, block // len(ls))
            for p0 in range(0, len(x), p_step):
                ps = slice(p0, min(p0 + p_step, len(x)))
                out[ps] += t.analytic(x[ps], n[ps], lanes[ls], flags[ls]) @ lanes[ls, 12:15]
    return out


@dataclass
class Reference:
    mean: np.ndarray  # (H, W, 3)
    se: np.ndarray  # (H, W, 3) standard error of the mean (0: exact)
    lum_se: np.ndarray  # (H, W)
    image_se: float  # standard error of the image mean luminance
    terms: int  # light count: the float32 sums behind an exact pixel have this many terms
    seconds: float = 0.0



def _gbuffer(r: Renderer) -> np.ndarray:
    """The G-buffer of the frame the renderer rendered last."""
    return r.read_gbuffer()



def luminance(x: np.ndarray) -> np.ndarray:
    return x @ LUMINANCE



def _deterministic(scene, lights) -> bool:
    """Only delta lights (scene lights whose type says they have no shape: points and spots of radius 0, suns of
    angle 0; no world, no emissive triangles): the exhaustive reference is exact."""
    return len(lights) == len(scene.lights) and not any(type_of(lt).has_shape(lt) for lt in scene.lights)


def compute_reference(case: Case, device=None, frame: int | None = None, seed: int = 0) -> Reference:
    """The case's reference image at its evaluation frame (a still camera there)."""
    t0 = time.perf_counter()
    frame = case.eval_frame if frame is None else frame
    scene = case.scene
    if case.reference == "exhaustive":
        # the case's own settings (its bounces among them) under the exhaustive direct light
        r = Renderer(scene, Settings(**{**case.settings, "method": "reference", "jitter": False, "taa": False,
                                        "seed": 9001 + 100_000 * seed}), device)
        lights = scene_lights(scene, frame)
        # delta lights alone make the direct light exact, but light that bounces is still a path tracer's estimate
        exact = _deterministic(scene, lights) and not case.settings.get("max_bounces", 0)
        batches, frames = (1, 1) if exact else (case.ref_batches, case.ref_frames)
        means = []
        for b in range(batches):
            r.settings.seed = 9001 + 100_000 * seed + b
            means.append(r.render_still(frame, frames).color[..., :3].astype(np.float64))
        m = np.stack(means)
        if batches > 1:
            se = m.std(axis=0, ddof=1) / math.sqrt(batches)
            lum_se = luminance(m).std(axis=0, ddof=1) / math.sqrt(batches)
            image_se = float(luminance(m).mean(axis=(1, 2)).std(ddof=1) / math.sqrt(batches))
        else:
            se = np.zeros_like(m[0])
            lum_se = np.zeros(m.shape[1:3])
            image_se = 0.0
        return Reference(m.mean(axis=0), se, lum_se, image_se, len(lights), time.perf_counter() - t0)
    cam = scene.camera
    assert cam is not None
    shape = (cam.height, cam.width)
    if case.reference == "zero":
        z = np.zeros((*shape, 3))
        return Reference(z, z.copy(), np.zeros(shape), 0.0, 1, time.perf_counter() - t0)
    # analytic, at the G-buffer points of the frame under test (jitter off: the same in every run)
    r = Renderer(scene, Settings(method="light_array", jitter=False, taa=False), device)
    r.render_frame(frame, still=True)
    g = _gbuffer(r).reshape(-1)
    # the points that reflect light: emitters of albedo 0 (emissive triangles the camera sees) add only their emission,
    # and the closed forms need not hold there (another emitter may cross their horizon)
    hit = (g["normal"][:, 3].view(np.int32) >= 0) & np.any(g["albedo"][:, :3] > 0, axis=1)
    lights = scene_lights(scene, frame)
    e = analytic_direct(g["pos"][hit, :3], g["normal"][hit, :3], lights.records)
    img = g["emission"][:, :3].astype(np.float64)
    img[hit] += g["albedo"][hit, :3] / math.pi * e
    z = np.zeros((*shape, 3))
    return Reference(img.reshape(*shape, 3), z, np.zeros(shape), 0.0, max(len(lights), 1), time.perf_counter() - t0)

