"""Temporal stability of what a viewer sees (`restircl report --flicker`): flicker and boiling per method.

Each method renders the animation path (ReSTIR and TAA history carried from frame to frame, as a viewport or an
animation shows it) for `warmup` frames, then `frames` consecutive output frames x_t are kept. With r_t the
converged reference of frame t (one image for a still camera), per pixel and over the kept frames:

- flicker   the temporal standard deviation of the error x_t - r_t (luminance): what changes from one frame to
            the next. For a still camera it is the standard deviation of the pixel itself.
- error     the root mean square of x_t - r_t: flicker plus any steady offset (bias, a smear that stays).
- ratio     mean flicker / mean error: 1 means the error is all frame-to-frame noise (what a denoiser or TAA can
            average away); near 0, a steady error (bias, ghosting); an estimator whose reuse correlates frames
            lowers it at equal error.
- level     mean output luminance over the kept frames / the reference's: below 1, the method darkens (a biased
            filter that removes bright samples shows it here first).
- boiling   pixels per kept frame (mean) that are a blotch: brighter than BOIL_K times the mean of their 8
            neighbours in x_t while not so in r_t (a small light seen directly is such a pixel in the reference
            too, and is not counted), and brighter than the reference by BOIL_K times the reference's
            neighbourhood mean. ReSTIR's spatial reuse turns one lucky sample into a cluster of such pixels.

Relative values use the reference's local level (luminance + 0.1), so bright and dark parts of an image count alike.
A moving camera uses a slowed copy of the scene's camera path (`slowed`), with a reference per kept frame.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import asdict, dataclass
from pathlib import Path

import numpy as np

from ...render.pipeline import Renderer
from ...scene.scene import Scene
from ...settings.table import Settings
from .methods import method_settings
from .reference import get_reference

BOIL_K = 4.0
LUMINANCE = np.array([0.2126, 0.7152, 0.0722])


@dataclass
class Flicker:
    method: str
    camera: str  # still | moving
    frames: int
    flicker: float  # mean over pixels of the temporal std of the relative error
    error: float  # mean over pixels of the RMS relative error
    ratio: float
    boiling: float  # boiling pixels per frame
    boiling_reference: float  # the same count in the reference (steady highlights excluded): 0 by construction
    level: float = 1.0  # mean output luminance / the reference's

    def row(self) -> str:
        return (f"| {self.method} | {self.camera} | {self.flicker:.4f} | {self.error:.4f} | {self.ratio:.2f} | "
                f"{self.boiling:.1f} | {self.level:.3f} |")


HEADER = ("| method | camera | flicker | error | flicker / error | boiling px / frame | level |\n"
          "|---|---|---|---|---|---|---|")


def _lum(img: np.ndarray) -> np.ndarray:
    return np.asarray(img, np.float64)[..., :3] @ LUMINANCE


def neighbour_mean(lum: np.ndarray) -> np.ndarray:
    """Mean of each pixel's 8 neighbours (edges: the neighbours that exist)."""
    p = np.pad(lum, 1)
    ones = np.pad(np.ones_like(lum), 1)
    h, w = lum.shape
    tot = sum(p[1 + dy:1 + dy + h, 1 + dx:1 + dx + w] for dy in (-1, 0, 1) for dx in (-1, 0, 1)) - lum
    cnt = sum(ones[1 + dy:1 + dy + h, 1 + dx:1 + dx + w] for dy in (-1, 0, 1) for dx in (-1, 0, 1)) - 1.0
    return tot / cnt


def boiling_mask(x: np.ndarray, ref: np.ndarray, k: float = BOIL_K) -> np.ndarray:
    """(H, W) bool: the blotches of image x against its reference (see the module docstring)."""
    lx, lr = _lum(x), _lum(ref)
    nx, nr = neighbour_mean(lx), neighbour_mean(lr)
    return (lx > k * nx + 1e-6) & ~(lr > k * nr) & (lx - lr > k * (nr + 1e-3))


def stats(method: str, camera: str, outputs: list[np.ndarray], refs: list[np.ndarray]) -> Flicker:
    """Flicker statistics of consecutive output frames against their references (one list entry per frame)."""
    x = np.stack([_lum(o) for o in outputs])
    r = np.stack([_lum(o) for o in refs])
    scale = np.mean(r, axis=0) + 0.1
    err = (x - r) / scale
    flick = float(np.mean(np.std(err, axis=0)))
    rms = float(np.mean(np.sqrt(np.mean(err * err, axis=0))))
    boil = float(np.mean([boiling_mask(o, rf).sum() for o, rf in zip(outputs, refs, strict=True)]))
    boil_ref = float(np.mean([boiling_mask(rf, rf).sum() for rf in refs]))
    level = float(x.mean() / r.mean()) if r.mean() > 0 else 1.0
    return Flicker(method, camera, len(outputs), flick, rms, flick / rms if rms > 0 else 0.0, boil, boil_ref, level)


def slowed(scene: Scene, steps: int) -> Scene:
    """A copy of `scene` whose camera takes `steps` frames for each frame of its path (positions interpolated
    linearly, orientations by normalised linear blend then re-orthonormalised), other animation held at frame 0."""
    import copy

    cam = scene.camera
    assert cam is not None
    m = cam.transforms
    n = (m.shape[0] - 1) * steps + 1
    out = np.empty((n, 4, 4))
    for f in range(n):
        a, t = divmod(f, steps)
        b = min(a + 1, m.shape[0] - 1)
        mix = m[a] * (1 - t / steps) + m[b] * (t / steps)
        u, _, vt = np.linalg.svd(mix[:3, :3])
        mix[:3, :3] = u @ vt
        out[f] = mix
    sc = copy.copy(scene)
    sc.camera = copy.copy(cam)
    sc.camera.transforms = out
    sc.frame_count = n
    return sc


def run_flicker(scene: Scene, methods: list[str], frames: int = 16, warmup: int = 16, moving: bool = False,
                steps: int = 8, device=None, cache_dir: Path | None = None, reference_seconds: float = 20.0,
                base: Settings | None = None, seed: int = 4242,
                log: Callable[[str], None] = print) -> list[Flicker]:
    """Flicker statistics of each method on a still camera (frame 0 held) or a slowed moving camera."""
    if moving:
        scene = slowed(scene, steps)
        first = 0
        if scene.frames < warmup + frames:
            raise ValueError(f"flicker: {scene.name} has {scene.frames} slowed frames, fewer than "
                             f"{warmup} + {frames}")
        kept = list(range(warmup, warmup + frames))
        refs = [get_reference(scene, f, reference_seconds, device=device, cache_dir=cache_dir, log=log).image
                for f in kept]
    else:
        first = 0
        kept = [first] * frames
        refs = [get_reference(scene, first, reference_seconds, device=device, cache_dir=cache_dir, log=log).image]
        refs = refs * frames
    out = []
    for name in methods:
        r = Renderer(scene, method_settings(name, base, seed), device)
        seq = list(range(warmup)) if moving else [first] * warmup
        for f in seq:
            r.render_frame(f, aovs=False)
        outputs = [r.render_frame(f, aovs=False).color for f in kept]
        res = stats(name, "moving" if moving else "still", outputs, refs)
        out.append(res)
        log(res.row())
    return out


def as_json(results: list[Flicker]) -> list[dict]:
    return [asdict(r) for r in results]
