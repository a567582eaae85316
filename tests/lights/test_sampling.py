"""Lights: sampled points follow each light type's pdf (chi-square), and the estimator contrib / pdf integrates to
the irradiance computed independently in numpy (analytic or quadrature), within 4 standard errors."""

import math

import numpy as np
import pyopencl as cl
import pyopencl.cltypes as clt
import pytest
from restircl import Light, Scene, look_at, translation
from restircl.core.program import build_program
from restircl.lights.device_lights import scene_lights
from restircl.render.features import general_flags

from ..stats import pooled_chi2

SRC = """
#include "types.h"
#include "sampling/rng.h"
#include "lights/lights.h"
__kernel void sample_light(const __global Light* lights, float4 x4, float4 n4, uint seed, __global float4* out)
{
    int i = get_global_id(0);
    uint rng = rng_seed((uint)i, 0u, seed, 0u);
    float r0 = rng_next(&rng), r1 = rng_next(&rng);
    float pdf;
    float2 uv = light_sample(&lights[0], x4.xyz, r0, r1, &pdf);
    LightEval e;
    bool ok = pdf > 0.0f && light_eval(&lights[0], uv.x, uv.y, x4.xyz, n4.xyz, &e);
    out[3 * i + 0] = (float4)(ok ? e.pos : (float3)(0.0f), pdf);
    out[3 * i + 1] = (float4)(ok ? e.contrib : (float3)(0.0f), ok ? 1.0f : 0.0f);
    out[3 * i + 2] = (float4)(ok ? e.wi : (float3)(0.0f), 0.0f);
}
"""

N = 200_000


def launch(device, recs, x, n, seed: int, count: int) -> np.ndarray:
    prog = build_program(device, general_flags(), source=SRC)
    mf = cl.mem_flags
    lb = cl.Buffer(device.context, mf.READ_ONLY | mf.COPY_HOST_PTR, hostbuf=recs)
    out = np.empty((count, 3, 4), np.float32)
    ob = cl.Buffer(device.context, mf.WRITE_ONLY, out.nbytes)
    kernel = cl.Kernel(prog, "sample_light")
    kernel(device.queue, (count,), None, lb, clt.make_float4(*x, 0.0), clt.make_float4(*n, 0.0), np.uint32(seed), ob)
    cl.enqueue_copy(device.queue, out, ob)
    return out


def run_light(device, light: Light, x, n, seed: int = 1, count: int = N):
    recs = scene_lights(Scene(lights=[light]), 0).records
    out = launch(device, recs, x, n, seed, count)
    pos, pdf = out[:, 0, :3].astype(np.float64), out[:, 0, 3].astype(np.float64)
    contrib, ok = out[:, 1, :3].astype(np.float64), out[:, 1, 3] > 0
    wi = out[:, 2, :3].astype(np.float64)
    return recs, pos, pdf, contrib, ok, wi


def estimate(contrib, pdf, ok):
    est = np.where(ok, contrib[:, 0] / np.where(pdf > 0, pdf, 1.0), 0.0)
    return est.mean(), est.std(ddof=1) / math.sqrt(len(est))


def plane_coords(points, origin, a, b):
    """Coordinates of points in the (non-orthogonal) basis a, b of a plane through origin."""
    m = np.stack([a, b], axis=1)
    coef, *_ = np.linalg.lstsq(m, (points - origin).T, rcond=None)
    return coef.T


def uniform_reference(shape: str, count: int, rng: np.random.Generator):
    """Uniform points (by rejection) in the shape's parameter plane: (s, t) coordinates."""
    pts = rng.uniform(-1, 1, (count * 2, 2)) if shape == "disk" else rng.uniform(0, 1, (count * 2, 2))
    if shape == "disk":
        pts = pts[(pts**2).sum(1) <= 1]
    elif shape == "triangle":
        pts = pts[pts.sum(1) <= 1]
    return pts[:count]


def grid_chi2(obs_pts, ref_pts, lo, hi, bins=10):
    h_obs, _, _ = np.histogram2d(obs_pts[:, 0], obs_pts[:, 1], bins=bins, range=[[lo, hi], [lo, hi]])
    h_ref, _, _ = np.histogram2d(ref_pts[:, 0], ref_pts[:, 1], bins=bins, range=[[lo, hi], [lo, hi]])
    # the reference is itself a sample: only bins it covers well are compared (expected from a 10x larger sample)
    return pooled_chi2(h_obs, h_ref / h_ref.sum(), min_expected=20)


X = np.array([0.0, 0.0, 0.0])
UP = np.array([0.0, 0.0, 1.0])


@pytest.mark.parametrize("shape", ["SQUARE", "DISK"])
def test_area_light_points_are_uniform_in_area(device, shape):
    light = Light("a", "area", (1, 1, 1), 100.0, translation(0.3, -0.2, 1.5), shape=shape, size=1.0)
    recs, pos, pdf, contrib, ok, _ = run_light(device, light, X, UP)
    r = recs[0]
    if shape == "SQUARE":
        st = plane_coords(pos, r["p"][:3], r["a"][:3], r["b"][:3])
        ref = uniform_reference("square", 10 * N, np.random.default_rng(5))
        stat, p, dof = grid_chi2(st, ref, 0.0, 1.0)
        np.testing.assert_allclose(pdf, 1.0, rtol=1e-5)  # area 1 m^2
    else:
        st = plane_coords(pos, r["p"][:3], r["a"][:3], r["b"][:3])
        ref = uniform_reference("disk", 10 * N, np.random.default_rng(5))
        stat, p, dof = grid_chi2(st, ref, -1.0, 1.0)
        np.testing.assert_allclose(pdf, 1.0 / (math.pi * 0.25), rtol=1e-5)
    assert dof > 50 and p > 1e-4, (stat, p, dof)


def test_triangle_light_points_are_uniform_in_area(device):
    from restircl import Material, Mesh

    v = np.array([[0, 0, 2.0], [1.5, 0, 2.0], [0.2, 1.0, 2.2]])
    scene = Scene([Mesh("tri", v, [[0, 1, 2]], 0)], [Material("lamp", (0, 0, 0), (1, 1, 1), 3.0)])
    recs = scene_lights(scene, 0).records
    out = launch(device, recs, X, UP, 3, N)
    st = plane_coords(out[:, 0, :3].astype(np.float64), v[0], v[1] - v[0], v[2] - v[0])
    ref = uniform_reference("triangle", 10 * N, np.random.default_rng(9))
    stat, p, dof = grid_chi2(st, ref, 0.0, 1.0)
    assert dof > 30 and p > 1e-4, (stat, p, dof)
    area = 0.5 * np.linalg.norm(np.cross(v[1] - v[0], v[2] - v[0]))
    np.testing.assert_allclose(out[:, 0, 3], 1.0 / area, rtol=1e-5)


def cone_bins(dirs, axis, omc, bins_t=10, bins_phi=8):
    """Bin unit directions by (1 - cos theta) / omc and azimuth around `axis`: uniform in solid angle within the
    cone means uniform over this grid."""
    axis = axis / np.linalg.norm(axis)
    ref = np.array([1.0, 0, 0]) if abs(axis[0]) < 0.9 else np.array([0, 1.0, 0])
    s = np.cross(axis, ref)
    s /= np.linalg.norm(s)
    t = np.cross(axis, s)
    c = np.clip(dirs @ axis, -1, 1)
    u = (1 - c) / omc
    phi = (np.arctan2(dirs @ t, dirs @ s) + np.pi) / (2 * np.pi)
    h, _, _ = np.histogram2d(u, phi, bins=[bins_t, bins_phi], range=[[0, 1], [0, 1]])
    return h


@pytest.mark.parametrize("dist", [3.0, 1.05, 1e4])
def test_sphere_light_samples_uniform_in_visible_cone(device, dist):
    r = 1.0
    centre = np.array([0.2, 0.1, dist])
    light = Light("s", "point", (1, 1, 1), 100.0, translation(*centre), radius=r, soft_falloff=False)
    _, pos, pdf, contrib, ok, wi = run_light(device, light, X, UP)
    d = centre - X
    dc = np.linalg.norm(d)
    sin2 = (r / dc) ** 2
    omc = sin2 / (1 + math.sqrt(1 - sin2))
    if dist < 100:
        h = cone_bins(wi[ok], d, omc)
        stat, p, dof = pooled_chi2(h, np.ones_like(h) / h.size)
    else:
        # float32 directions cannot resolve a 1e-4 rad cone: seen from far away, uniform in solid angle means the
        # sampled sphere points project uniformly onto the disk facing x
        ny = (pos[ok] - centre) / r
        axis = d / dc
        s_ax = np.cross(axis, [1.0, 0, 0])
        s_ax /= np.linalg.norm(s_ax)
        t_ax = np.cross(axis, s_ax)
        proj = np.stack([ny @ s_ax, ny @ t_ax], 1)
        ref = uniform_reference("disk", 10 * N, np.random.default_rng(4))
        stat, p, dof = grid_chi2(proj, ref, -1.0, 1.0)
    assert p > 1e-4, (stat, p, dof)
    # the returned pdf is the area density of the cone sampler: cos_l / (dist^2 * solid angle)
    if dist < 100:
        nl = (pos - centre) / r
        to_x = X - pos
        d2 = (to_x**2).sum(1)
        cos_l = (nl * to_x).sum(1) / np.sqrt(d2)
        expect = cos_l / (d2 * 2 * math.pi * omc)
        np.testing.assert_allclose(pdf[ok], expect[ok], rtol=2e-3)


def test_sun_directions_uniform_in_cone(device):
    angle = math.radians(10.0)
    light = Light("sun", "sun", (1, 1, 1), 3.0, look_at((1, 1, 3), (0, 0, 0)), angle=angle)
    _, pos, pdf, contrib, ok, wi = run_light(device, light, X, UP)
    axis = np.array([1.0, 1.0, 3.0])
    omc = 1 - math.cos(angle / 2)
    h = cone_bins(wi, axis, omc)
    stat, p, dof = pooled_chi2(h, np.ones_like(h) / h.size)
    assert p > 1e-4, (stat, p, dof)


def _check(mean, se, expect):
    assert abs(mean - expect) <= 4 * se + 1e-6 * abs(expect), (mean, se, expect)


def quad_irradiance(corner, a, b, x, n, radiance, res=800):
    """Irradiance at x from a one-sided emitting parallelogram (emitting along cross(a, b)), by midpoint rule."""
    s = (np.arange(res) + 0.5) / res
    u, v = np.meshgrid(s, s, indexing="ij")
    pts = corner + u[..., None] * a + v[..., None] * b
    nl = np.cross(a, b)
    area = np.linalg.norm(nl)
    nl /= area
    d = pts - x
    d2 = (d**2).sum(-1)
    w = d / np.sqrt(d2)[..., None]
    cos_x = np.clip(w @ n, 0, None)
    cos_l = np.clip(-(w @ nl), 0, None)
    return radiance * (cos_x * cos_l / d2).mean() * area


def test_units_point_light(device):
    light = Light("p", "point", (1, 1, 1), 100.0, translation(0.5, 0, 2.0))
    _, pos, pdf, contrib, ok, _ = run_light(device, light, X, UP)
    d2 = 0.25 + 4.0
    expect = 100.0 / (4 * math.pi) * (2.0 / math.sqrt(d2)) / d2
    mean, se = estimate(contrib, pdf, ok)
    assert mean == pytest.approx(expect, rel=1e-5)


@pytest.mark.parametrize("soft", [False, True])
def test_units_sphere_light(device, soft):
    h, r = 2.0, 0.5
    light = Light("p", "point", (1, 1, 1), 100.0, translation(0, 0, h), radius=r, soft_falloff=soft)
    _, pos, pdf, contrib, ok, _ = run_light(device, light, X, UP)
    intensity = 100.0 / (4 * math.pi)
    # physical sphere above the horizon: I / h^2 at normal incidence; soft falloff (a disk facing x): I / (h^2 + r^2)
    expect = intensity / (h * h + r * r) if soft else intensity / (h * h)
    mean, se = estimate(contrib, pdf, ok)
    _check(mean, se, expect)


def test_units_spot_light_cone_and_blend(device):
    size, blend = math.radians(60), 0.5
    m = look_at((0, 0, 2), (0, 0, 0))
    light = Light("s", "spot", (1, 1, 1), 100.0, m, spot_size=size, spot_blend=blend)
    cos_half = math.cos(size / 2)
    for xpos in (0.0, 0.6, 0.9, 1.3):
        x = np.array([xpos, 0, 0])
        _, pos, pdf, contrib, ok, _ = run_light(device, light, x, UP, count=1000)
        d = np.array([0, 0, 2.0]) - x
        dist = np.linalg.norm(d)
        c = 2.0 / dist  # cosine between the spot axis (-Z) and the direction to x
        t = np.clip((c - cos_half) / ((1 - cos_half) * blend), 0, 1)
        mask = t * t * (3 - 2 * t) if c > cos_half else 0.0
        expect = 100.0 / (4 * math.pi) * mask * (2.0 / dist) / dist**2
        mean, se = estimate(contrib, pdf, ok)
        assert mean == pytest.approx(expect, rel=1e-4, abs=1e-9), xpos


def test_units_sun(device):
    for angle in (0.0, math.radians(10.0)):
        light = Light("sun", "sun", (1, 1, 1), 3.0, look_at((0, 0, 1), (0, 0, 0)), angle=angle)
        _, pos, pdf, contrib, ok, _ = run_light(device, light, X, UP)
        mean, se = estimate(contrib, pdf, ok)
        _check(mean, se, 3.0)  # Blender: irradiance at normal incidence equals the strength


@pytest.mark.parametrize("shape,size,size_y", [("SQUARE", 1.0, 1.0), ("RECTANGLE", 2.0, 0.5), ("DISK", 1.0, 1.0)])
def test_units_area_light(device, shape, size, size_y):
    m = translation(0.3, 0.2, 1.0)  # facing down (-Z) onto the receiver at the origin
    light = Light("a", "area", (1, 1, 1), 50.0, m, shape=shape, size=size, size_y=size_y)
    recs, pos, pdf, contrib, ok, _ = run_light(device, light, X, UP)
    mean, se = estimate(contrib, pdf, ok)
    if shape == "DISK":
        area = math.pi * size * size / 4
        radiance = 50.0 / (math.pi * area)
        # quadrature over the disk: sample a fine polar grid
        rr = (np.arange(400) + 0.5) / 400 * size / 2
        ph = (np.arange(400) + 0.5) / 400 * 2 * np.pi
        R, P = np.meshgrid(rr, ph, indexing="ij")
        pts = np.stack([0.3 + R * np.cos(P), 0.2 + R * np.sin(P), np.ones_like(R)], -1)
        d2 = (pts**2).sum(-1)
        cosx = pts[..., 2] / np.sqrt(d2)
        dA = R * (size / 2 / 400) * (2 * np.pi / 400)
        expect = radiance * (cosx * cosx / d2 * dA).sum()
    else:
        area = size * (size_y if shape == "RECTANGLE" else size)
        r = recs[0]
        expect = quad_irradiance(r["p"][:3].astype(float), r["a"][:3].astype(float), r["b"][:3].astype(float),
                                 X, UP, 50.0 / (math.pi * area))
    _check(mean, se, expect)
    # one-sided: from above the light (behind its emitting side) nothing arrives
    _, _, pdf2, contrib2, ok2, _ = run_light(device, light, np.array([0.3, 0.2, 2.0]), -UP, count=2000)
    assert not ok2.any()


@pytest.mark.parametrize("shape", ["RECTANGLE", "ELLIPSE"])
def test_a_mirroring_transform_keeps_the_emitting_side(device, shape):
    """Blender's area light emits along its transform's -Z column also where the transform mirrors (Cycles does):
    the record's cross(span_u, span_v) points there, and the floor below is lit as by the unmirrored light."""
    from restircl import Camera, Material, Mesh, Renderer, Scene, Settings, look_at
    from restircl.lights.device_lights import scene_lights
    from restircl.scenes import quad

    mirror = np.diag([-1.0, 1.0, 1.0, 1.0])
    images = []
    for m in (np.eye(4), mirror):
        m = m.copy()
        m[:3, 3] = (0.0, 0.0, 1.0)
        light = Light("panel", "area", (1.0, 1.0, 1.0), 50.0, m, shape=shape, size=0.8, size_y=0.5)
        fv, ft = quad(4.0, 4.0)
        cam = Camera(look_at((0.0, -3.0, 2.0), (0.0, 0.0, 0.0)), 24, 16)
        scene = Scene([Mesh("floor", fv, ft, 0)], [Material("grey", (0.7, 0.7, 0.7))], [light], cam)
        rec = np.ascontiguousarray(scene_lights(scene, 0).records[:1]).view(np.float32).reshape(16)
        normal = np.cross(rec[4:7], rec[8:11])
        assert normal[2] < 0 and np.allclose(normal[:2], 0.0, atol=1e-6), normal
        r = Renderer(scene, Settings(method="reference", jitter=False, seed=3), device)
        images.append(r.render_still(0, 64).color[..., :3])
    assert images[1].mean() > 0 and images[1].mean() == pytest.approx(images[0].mean(), rel=0.02)
