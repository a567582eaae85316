"""An independent path-traced reference of global illumination, in numpy, for the unbiasedness tests of the
renderer's path kernel; and the small scene those tests render (path_test_scene).

It shares no code with the renderer's estimators: nothing from restircl is imported but the scene model (Scene,
Camera, Mesh, Material, Light, Environment: the fields a user fills). The camera, the scene's world-space geometry,
the light units, the ray intersection and the estimator are written here again from their definitions
(docs/units.md, Blender's camera).

Estimator: brute force. Pure BSDF sampling: at every path vertex one cosine-weighted direction (no light sampling,
no MIS), and emission counts where a ray finds it. Rays are tested against every triangle (Moller-Trumbore, its
triple products expanded into matrix products, in blocks of bounded size) and every area light. Optional Russian
roulette (`survival` < 1) keeps it unbiased. Random numbers come from a numpy Generator of a fixed seed.

What it supports, and what it refuses (NotImplementedError, never a silent approximation):
- triangle meshes with flat (geometric) normals, two-sided surfaces; Mesh.normals (smooth shading) is refused;
- Lambertian materials: kind "diffuse", or "principled" with Metallic 0 and Specular IOR Level 0 (no specular layer:
  its diffuse albedo is then the Base Color); constant inputs only, no layers, no normal map. Albedo max(c, 0);
- emission: Material.emission x emission_strength, a radiance in W/(m^2 sr), two-sided (Cycles' emission shader);
  an emissive surface reflects as well (its albedo);
- area lights of shape SQUARE and RECTANGLE: the parallelogram spanned by the transform's X and Y columns times
  size (size_y), radiance colour x power / (pi A), one-sided: it emits along the transform's -Z column only (also
  for a mirroring transform, as Cycles). Lights are transparent, as in Cycles (its default Transparent Max Bounces
  8): a ray that meets one goes on to the surface behind it, having picked up the radiance where it met the
  emitting side; `transparent_lights=False` ends a ray at the first emitting side it meets instead (Cycles with
  Transparent Max Bounces 0, and the renderer's camera rays today); the back side never stops a ray. The camera
  sees a light only where Light.visible_camera is set; other light types (point, spot, sun, disk, ellipse) are
  refused: a BSDF ray cannot find a delta light;
- a constant world (Environment without an image): colour x strength from every direction a ray escapes to; camera
  rays that miss see it where Environment.visible_camera is set;
- perspective and orthographic cameras as Blender defines them: the ray through the pixel's centre (x + 0.5,
  y + 0.5), row 0 at the top, no jitter, sensor fit AUTO / HORIZONTAL / VERTICAL, shift.

Bounce numbering (Cycles' Light Paths: Max Bounces B keeps b = 0..B; B = 0 is direct light only):
- `emission`: what the camera ray sees directly (emission of the primary hit, a camera-visible light, the world);
- `radiance[0]`: light reaching the primary hit directly, i.e. emission found by the first BSDF ray from it;
- `radiance[b]`: light that scattered b more times (emission found by the (b + 1)-th BSDF ray of the path).
A renderer with Max Bounces B converges to `cumulative[B] = emission + radiance[0] + ... + radiance[B]`, whose
standard error `cumulative_se[B]` comes from the per-path sums (a path's bounces are correlated). tests/stats.py
`disagreement` compares such a mean with another image within their standard errors.
Units: radiance in W/(m^2 sr) per RGB channel, lengths in scene units (metres).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from restircl import Camera, Environment, Light, Material, Mesh, Scene, look_at, translation

PAIR_BUDGET = 1 << 18  # ray-shape pairs per block of the brute-force intersection (a few MiB per array)
PATH_BUDGET = 1 << 16  # paths traced together
OFFSET = 1e-9  # a new ray leaves its surface this far (relative to the scene's scale) along the normal

#: (u (n, 2) uniform numbers in [0, 1), unit normals (n, 3)) -> (unit directions (n, 3), pdf (n,) per steradian)
Hemisphere = Callable[[np.ndarray, np.ndarray], tuple[np.ndarray, np.ndarray]]


def _frame_of(transforms: np.ndarray, frame: int) -> np.ndarray:
    return transforms[min(max(frame, 0), transforms.shape[0] - 1)]


def _unit(v: np.ndarray) -> np.ndarray:
    return v / np.linalg.norm(v, axis=-1, keepdims=True)


# ---- the scene at one frame ------------------------------------------------------------------------------------


@dataclass(frozen=True)
class Shapes:
    """Flat shapes spanned from a corner v0 by two edges e1, e2 (triangles or parallelograms), with the per-shape
    factors of Moller-Trumbore's triple products, so that a block of rays meets a block of shapes in matrix
    products: with w = o x d, det = -d.n, u det = w.e2 - d.(e2 x v0), v det = -w.e1 - d.(v0 x e1),
    t det = o.n - v0.n, where n = e1 x e2."""

    v0: np.ndarray
    e1: np.ndarray
    e2: np.ndarray
    parallelogram: bool

    @property
    def n(self) -> np.ndarray:
        return np.cross(self.e1, self.e2)

    def __len__(self) -> int:
        return len(self.v0)


def crossings(o: np.ndarray, d: np.ndarray, s: Shapes) -> np.ndarray:
    """(R, S) distances t > 0 at which rays o + t d (R rays) meet shapes s; inf where they do not. The (R, S)
    arrays are worked on in place (the reference traces spend most of their time here)."""
    n = s.n
    w = np.cross(o, d)
    det = d @ n.T
    np.negative(det, out=det)
    udet = w @ s.e2.T
    udet -= d @ np.cross(s.e2, s.v0).T
    vdet = w @ s.e1.T
    np.negative(vdet, out=vdet)
    vdet -= d @ np.cross(s.v0, s.e1).T
    tdet = o @ n.T
    tdet -= np.einsum("ij,ij->i", s.v0, n)
    sign = np.sign(det)
    udet *= sign  # u det and v det with the sign of det: u and v times |det|
    vdet *= sign
    adet = np.abs(det, out=sign)
    inside = udet >= 0
    inside &= vdet >= 0
    if s.parallelogram:
        inside &= udet <= adet
        inside &= vdet <= adet
    else:
        udet += vdet
        inside &= udet <= adet
    inside &= adet > 0
    with np.errstate(divide="ignore", invalid="ignore"):
        t = np.divide(tdet, det, out=tdet)
    inside &= t > 0
    return np.where(inside, t, np.inf)


def _blocks(shapes: int) -> tuple[int, int]:
    """(rays, shapes) per block: at most PAIR_BUDGET pairs."""
    shape_block = max(1, min(shapes, PAIR_BUDGET))
    return max(1, PAIR_BUDGET // shape_block), shape_block


def nearest(o: np.ndarray, d: np.ndarray, s: Shapes) -> tuple[np.ndarray, np.ndarray]:
    """The closest shape each ray meets: (t (R,), index (R,)), inf and -1 where it meets none."""
    best_t = np.full(len(o), np.inf)
    best_i = np.full(len(o), -1, np.int64)
    ray_block, shape_block = _blocks(len(s))
    for r0 in range(0, len(o), ray_block):
        r = slice(r0, r0 + ray_block)
        for s0 in range(0, len(s), shape_block):
            part = Shapes(s.v0[s0:s0 + shape_block], s.e1[s0:s0 + shape_block], s.e2[s0:s0 + shape_block],
                          s.parallelogram)
            t = crossings(o[r], d[r], part)
            k = np.argmin(t, axis=1)
            tk = t[np.arange(len(k)), k]
            closer = tk < best_t[r]
            best_t[r] = np.where(closer, tk, best_t[r])
            best_i[r] = np.where(closer, k + s0, best_i[r])
    return best_t, best_i


@dataclass(frozen=True)
class Geometry:
    """The scene at one frame in world space (float64): its triangles with their diffuse albedo and emitted
    radiance, its area lights (emitting normal, radiance, camera visibility) and the world's radiance."""

    triangles: Shapes
    albedo: np.ndarray  # (T + 1, 3): row T (index -1) is 0, for rays that meet no triangle
    emission: np.ndarray  # (T + 1, 3), both sides; row T is 0
    lights: Shapes  # parallelograms
    light_normal: np.ndarray  # (Q, 3) unit, the emitting side
    light_radiance: np.ndarray  # (Q, 3)
    light_camera: np.ndarray  # (Q,) bool: Ray Visibility > Camera
    world: np.ndarray  # (3,) radiance of every escaping direction
    world_camera: bool
    scale: float  # the largest coordinate magnitude, for ray offsets

    def lights_met(self, o: np.ndarray, d: np.ndarray, t_max: np.ndarray,
                   camera: bool) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """What rays meet of the lights' emitting sides before t_max (camera rays: only the lights visible to the
        camera): (the sum of their radiances (R, 3), the distance to the nearest (R,), inf where none, and its
        radiance (R, 3))."""
        total, first = np.zeros((len(o), 3)), np.zeros((len(o), 3))
        t_first = np.full(len(o), np.inf)
        keep = self.light_camera if camera else np.ones(len(self.lights), bool)
        if not np.any(keep):
            return total, t_first, first
        ray_block, _ = _blocks(len(self.lights))
        for r0 in range(0, len(o), ray_block):
            r = slice(r0, r0 + ray_block)
            t = crossings(o[r], d[r], self.lights)
            t = np.where((t < t_max[r, None]) & (d[r] @ self.light_normal.T < 0) & keep, t, np.inf)
            total[r] = np.isfinite(t) @ self.light_radiance
            k = np.argmin(t, axis=1)
            t_first[r] = t[np.arange(len(k)), k]
            first[r] = np.where(np.isfinite(t_first[r])[:, None], self.light_radiance[k], 0.0)
        return total, t_first, first


def diffuse_response(m: Material) -> tuple[np.ndarray, np.ndarray]:
    """(albedo, emitted radiance) of a Lambertian material; NotImplementedError for anything else."""
    label = f"material {m.name!r}"
    if m.layers or m.normal is not None:
        raise NotImplementedError(f"{label}: layers and normal maps are not supported")
    if m.kind == "principled":
        if not (isinstance(m.metallic, int | float) and isinstance(m.specular, int | float)):
            raise NotImplementedError(f"{label}: textured metallic or specular")
        if m.metallic != 0 or m.specular != 0:
            raise NotImplementedError(f"{label}: only a principled BSDF without metallic and specular is Lambertian")
    elif m.kind != "diffuse":
        raise NotImplementedError(f"{label}: kind {m.kind!r}")
    colours = []
    for what in (m.albedo, m.emission):
        if not isinstance(what, tuple | list | np.ndarray) or np.shape(what) != (3,):
            raise NotImplementedError(f"{label}: textured colours are not supported")
        colours.append(np.asarray(what, dtype=np.float64))
    return np.maximum(colours[0], 0.0), colours[1] * float(m.emission_strength)


def _mesh_triangles(mesh: Mesh, frame: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    if mesh.normals is not None:
        raise NotImplementedError(f"mesh {mesh.name!r}: smooth shading normals are not supported")
    m = _frame_of(mesh.transforms, frame)
    v = mesh.vertices @ m[:3, :3].T + m[:3, 3]
    a, b, c = (v[mesh.triangles[:, k]] for k in range(3))
    return a, b, c


def _area_light(lt: Light, frame: int) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """corner, edge x, edge y, emitting unit normal and radiance of a square or rectangular area light."""
    if lt.type != "area" or lt.shape not in ("SQUARE", "RECTANGLE"):
        raise NotImplementedError(f"light {lt.name!r}: only SQUARE and RECTANGLE area lights are supported")
    m = _frame_of(lt.transforms, frame)
    ex = m[:3, 0] * lt.size
    ey = m[:3, 1] * (lt.size_y if lt.shape == "RECTANGLE" else lt.size)
    area = float(np.linalg.norm(np.cross(ex, ey)))
    radiance = np.asarray(lt.color, dtype=np.float64) * lt.power_at(frame) / (math.pi * area)
    return m[:3, 3] - 0.5 * (ex + ey), ex, ey, _unit(-m[:3, 2]), radiance


def _world(env: Environment | None, frame: int) -> tuple[np.ndarray, bool]:
    if env is None:
        return np.zeros(3), False
    if env.image is not None or env.path is not None:
        raise NotImplementedError(f"world {env.name!r}: only a constant colour is supported")
    return np.asarray(env.color, dtype=np.float64) * env.strength_at(frame), bool(env.visible_camera)


def scene_geometry(scene: Scene, frame: int = 0) -> Geometry:
    """The world-space geometry, materials, lights and world of `scene` at `frame`."""
    responses = [diffuse_response(m) for m in scene.materials]
    parts = [(*_mesh_triangles(mesh, frame), mesh.material_ids) for mesh in scene.meshes if len(mesh.triangles)]
    if parts:
        a, b, c, ids = (np.concatenate([p[k] for p in parts]) for k in range(4))
    else:
        a = b = c = np.zeros((0, 3))
        ids = np.zeros(0, np.int64)
    keep = np.linalg.norm(np.cross(b - a, c - a), axis=1) > 0  # a degenerate triangle is never hit
    a, b, c, ids = a[keep], b[keep], c[keep], ids[keep]
    none = np.zeros((1, 3))
    albedo = np.concatenate([np.array([r[0] for r in responses]).reshape(-1, 3)[ids], none])
    emission = np.concatenate([np.array([r[1] for r in responses]).reshape(-1, 3)[ids], none])
    lights = [_area_light(lt, frame) for lt in scene.lights]
    q = [np.array([x[k] for x in lights]).reshape(-1, 3) for k in range(5)]
    world, world_camera = _world(scene.environment, frame)
    scale = max([1.0, *(float(np.abs(x).max()) for x in (a, b, c, *q[:3]) if x.size)])
    return Geometry(Shapes(a, b - a, c - a, False), albedo, emission, Shapes(q[0], q[1], q[2], True), q[3], q[4],
                    np.array([lt.visible_camera for lt in scene.lights], bool), world, world_camera, scale)


# ---- the camera --------------------------------------------------------------------------------------------------


def camera_rays(cam: Camera, frame: int = 0) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(origins (H, W, 3), unit directions (H, W, 3), forward (3,)) of the rays through the pixels' centres.

    Blender's rules: the camera looks along its -Z column with its Y column up; the sensor is fitted along the
    wider image axis (AUTO, with the sensor width) or the named one; half the fitted axis spans sensor / (2 lens)
    at unit distance (half the ortho scale for an orthographic camera), the other axis in proportion; the shift is
    a fraction of the fitted axis' full span. The basis is made orthonormal keeping -Z exactly."""
    m = _frame_of(cam.transforms, frame)
    forward = _unit(-m[:3, 2])
    up = _unit(np.cross(_unit(m[:3, 0]), forward))
    right = np.cross(forward, up)
    w, h = cam.width, cam.height
    fit = ("HORIZONTAL" if w >= h else "VERTICAL") if cam.sensor_fit == "AUTO" else cam.sensor_fit
    sensor = cam.sensor_height if cam.sensor_fit == "VERTICAL" else cam.sensor_width
    half = 0.5 * cam.ortho_scale if cam.type == "ORTHO" else 0.5 * sensor / cam.lens
    half_x, half_y = (half, half * h / w) if fit == "HORIZONTAL" else (half * w / h, half)
    xs = (2.0 * (np.arange(w) + 0.5) / w - 1.0) * half_x + 2.0 * cam.shift_x * half
    ys = (1.0 - 2.0 * (np.arange(h) + 0.5) / h) * half_y + 2.0 * cam.shift_y * half
    plane = xs[None, :, None] * right + ys[:, None, None] * up  # (H, W, 3)
    if cam.type == "ORTHO":
        return m[:3, 3] + plane, np.broadcast_to(forward, plane.shape).copy(), forward
    return np.broadcast_to(m[:3, 3], plane.shape).copy(), _unit(forward + plane), forward


# ---- sampling ------------------------------------------------------------------------------------------------


def _tangents(n: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    helper = np.where(np.abs(n[:, :1]) < 0.9, [[1.0, 0.0, 0.0]], [[0.0, 1.0, 0.0]])
    t = _unit(np.cross(helper, n))
    return t, np.cross(n, t)


def _local(n: np.ndarray, x: np.ndarray, y: np.ndarray, z: np.ndarray) -> np.ndarray:
    t, b = _tangents(n)
    return x[:, None] * t + y[:, None] * b + z[:, None] * n


def cosine_hemisphere(u: np.ndarray, n: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Directions about n with density cos / pi (a uniform disk lifted to the hemisphere)."""
    r, phi = np.sqrt(u[:, 0]), 2.0 * math.pi * u[:, 1]
    z = np.sqrt(np.maximum(1.0 - u[:, 0], 0.0))
    return _local(n, r * np.cos(phi), r * np.sin(phi), z), z / math.pi


def uniform_hemisphere(u: np.ndarray, n: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Directions about n with density 1 / (2 pi)."""
    z, phi = u[:, 0], 2.0 * math.pi * u[:, 1]
    r = np.sqrt(np.maximum(1.0 - z * z, 0.0))
    return _local(n, r * np.cos(phi), r * np.sin(phi), z), np.full(len(u), 0.5 / math.pi)


# ---- the estimator -----------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class PathEstimate:
    """Per pixel (row 0 at the top): what the camera sees directly, and the mean radiance per bounce with its
    standard error (from the sample variance of `samples` paths per pixel)."""

    emission: np.ndarray  # (H, W, 3): exact, the camera ray is fixed
    radiance: np.ndarray  # (B + 1, H, W, 3)
    radiance_se: np.ndarray  # (B + 1, H, W, 3)
    cumulative: np.ndarray  # (B + 1, H, W, 3): emission + radiance[0..b], what Max Bounces b converges to
    cumulative_se: np.ndarray  # (B + 1, H, W, 3): from the per-path sums (the bounces of a path are correlated)
    depth: np.ndarray  # (H, W) view depth of the primary surface hit, inf where there is none
    position: np.ndarray  # (H, W, 3) the primary hit, nan where none
    normal: np.ndarray  # (H, W, 3) its geometric normal, facing the camera; nan where none
    samples: int

    @property
    def direct(self) -> tuple[np.ndarray, np.ndarray]:
        """(mean, standard error) of the direct light image, camera-seen emission included (Max Bounces 0)."""
        return self.cumulative[0], self.cumulative_se[0]


@dataclass
class _Vertices:
    """Path vertices on surfaces: position, geometric normal facing where the path came from, albedo."""

    x: np.ndarray
    n: np.ndarray
    albedo: np.ndarray


def _hits(geo: Geometry, o: np.ndarray, d: np.ndarray, transparent: bool,
          camera: bool = False) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(t, index of the triangle the path goes on from (-1: it ends), radiance found on the way: the emitting sides
    of the lights met, the surface's emission or the world where the ray escapes). Opaque lights (`transparent`
    False) end a ray at the first emitting side it meets."""
    t, k = nearest(o, d, geo.triangles)
    world = geo.world if geo.world_camera or not camera else np.zeros(3)
    found = np.where((k >= 0)[:, None], geo.emission[k], world)
    total, t_light, first = geo.lights_met(o, d, t, camera)
    if transparent:
        return t, k, found + total
    stopped = t_light < t
    return t, np.where(stopped, -1, k), np.where(stopped[:, None], first, found)


def _vertices(geo: Geometry, o: np.ndarray, d: np.ndarray, t: np.ndarray, k: np.ndarray) -> _Vertices:
    n = _unit(geo.triangles.n[k])
    n = np.where((np.einsum("ij,ij->i", n, d) > 0)[:, None], -n, n)
    return _Vertices(o + t[:, None] * d, n, geo.albedo[k])


def _trace(geo: Geometry, v: _Vertices, bounces: int, rng: np.random.Generator, survival: float,
           hemisphere: Hemisphere, transparent: bool) -> np.ndarray:
    """(B + 1, n, 3) radiance per bounce of one path from each vertex of v."""
    out = np.zeros((bounces + 1, len(v.x), 3))
    alive = np.arange(len(v.x))
    beta = np.ones((len(v.x), 3))
    for b in range(bounces + 1):
        if survival < 1.0:
            keep = rng.random(len(alive)) < survival
            alive, beta, v = alive[keep], beta[keep] / survival, _Vertices(v.x[keep], v.n[keep], v.albedo[keep])
        d, pdf = hemisphere(rng.random((len(alive), 2)), v.n)
        cos = np.einsum("ij,ij->i", d, v.n)
        ok = (pdf > 0) & (cos > 0)
        weight = np.where(ok, cos / np.where(ok, pdf, 1.0), 0.0) / math.pi
        beta = beta * v.albedo * weight[:, None]
        o = v.x + (OFFSET * geo.scale) * v.n
        t, k, found = _hits(geo, o, d, transparent)
        out[b, alive] = beta * found
        go = (k >= 0) & np.any(beta > 0, axis=1)
        alive, beta = alive[go], beta[go]
        v = _vertices(geo, o[go], d[go], t[go], k[go])
        if not len(alive):
            break
    return out


def _primary(geo: Geometry, cam: Camera, frame: int,
             transparent: bool) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """(emission seen (P, 3), t (P,), triangle (P,), origins, directions) of the P pixels' camera rays."""
    o, d, _ = camera_rays(cam, frame)
    o, d = o.reshape(-1, 3), d.reshape(-1, 3)
    t, k, seen = _hits(geo, o, d, transparent, camera=True)
    return seen, t, k, o, d


def _mean_se(total: np.ndarray, squares: np.ndarray, n: int) -> tuple[np.ndarray, np.ndarray]:
    mean = total / n
    var = np.maximum(squares - total * mean, 0.0) / max(n - 1, 1)
    return mean, np.sqrt(var / n)


def trace_paths(scene: Scene, bounces: int, samples: int, *, frame: int = 0, seed: int = 0, survival: float = 1.0,
                hemisphere: Hemisphere = cosine_hemisphere, transparent_lights: bool = True) -> PathEstimate:
    """Trace `samples` paths per pixel of `scene` at `frame`, each with up to bounces + 1 BSDF rays, and return the
    mean radiance per bounce (module docstring: numbering, units). `survival` < 1: Russian roulette before every
    BSDF ray (the path goes on with that probability, its weight divided by it). `hemisphere` draws the BSDF
    directions (cosine_hemisphere; uniform_hemisphere is the slower check of it). `transparent_lights` False: a
    ray ends at the first area light whose emitting side it meets (Cycles with Transparent Max Bounces 0, and the
    renderer's camera rays at lights visible to the camera)."""
    if bounces < 0 or samples < 1 or not 0.0 < survival <= 1.0:
        raise ValueError("bounces >= 0, samples >= 1 and 0 < survival <= 1")
    cam = scene.camera
    geo = scene_geometry(scene, frame)
    seen, t, k, o, d = _primary(geo, cam, frame, transparent_lights)
    hit = np.nonzero(k >= 0)[0]
    first = _vertices(geo, o[hit], d[hit], t[hit], k[hit])
    rng = np.random.default_rng(seed)
    shape = (bounces + 1, len(hit), 3)
    sums = [np.zeros(shape) for _ in range(4)]  # per bounce: sum, sum of squares; the same of the cumulative sums
    per_batch = max(1, PATH_BUDGET // max(len(hit), 1))
    for start in range(0, samples, per_batch):
        m = min(per_batch, samples - start)
        rep = _Vertices(*(np.tile(a, (m, 1)) for a in (first.x, first.n, first.albedo)))
        c = _trace(geo, rep, bounces, rng, survival, hemisphere, transparent_lights)
        c = c.reshape(bounces + 1, m, len(hit), 3)
        acc = np.cumsum(c, axis=0)
        for s, x in zip(sums, (c, c * c, acc, acc * acc), strict=True):
            s += x.sum(axis=1)
    pixels = cam.height * cam.width

    def image(x: np.ndarray) -> np.ndarray:
        full = np.zeros((bounces + 1, pixels, 3))
        full[:, hit] = x
        return full.reshape(bounces + 1, cam.height, cam.width, 3)

    mean, se = _mean_se(sums[0], sums[1], samples)
    acc_mean, acc_se = _mean_se(sums[2], sums[3], samples)
    emission = seen.reshape(cam.height, cam.width, 3)
    _, _, forward = camera_rays(cam, frame)
    position = np.full((pixels, 3), np.nan)
    normal = np.full((pixels, 3), np.nan)
    position[hit], normal[hit] = first.x, first.n
    depth = np.where(k >= 0, (position - o) @ forward, np.inf)
    return PathEstimate(emission, image(mean), image(se), emission + image(acc_mean), image(acc_se),
                        depth.reshape(cam.height, cam.width), position.reshape(cam.height, cam.width, 3),
                        normal.reshape(cam.height, cam.width, 3), samples)


# ---- the scene of the GI tests -----------------------------------------------------------------------------------


def _quad_mesh(name: str, corner: tuple[float, float, float], ex: tuple[float, float, float],
               ey: tuple[float, float, float], material: int) -> Mesh:
    c, a, b = (np.asarray(x, dtype=np.float64) for x in (corner, ex, ey))
    return Mesh(name, np.array([c, c + a, c + a + b, c + b]), np.array([[0, 1, 2], [0, 2, 3]]), material)


def _block(name: str, size: tuple[float, float, float], centre: tuple[float, float, float], turn_deg: float,
           material: int) -> Mesh:
    """An axis-aligned box of `size`, turned about Z and standing at `centre` (12 triangles)."""
    h = np.asarray(size, dtype=np.float64) / 2
    corners = np.array([[x, y, z] for z in (-1, 1) for y in (-1, 1) for x in (-1, 1)], float) * h
    faces = [(0, 2, 3, 1), (4, 5, 7, 6), (0, 1, 5, 4), (2, 6, 7, 3), (0, 4, 6, 2), (1, 3, 7, 5)]
    tris = np.array([t for a, b, c, d in faces for t in ((a, b, c), (a, c, d))])
    c, s = math.cos(math.radians(turn_deg)), math.sin(math.radians(turn_deg))
    turn = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
    return Mesh(name, corners @ turn.T + centre, tris, material)


def path_test_scene(width: int = 12, height: int = 9, *, light: str = "both",
                    world: tuple[float, float, float] | None = None, light_visible: bool = False) -> Scene:
    """A Cornell-like box, 3 m wide and deep, 2.5 m high, open towards the camera: a white floor, ceiling and back
    wall, a red left and a green right wall, a white block (Principled BSDF without specular) and a blue one
    (Diffuse BSDF). `light`: "quad" a 1.0 x 0.6 m RECTANGLE area light (60 W) 2 cm under the ceiling facing down;
    "mesh" a 0.6 x 0.3 m emissive patch (two-sided, radiance (4, 2.8, 1.6)) hanging horizontally near the back left;
    "both". `world`: a constant world colour (strength 1), else none. Every material is Lambertian, so
    trace_paths renders it."""
    if light not in ("quad", "mesh", "both"):
        raise ValueError(f"light must be quad, mesh or both, got {light!r}")
    wx, wy, wz = 1.5, 1.5, 2.5
    materials = [Material("white", (0.75, 0.75, 0.75)), Material("red", (0.65, 0.08, 0.06)),
                 Material("green", (0.12, 0.5, 0.1)), Material("blue", (0.15, 0.25, 0.7), kind="diffuse"),
                 Material("lamp", (0.0, 0.0, 0.0), (1.0, 0.7, 0.4), 4.0)]
    meshes = [
        _quad_mesh("floor", (-wx, -wy, 0), (2 * wx, 0, 0), (0, 2 * wy, 0), 0),
        _quad_mesh("ceiling", (-wx, -wy, wz), (0, 2 * wy, 0), (2 * wx, 0, 0), 0),
        _quad_mesh("back", (-wx, wy, 0), (2 * wx, 0, 0), (0, 0, wz), 0),
        _quad_mesh("left", (-wx, -wy, 0), (0, 2 * wy, 0), (0, 0, wz), 1),
        _quad_mesh("right", (wx, -wy, 0), (0, 0, wz), (0, 2 * wy, 0), 2),
        _block("tall", (0.7, 0.7, 1.4), (-0.5, 0.5, 0.7), 20.0, 0),
        _block("short", (0.6, 0.6, 0.6), (0.6, -0.3, 0.3), -15.0, 3),
    ]
    if light in ("mesh", "both"):
        meshes.append(_quad_mesh("lamp", (-1.25, 1.2, 1.3), (0.8, 0, 0), (0, 0, 0.6), 4))
    lights = []
    if light in ("quad", "both"):
        lights.append(Light("panel", "area", (1.0, 0.95, 0.85), 60.0, translation(0.2, 0.1, wz - 0.02),
                            shape="RECTANGLE", size=1.0, size_y=0.8, visible_camera=light_visible))
    cam = Camera(look_at((0.0, -4.6, 1.25), (0.0, 0.0, 1.2)), width, height, lens=35.0)
    env = Environment(color=world, strength=1.0) if world is not None else None
    return Scene(meshes, materials, lights, cam, name="path_test", environment=env)
