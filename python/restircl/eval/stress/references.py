"""References of the stress suite (eval/stress/suite.py): direct light computed analytically on the host in float64 at
the renderer's own G-buffer points, the exhaustive `reference` method averaged over batches, or an exact zero."""

from __future__ import annotations

import math
import time
from dataclasses import dataclass

import numpy as np

from ...lights import disk, quad, record, sphere, spot, sun, triangle
from ...lights.device_lights import scene_lights
from ...lights.record import LUMINANCE
from ...render.pipeline import Renderer
from ...settings.table import Settings
from .cases import Case


class NotAnalytic(ValueError):
    """The analytic reference does not cover this light (a disk light, or a light across a point's horizon)."""



def _polygon_psa(x: np.ndarray, n: np.ndarray, verts: np.ndarray, one_sided: np.ndarray) -> np.ndarray:
    """Projected solid angle (integral of cos over the solid angle) of polygons verts (T, V, 3) seen from points
    x (P, 3) with normals n (P, 3), by Lambert's formula: 1/2 |sum_i theta_i n . unit(g_i x g_i+1)|, (P, T). Each
    polygon must lie on one side of each point's horizon. A one-sided polygon emits along its winding's normal."""
    nv = verts.shape[1]
    nx, ny, nz = (n[:, k : k + 1] for k in range(3))
    g, above, below = [], None, None
    for i in range(nv):  # unit vectors from the points to vertex i, as three (P, T) arrays
        gx, gy, gz = (verts[None, :, i, k] - x[:, k : k + 1] for k in range(3))
        dist = np.sqrt(gx * gx + gy * gy + gz * gz)
        height = gx * nx + gy * ny + gz * nz
        tol = 1e-5 * dist  # float32 positions: a vertex on the horizon may land this far on either side
        a, b = height >= -tol, height <= tol
        above = a if above is None else above & a
        below = b if below is None else below & b
        g.append((gx / dist, gy / dist, gz / dist))
    if np.any(~above & ~below):
        raise NotAnalytic("a polygon light crosses the horizon of a shading point")
    total = np.zeros(above.shape)
    for i in range(nv):
        (ax, ay, az), (bx, by, bz) = g[i], g[(i + 1) % nv]
        cx, cy, cz = ay * bz - az * by, az * bx - ax * bz, ax * by - ay * bx
        sn = np.sqrt(cx * cx + cy * cy + cz * cz)
        theta = np.arctan2(sn, ax * bx + ay * by + az * bz)
        ok = sn > 0
        total += np.where(ok, theta * (cx * nx + cy * ny + cz * nz) / np.where(ok, sn, 1.0), 0.0)
    psa = 0.5 * np.abs(total)
    psa[~above] = 0.0
    # one-sided emitters: nothing reaches a point behind the emitting side
    nl = np.cross(verts[:, 1] - verts[:, 0], verts[:, 2] - verts[:, 0])  # (T, 3)
    side = sum((x[:, k : k + 1] - verts[None, :, 0, k]) * nl[None, :, k] for k in range(3))
    psa[one_sided[None, :] & ~(side > 0)] = 0.0
    return psa


def _spot_mask(rec: np.ndarray, x: np.ndarray) -> np.ndarray:
    """opencl/lights/spot.h spot_mask for spot records (S, 16) at points x (P, 3): (P, S)."""
    out = x[:, None, :] - rec[None, :, 0:3]
    out = out / np.linalg.norm(out, axis=-1, keepdims=True)
    c = np.einsum("psk,sk->ps", out, rec[:, 4:7])
    cos_half, smooth = rec[:, 8][None], rec[:, 9][None]
    t = np.clip((c - cos_half) / np.where(smooth > 0, smooth, 1.0), 0.0, 1.0)
    m = np.where(smooth > 0, t * t * (3 - 2 * t), 1.0)
    return np.where(c > cos_half, m, 0.0)


def analytic_direct(pos: np.ndarray, normal: np.ndarray, records: np.ndarray, block: int = 1_000_000) -> np.ndarray:
    """Unshadowed direct irradiance-weighted radiance sum_l Le_l * (projected solid angle or cos/d^2) at points
    pos (P, 3) with unit normals (P, 3), for the device light records (N,) layouts.LIGHT, in float64: multiply
    by albedo / pi for the reflected radiance. Raises NotAnalytic for what it does not cover."""
    x = np.asarray(pos, np.float64)
    n = np.asarray(normal, np.float64)
    r = records.view(np.float32).reshape(-1, 16).astype(np.float64)
    kinds = records.view(np.float32).reshape(-1, 16)[:, 3].view(np.int32)
    flags = records.view(np.float32).reshape(-1, 16)[:, 15].view(np.int32)
    le = r[:, 12:15]
    out = np.zeros((len(x), 3))
    if np.any(kinds == disk.TYPE.code):
        raise NotAnalytic("disk lights have no analytic reference here")

    def blocks(count: int, per: int):
        step = max(1, block // max(per, 1))
        for s in range(0, count, step):
            yield slice(s, min(s + step, count))

    # points and spots (radius 0): I cos / d^2 (times the spot mask)
    sel = np.nonzero(np.isin(kinds, (sphere.TYPE.code, spot.TYPE.code)))[0]
    for sl in blocks(len(sel), len(x)):
        rec = r[sel[sl]]
        d = rec[None, :, 0:3] - x[:, None, :]  # (P, S, 3)
        dc = np.linalg.norm(d, axis=-1)
        w = d / dc[..., None]
        cos = np.einsum("psk,pk->ps", w, n)
        rad = rec[:, 7][None]
        mask = np.ones_like(cos)
        spots = kinds[sel[sl]] == spot.TYPE.code
        if spots.any():
            mask[:, spots] = _spot_mask(rec[spots], x)
        soft = (flags[sel[sl]] & sphere.FLAG_SOFT_FALLOFF) != 0
        # a sphere (hard) of radius r: pi (r / D)^2 cos; a disk of radius r facing the point (soft falloff):
        # pi r^2 / (D^2 + r^2) cos; both exact when the emitter is wholly above or below the horizon
        sin_a = np.where(soft[None], rad / np.sqrt(dc * dc + rad * rad), rad / dc)
        if np.any((rad > 0) & (dc <= rad)):
            raise NotAnalytic("a shading point inside a sphere light")
        tol = 1e-6
        straddle = (rad > 0) & (np.abs(cos) < sin_a * (1 - tol))
        if np.any(straddle):
            raise NotAnalytic("a sphere light crosses the horizon of a shading point")
        geo = np.where(rad > 0, math.pi * sin_a**2 * cos, cos / (dc * dc))
        geo = np.where(cos > 0, geo * mask, 0.0)
        out += geo @ rec[:, 12:15]
    # suns: radiance Le over a cap of 1 - cos = omc around the direction: Le pi sin^2 cos, or Le cos for a delta
    for k in np.nonzero(kinds == sun.TYPE.code)[0]:
        wdir = r[k, 4:7]
        omc = r[k, 9]
        cos = n @ wdir
        if omc > 0:
            sin_h = math.sqrt(omc * (2 - omc))
            if np.any(np.abs(cos) < sin_h * (1 - 1e-6)):
                raise NotAnalytic("a sun crosses the horizon of a shading point")
            geo = math.pi * sin_h * sin_h * cos
        else:
            geo = cos
        out += np.where(cos > 0, geo, 0.0)[:, None] * le[k][None]
    # quads and triangles: Lambert's polygon formula
    for kind, nv in ((quad.TYPE.code, 4), (triangle.TYPE.code, 3)):
        sel = np.nonzero(kinds == kind)[0]
        if not len(sel):
            continue
        p, a, b = r[sel, 0:3], r[sel, 4:7], r[sel, 8:11]
        if nv == 4:  # a quad: p + u a + v b, emitting along cross(a, b)
            verts = np.stack([p, p + a, p + a + b, p + b], axis=1)
        else:
            verts = np.stack([p, p + a, p + b], axis=1)
        one_sided = (flags[sel] & record.FLAG_TWO_SIDED) == 0
        t_step = max(1, block // 8)  # polygons per block, then as many points as fit in `block` pairs
        for t0 in range(0, len(sel), t_step):
            tl = slice(t0, min(t0 + t_step, len(sel)))
            p_step = max(1, block // (tl.stop - tl.start))
            for p0 in range(0, len(x), p_step):
                ps = slice(p0, min(p0 + p_step, len(x)))
                out[ps] += _polygon_psa(x[ps], n[ps], verts[tl], one_sided[tl]) @ le[sel[tl]]
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



def _deterministic(lights) -> bool:
    """Only delta lights (points and spots of radius 0, suns of angle 0): the exhaustive reference is exact."""
    rec = lights.records.view(np.float32).reshape(-1, 16)
    kinds = rec[:, 3].view(np.int32)
    point = np.isin(kinds, (sphere.TYPE.code, spot.TYPE.code)) & (rec[:, 7] == 0)
    suns = (kinds == sun.TYPE.code) & (rec[:, 9] == 0)
    return bool(np.all(point | suns))


def compute_reference(case: Case, device=None, frame: int | None = None, seed: int = 0) -> Reference:
    """The case's reference image at its evaluation frame (a still camera there)."""
    t0 = time.perf_counter()
    frame = case.eval_frame if frame is None else frame
    scene = case.scene
    if case.reference == "exhaustive":
        r = Renderer(scene, Settings(method="reference", jitter=False, taa=False, seed=9001 + 100_000 * seed), device)
        lights = scene_lights(scene, frame)
        batches, frames = (1, 1) if _deterministic(lights) else (case.ref_batches, case.ref_frames)
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
    hit = g["normal"][:, 3].view(np.int32) >= 0
    lights = scene_lights(scene, frame)
    e = analytic_direct(g["pos"][hit, :3], g["normal"][hit, :3], lights.records)
    img = g["emission"][:, :3].astype(np.float64)
    img[hit] += g["albedo"][hit, :3] / math.pi * e
    z = np.zeros((*shape, 3))
    return Reference(img.reshape(*shape, 3), z, np.zeros(shape), 0.0, max(len(lights), 1), time.perf_counter() - t0)

