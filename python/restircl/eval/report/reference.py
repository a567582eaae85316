"""Converged reference images for `restircl report`, cached on disk.

References are computed once and cached, keyed by the scene's content (the file of its key form, scene/canonical.py:
an export that lists the same triangles in another order, or whose normals differ by float rounding, gives the same
key), the frame, the device and a digest of the reference estimator's own first two frames (a probe: an edit of the
code that changes what the reference estimator renders gives another key, so a stale reference is never reused; an
edit that leaves it bit-identical, e.g. to the ReSTIR kernels, keeps the cache). The probe is rendered from the key
form, so it does not see the order either; the reference from the canonical form. A reference is an unbiased
estimator run long: exhaustive over the lights (`reference`) when the scene has few, else RIS with 32 candidates;
its own remaining error is estimated from its half buffers and written into the report.
"""

from __future__ import annotations

import hashlib
import json
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ...render.pipeline import Renderer
from ...scene.canonical import canonical_scene, key_scene
from ...scene.scene import Scene
from ...settings.table import Settings


def estimator_digest(probe: np.ndarray, device_label: str) -> str:
    """Digest of a probe image (the reference estimator's first frames, bit for bit) and of the device."""
    h = hashlib.sha256()
    h.update(device_label.encode())
    h.update(np.ascontiguousarray(probe, dtype=np.float32).tobytes())
    return h.hexdigest()[:12]


def scene_digest(scene: Scene, cache_dir: Path) -> str:
    """Digest of the scene's content: the file of its key form (scene/canonical.py key_scene: the same for any order
    of its triangles)."""
    tmp = cache_dir / f"scene.{time.monotonic_ns()}.tmp.npz"
    key_scene(scene).save(tmp)
    try:
        return hashlib.sha256(tmp.read_bytes()).hexdigest()[:16]
    finally:
        tmp.unlink()


@dataclass
class Reference:
    image: np.ndarray  # (H, W, 3) float32
    method: str
    frames: int
    seconds: float
    est_rel_mse: float | None  # its own remaining error, estimated from its half buffers
    path: str


def default_cache_dir() -> Path:
    return Path.home() / ".cache" / "restircl"


def emissive_triangle_count(scene: Scene, frame: int = 0) -> int:
    """The emissive triangles (each a light): the exhaustive reference loops over every one of them."""
    emissive = np.array([m.is_emissive for m in scene.materials], bool)
    if not emissive.any():
        return 0
    return int(emissive[scene.world_triangles(frame).material].sum())


#: the Light Paths a reference copies from the settings it is a reference for
LIGHT_PATHS = ("max_bounces", "diffuse_bounces", "glossy_bounces", "min_light_bounces", "clamp_direct",
               "clamp_indirect", "light_threshold")


def overrides_tag(overrides: dict | None) -> str:
    """The part of a cache key that names the Settings overrides of a reference (empty without any: the keys of
    references of direct light stay as they were)."""
    return "".join(f"_{k}={overrides[k]}" for k in sorted(overrides or {}))


def get_reference(scene: Scene, frame: int = 0, seconds_hint: float = 60.0, frames: int | None = None, device=None,
                  cache_dir: Path | None = None, log: Callable[[str], None] = print,
                  overrides: dict | None = None, paths: Settings | None = None) -> Reference:
    """A converged image of `scene` at `frame`, cached on disk (see the module docstring). `overrides`: Settings
    fields of the estimator beside its method (the Light Paths of `restircl compare --max-bounces`: with bounces the
    path pass adds the bounced light to the reference estimator's direct light); they are part of the key. `paths`:
    settings whose Light Paths (LIGHT_PATHS) are added to `overrides` (None: direct light only)."""
    cache_dir = Path(cache_dir or default_cache_dir())
    cache_dir.mkdir(parents=True, exist_ok=True)
    n_lights = len(scene.lights) + emissive_triangle_count(scene, frame)
    overrides = {**({name: getattr(paths, name) for name in LIGHT_PATHS} if paths is not None else {}),
                 **(overrides or {})}
    settings = Settings(method="reference" if n_lights <= 16 else "ris", candidates=32, seed=987654,
                        **overrides).validate()
    # the probe, and so the key, must not see the order of the triangles nor the rounding of their normals
    pr = Renderer(key_scene(scene), settings, device)
    probe = pr.render_still(frame, 2).color
    key = (f"{scene_digest(scene, cache_dir)}_{estimator_digest(probe, pr.device.label)}_f{frame}"
           f"{overrides_tag(overrides)}")
    path = cache_dir / f"reference_{scene.name}_{key}.npy"
    meta_path = path.with_suffix(".json")
    if path.exists() and meta_path.exists():
        meta = json.loads(meta_path.read_text())
        log(f"reference: cached {path}")
        return Reference(np.load(path), meta["method"], meta["frames"], meta["seconds"], meta["est_rel_mse"],
                         str(path))
    r = Renderer(canonical_scene(scene), settings, pr.device)
    if frames is None:
        r.render_still(frame, 1)  # its first uploads out of the timing
        t0 = time.perf_counter()
        r.render_still(frame, 4)
        per = (time.perf_counter() - t0) / 4
        frames = int(min(max(seconds_hint / max(per, 1e-6), 256), 1 << 17))
    log(f"reference: {settings.method} x {frames} frames ...")
    t0 = time.perf_counter()
    out = r.render_still(frame, frames)
    seconds = time.perf_counter() - t0
    img = out.color[..., :3].astype(np.float32)
    np.save(path, img)
    meta = {"method": settings.method, "frames": frames, "seconds": seconds, "est_rel_mse": out.error_estimate,
            "scene": scene.name, "frame": frame, "overrides": overrides or {}}
    meta_path.write_text(json.dumps(meta, indent=1))
    est = f"{out.error_estimate:.2e}" if out.error_estimate is not None else "n/a"
    log(f"reference: saved {path} ({seconds:.0f} s, its estimated relMSE {est})")
    return Reference(img, settings.method, frames, seconds, out.error_estimate, str(path))

