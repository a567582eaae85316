"""Traversal benchmark: BVH build time and Mrays/s of opencl/bvh/traverse.h against Embree (embreex) on the same rays.

    python -m restircl.eval.bench.traversal [--triangles N] [--width W] [--height H] [--no-embree] [--scene S]
                                         [--device D] [--leaf-packets on|off]

The scene is procedural (a displaced ground grid with spheres and boxes of log-normal sizes spread over it), or
with --scene light_cloud / light_panels the emissive-triangle scenes of `restircl bench lights` (triangles scattered
in a slab / lying flat in one layer) with N lights, seen from their camera.
Two ray sets: camera rays (closest hit, one per pixel) and incoherent shadow rays (any hit) from the primary hit
points towards random points in the cosine-weighted hemisphere of the surface (diffuse-like directions).
Embree traces single rays on one thread per process: it runs in one process per core, each with its own scene,
the rays split between them; only the tracing is timed (eval/bench/tracers.py). Our side runs on the chosen
OpenCL device (--device, as everywhere in restircl; default: the default choice).
"""

from __future__ import annotations

import argparse
import math
import os
import time

import numpy as np

from ...core.device import Device, get_device
from .scenes import light_scaling_scene
from .tracers import EmbreeTracer, OpenCLTracer

# ---- procedural scene ----------------------------------------------------------------------------------------


def _grid(nx: int, ny: int) -> tuple[np.ndarray, np.ndarray]:
    """Unit grid [0, 1]^2 in xy: vertices (nx+1)*(ny+1), triangles 2*nx*ny."""
    xs, ys = np.meshgrid(np.linspace(0, 1, nx + 1), np.linspace(0, 1, ny + 1), indexing="ij")
    verts = np.stack([xs.ravel(), ys.ravel(), np.zeros(xs.size)], 1)
    i, j = np.meshgrid(np.arange(nx), np.arange(ny), indexing="ij")
    a = (i * (ny + 1) + j).ravel()
    b, c, d = a + (ny + 1), a + (ny + 1) + 1, a + 1
    tris = np.concatenate([np.stack([a, b, c], 1), np.stack([a, c, d], 1)])
    return verts, tris


def _sphere(n_theta: int, n_phi: int) -> tuple[np.ndarray, np.ndarray]:
    """Unit UV sphere, closed, outward winding."""
    verts, tris = _grid(n_phi, n_theta)
    u, v = verts[:, 0], verts[:, 1]
    th, ph = v * math.pi, u * 2 * math.pi
    verts = np.stack([np.sin(th) * np.cos(ph), np.sin(th) * np.sin(ph), np.cos(th)], 1)
    return verts, tris[:, ::-1]


def _box() -> tuple[np.ndarray, np.ndarray]:
    """Unit cube [-1, 1]^3, two triangles per face, outward winding."""
    v = np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)], float)
    quads = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
    tris = [(a, b, c) for a, b, c, d in quads] + [(a, c, d) for a, b, c, d in quads]
    return v, np.array(tris)


def _instances(verts, tris, pos, scale, angle):
    """Copies of a mesh, scaled (per axis), rotated about z and moved: (v0, v1, v2) arrays."""
    c, s = np.cos(angle), np.sin(angle)
    p = verts[None] * scale[:, None, :]
    x = c[:, None] * p[..., 0] - s[:, None] * p[..., 1]
    y = s[:, None] * p[..., 0] + c[:, None] * p[..., 1]
    w = np.stack([x, y, p[..., 2]], -1) + pos[:, None, :]
    return tuple(w[:, tris[:, k]].reshape(-1, 3) for k in range(3))


def make_scene(triangles: int = 1_000_000, seed: int = 7):
    """(v0, v1, v2) of about `triangles` triangles over a 200 x 200 area: 30% ground, 50% spheres, 20% boxes."""
    rng = np.random.default_rng(seed)
    size = 200.0

    def height(x, y):
        return 1.5 * np.sin(x * 0.07) * np.cos(y * 0.05) + 0.4 * np.sin(0.31 * x + 0.17 * y) + 0.1 * np.sin(1.7 * x)

    n_ground = max(2, int(0.3 * triangles))
    g = max(1, int(math.sqrt(n_ground / 2)))
    gv, gt = _grid(g, g)
    gv = (gv - 0.5) * size
    gv[:, 2] = height(gv[:, 0], gv[:, 1])
    parts = [tuple(gv[gt[:, k]] for k in range(3))]

    sv, st = _sphere(12, 24)  # 576 triangles
    n_sph = max(1, int(0.5 * triangles) // len(st))
    r = np.exp(rng.normal(0.0, 0.6, n_sph)) * 0.8
    xy = rng.uniform(-0.48, 0.48, (n_sph, 2)) * size
    pos = np.column_stack([xy, height(xy[:, 0], xy[:, 1]) + r * rng.uniform(0.6, 3.0, n_sph)])
    parts.append(_instances(sv, st, pos, np.repeat(r[:, None], 3, 1), rng.uniform(0, 2 * np.pi, n_sph)))

    bv, bt = _box()
    n_box = max(1, int(0.2 * triangles) // len(bt))
    sc = np.exp(rng.normal(0.0, 0.7, (n_box, 3))) * np.array([1.0, 1.0, 1.5])
    xy = rng.uniform(-0.48, 0.48, (n_box, 2)) * size
    pos = np.column_stack([xy, height(xy[:, 0], xy[:, 1]) + sc[:, 2] * 0.8])
    parts.append(_instances(bv, bt, pos, sc, rng.uniform(0, 2 * np.pi, n_box)))
    return tuple(np.concatenate([p[k] for p in parts]) for k in range(3))


def light_cloud_scene(lights: int, kind: str = "triangles"):
    """(v0, v1, v2) of the emissive-triangle scenes of `restircl bench lights` (bench_scenes.light_scaling_scene):
    a ground, 30 spheres and `lights` small triangles scattered 0.3..5 m above it (kind "triangles") or lying flat
    at 5 m ("panels"), with that benchmark's camera (eye, target, horizontal field of view in degrees)."""
    scene = light_scaling_scene(lights, 64, 36, kind=kind)
    mesh = scene.meshes[0]
    v = np.asarray(mesh.vertices, np.float64)
    t = np.asarray(mesh.triangles)
    fov = math.degrees(2 * math.atan(0.5 * scene.camera.sensor_width / scene.camera.lens))
    return tuple(v[t[:, k]] for k in range(3)), ((0.0, -22.0, 9.0), (0.0, 0.0, 0.0), fov)


def camera_rays(width: int, height: int, eye=(-70.0, -80.0, 28.0), target=(10.0, 5.0, 0.0), fov: float = 60.0):
    """Pinhole camera (default: above the ground of make_scene, looking across it): (origins, unit directions),
    float32, row-major."""
    eye = np.array(eye, np.float64)
    target = np.array(target, np.float64)
    fwd = target - eye
    fwd /= np.linalg.norm(fwd)
    right = np.cross(fwd, [0.0, 0.0, 1.0])
    right /= np.linalg.norm(right)
    up = np.cross(right, fwd)
    tx = math.tan(math.radians(fov) / 2)
    ty = tx * height / width
    px = ((np.arange(width) + 0.5) / width * 2 - 1) * tx
    py = (1 - (np.arange(height) + 0.5) / height * 2) * ty
    X, Y = np.meshgrid(px, py)
    d = fwd + X[..., None] * right + Y[..., None] * up
    d = d.reshape(-1, 3)
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    o = np.broadcast_to(eye, d.shape)
    return o.astype(np.float32), d.astype(np.float32)


def offset_ray_origin(p: np.ndarray, ng: np.ndarray) -> np.ndarray:
    """numpy twin of offset_ray_origin in opencl/bvh/traverse.h (float32)."""
    p = p.astype(np.float32)
    of = (np.float32(256.0) * ng.astype(np.float32)).astype(np.int32)
    pi = (p.view(np.int32) + np.where(p < 0, -of, of)).view(np.float32)
    pf = p + np.float32(1.0 / 65536.0) * ng.astype(np.float32)
    return np.where(np.abs(p) < np.float32(1.0 / 32.0), pf, pi)


def shadow_rays(o, d, t, prim, tris, rng):
    """From each primary hit, a ray to a random point in the cosine-weighted hemisphere of the geometric normal
    facing the camera, up to 40 units away (d unnormalised, tmax = 1). Only hits make rays."""
    hit = prim >= 0
    leaf = prim[hit]
    tr = tris[leaf]
    e1, e2 = tr["e1"][:, :3].astype(np.float64), tr["e2"][:, :3].astype(np.float64)
    n = np.cross(e1, e2)
    n /= np.linalg.norm(n, axis=1, keepdims=True)
    dd = d[hit].astype(np.float64)
    n = np.where(np.sum(n * dd, 1, keepdims=True) > 0, -n, n)
    p = (o[hit].astype(np.float64) + t[hit, None] * dd).astype(np.float32)
    org = offset_ray_origin(p, n)
    # cosine-weighted direction about n
    u1, u2 = rng.random(len(n)), rng.random(len(n))
    r, phi = np.sqrt(u1), 2 * np.pi * u2
    a = np.where(np.abs(n[:, :1]) > 0.9, np.array([[0.0, 1.0, 0.0]]), np.array([[1.0, 0.0, 0.0]]))
    tx = np.cross(a, n)
    tx /= np.linalg.norm(tx, axis=1, keepdims=True)
    ty = np.cross(n, tx)
    w = (r * np.cos(phi))[:, None] * tx + (r * np.sin(phi))[:, None] * ty + np.sqrt(1 - u1)[:, None] * n
    dist = rng.uniform(0.5, 40.0, len(n))[:, None]
    return org.astype(np.float32), (w * dist).astype(np.float32)



# ---- the benchmark -------------------------------------------------------------------------------------------


def run(triangles: int = 1_000_000, width: int = 640, height: int = 360, embree: bool = True,
        print_fn=print, local_size: int | None = 64, repeats: int = 3, scene: str = "mixed", device=None,
        leaf_packets: bool | None = None) -> dict:
    """Build, trace and (if embreex imports) compare with Embree; returns the figures as a dict. scene "mixed":
    make_scene(triangles); "light_cloud" / "light_panels": light_cloud_scene(triangles), `triangles` being the
    light count. device: a restircl Device or a device spec ('P:D' or a name substring; None: the default choice),
    resolved before the scene is built, so that an unknown device fails at once (DeviceError). leaf_packets: the
    leaf layout and leaf size of bvh_packets (None: bvh_packets.ENABLED)."""
    from ...bvh import packets as bvh_packets

    saved = bvh_packets.ENABLED
    if leaf_packets is not None:
        bvh_packets.ENABLED = leaf_packets
    try:
        return _run(triangles, width, height, embree, print_fn, local_size, repeats, scene, device)
    finally:
        bvh_packets.ENABLED = saved


def _run(triangles, width, height, embree, print_fn, local_size, repeats, scene, device) -> dict:
    from ...bvh import packets as bvh_packets
    from ...bvh.build import build_bvh, make_tris
    from ...bvh.packets import device_arrays, leaf_max

    dev = device if isinstance(device, Device) else get_device(device)
    res: dict = {}
    t0 = time.perf_counter()
    if scene in ("light_cloud", "light_panels"):
        (v0, v1, v2), view = light_cloud_scene(triangles, "triangles" if scene == "light_cloud" else "panels")
    elif scene == "mixed":
        v0, v1, v2 = make_scene(triangles)
        view = None
    else:
        raise ValueError(f"scene must be mixed, light_cloud or light_panels, got {scene!r}")
    n = len(v0)
    res["triangles"] = n
    print_fn(f"scene: {scene}, {n} triangles ({time.perf_counter() - t0:.2f} s to generate)")
    bvh = build_bvh(v0, v1, v2)
    tris = make_tris(v0, v1, v2, np.zeros(n, np.int32), np.arange(n), bvh.order)
    res.update(build_seconds=bvh.build_seconds, nodes=bvh.node_count, leaves=bvh.leaf_count, depth=bvh.depth,
               sah_cost=bvh.sah_cost)
    print_fn(f"BVH build: {bvh.build_seconds:.2f} s, {bvh.node_count} nodes, {bvh.leaf_count} leaves, "
             f"depth {bvh.depth}, SAH cost {res['sah_cost']:.1f}; leaves of <= {leaf_max()} triangles, "
             f"{'packets' if bvh_packets.ENABLED else 'tested one by one'}")

    ours = OpenCLTracer(*device_arrays(bvh.nodes, tris), device=dev, local_size=local_size)
    res["device"] = ours.dev.label
    print_fn(f"device: {ours.dev.label}; POCL_WORK_GROUP_METHOD={os.environ.get('POCL_WORK_GROUP_METHOD', '')!r}, "
             f"local size {local_size or 'None (chosen by the runtime)'}; load average {os.getloadavg()[0]:.1f}")
    print_fn("Mrays/s: wall clock (best of the timed runs); in brackets per CPU-second of all threads, which does "
             "not depend on other load")
    o, d = camera_rays(width, height) if view is None else camera_rays(width, height, *view)
    t, leaf, sec = ours.closest(o, d, repeats=repeats)
    res["primary_rays"] = len(o)
    res["primary_mrays"] = len(o) / sec / 1e6
    res["primary_mrays_cpu"] = len(o) / ours.last_cpu_seconds / 1e6
    hit = leaf >= 0
    prim = np.full(len(o), -1, np.int64)
    prim[hit] = bvh.order[leaf[hit]]
    print_fn(f"ours   primary: {res['primary_mrays']:6.2f} Mrays/s [{res['primary_mrays_cpu']:5.2f}] "
             f"({len(o)} rays, {hit.mean() * 100:.1f}% hit)")
    rng = np.random.default_rng(1)
    so, sd = shadow_rays(o, d, t.astype(np.float64), leaf, tris, rng)
    occ, sec = ours.any(so, sd, 1.0, repeats=repeats)
    res["shadow_rays"] = len(so)
    res["shadow_mrays"] = len(so) / sec / 1e6
    res["shadow_mrays_cpu"] = len(so) / ours.last_cpu_seconds / 1e6
    print_fn(f"ours   shadow : {res['shadow_mrays']:6.2f} Mrays/s [{res['shadow_mrays_cpu']:5.2f}] "
             f"({len(so)} rays, {occ.mean() * 100:.1f}% occluded)")

    if embree:
        _against_embree(res, (v0, v1, v2), (o, d, t, prim), (so, sd, occ), repeats, print_fn)
    return res


def _against_embree(res: dict, triangles, primary, shadow, repeats, print_fn) -> None:
    """Embree's Mrays/s on the same rays (not timed: its scene set-up), the ratios and the agreement of the hits."""
    v0, v1, v2 = triangles
    o, d, t, prim = primary
    so, sd, occ = shadow
    try:
        import embreex  # noqa: F401
    except ImportError:
        print_fn("embreex not installed: no Embree comparison (pip install embreex)")
        return
    t1 = time.perf_counter()
    emb = EmbreeTracer(v0, v1, v2)
    print_fn(f"Embree: {emb.processes} processes, scenes ready in {time.perf_counter() - t1:.1f} s (not timed)")
    try:
        et, eprim, esec = emb.closest(o, d, repeats=repeats)
        ecpu = emb.last_cpu_seconds
        eocc, ssec = emb.any(so, sd, 1.0, repeats=repeats)
        scpu = emb.last_cpu_seconds
    finally:
        emb.close()
    res["embree_primary_mrays"] = len(o) / esec / 1e6
    res["embree_shadow_mrays"] = len(so) / ssec / 1e6
    res["embree_primary_mrays_cpu"] = len(o) / ecpu / 1e6
    res["embree_shadow_mrays_cpu"] = len(so) / scpu / 1e6
    res["primary_ratio"] = res["primary_mrays"] / res["embree_primary_mrays"]
    res["shadow_ratio"] = res["shadow_mrays"] / res["embree_shadow_mrays"]
    res["primary_ratio_cpu"] = res["primary_mrays_cpu"] / res["embree_primary_mrays_cpu"]
    res["shadow_ratio_cpu"] = res["shadow_mrays_cpu"] / res["embree_shadow_mrays_cpu"]
    same_prim = prim == eprim
    both_hit = (prim >= 0) & (eprim >= 0)
    with np.errstate(invalid="ignore"):
        close_t = both_hit & (np.abs(t - et) <= 1e-4 * np.maximum(np.abs(et), 1.0))
    res["primary_agreement"] = float(np.mean(same_prim | close_t))
    res["primary_same_prim"] = float(np.mean(same_prim))
    res["shadow_agreement"] = float(np.mean(occ == eocc))
    for kind, label in (("primary", "primary"), ("shadow", "shadow ")):
        print_fn(f"Embree {label}: {res[f'embree_{kind}_mrays']:6.2f} Mrays/s "
                 f"[{res[f'embree_{kind}_mrays_cpu']:5.2f}]; ours/Embree {res[f'{kind}_ratio']:.2f} "
                 f"[{res[f'{kind}_ratio_cpu']:.2f}]")
    print_fn(f"agreement with Embree: primary {res['primary_agreement'] * 100:.3f}% (same triangle "
             f"{res['primary_same_prim'] * 100:.3f}%, else same t), shadow {res['shadow_agreement'] * 100:.3f}%")


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(prog="python -m restircl.eval.bench.traversal", description=__doc__.split("\n")[0])
    ap.add_argument("--triangles", type=int, default=1_000_000)
    ap.add_argument("--width", type=int, default=640)
    ap.add_argument("--height", type=int, default=360)
    ap.add_argument("--no-embree", action="store_true", help="skip the Embree comparison")
    ap.add_argument("--local-size", type=int, default=64,
                    help="OpenCL local size; the global size is padded to a multiple (0: let the runtime choose)")
    ap.add_argument("--repeats", type=int, default=3, help="timed runs per measurement (best is kept)")
    ap.add_argument("--scene", choices=("mixed", "light_cloud", "light_panels"), default="mixed",
                    help="mixed: ground, spheres and boxes of --triangles triangles; light_cloud / light_panels: "
                         "the emissive-triangle scenes of `restircl bench lights` (scattered / flat) with "
                         "--triangles lights, seen from their camera")
    ap.add_argument("--device", default=None, help="OpenCL device: 'P:D' or a name substring (default: the default "
                    "choice, which honours $RESTIRCL_DEVICE)")
    ap.add_argument("--leaf-packets", choices=("on", "off"), default=None,
                    help="leaves as packets of up to 3 triangles tested together (on, the default) or leaves of up "
                         "to 2 triangles tested one by one (off)")
    args = ap.parse_args(argv)
    run(args.triangles, args.width, args.height, embree=not args.no_embree, local_size=args.local_size or None,
        repeats=args.repeats, scene=args.scene, device=args.device,
        leaf_packets=None if args.leaf_packets is None else args.leaf_packets == "on")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
