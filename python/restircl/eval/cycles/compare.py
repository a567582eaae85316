"""Ours against Cycles at equal wall time on the tuning scenes (`restircl compare`, issue 23).

Per scene kind (eval/scenes/held_out.py; the validation scenes of global illumination, eval/scenes/validation.py, by
their kinds too: eval/scenes/kinds.py) and per wall-time budget (1, 4, 16 s), each method renders a still image from
scratch and its relMSE is measured against a high-sample Cycles image. Every render, ours and Cycles', the timed
ones, the references and the calibration, has the same Light Paths (eval/cycles/paths.py: direct light only by
default, or Max Bounces N with Cycles' diffuse and glossy limits, unclamped, no light threshold):

- cycles: Cycles, direct light only (cycles.direct_only: bounces 0, no light threshold, box filter 1 px, no
  adaptive sampling, denoising or clamping), on `threads` threads, timed as the wall clock of
  bpy.ops.render.render (scene sync, render, writing its EXR), as the user sees it. Cycles' own time limit counts
  its render only, so it is set to the budget less the fixed cost of a call (sync, set-up, writing), measured by a
  calibration of the same scene. Where that fixed cost leaves no time for one sample (an HDRI world: Cycles
  builds its importance map in every call's sync, seconds on 2 cores), Cycles renders one sample and the row says
  how long that took (`over_budget`): it cannot meet the budget, and its error is that of its first image.
- default: `Settings()` (the add-on's defaults come from the same table: ReSTIR with temporal and spatial reuse,
  what F12 used before still_method) through `Renderer(...).render_still`, the wall clock from before the
  Renderer is made (BVH build, upload; the kernels are already compiled, as on any F12 after the first) to the
  image read back, stopped when the budget is spent.
- auto: our still path as F12 uses it now: `still_settings(Settings(), scene)` (render/still_method.py).
- ris and the other candidates for the still path: the same with their overrides of `Settings()` (OURS).

The reference is two independent Cycles renders of `reference_spp` samples each (2 x 1024 as in the issue),
averaged and cached on disk (keyed by the scene file's content, the resolution, the sample count, the Light Paths and
Blender's version); their difference estimates its own remaining relMSE. Before the timing, a converged render of ours
(report_reference.get_reference, cached) is compared with it: relMSE and the ratio of the image sums, so a
disagreement of the two renderers (units, geometry) cannot pass for an error of the estimator.
"""

from __future__ import annotations

import hashlib
import json
import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np

from ...render.half_error import rel_mse_from_halves
from ...render.pipeline import Renderer
from ...render.still_method import still_settings
from ...scene.scene import Scene
from ...settings.table import Settings
from ..metrics import rel_mse
from ..report.reference import default_cache_dir, get_reference, scene_digest
from ..scenes import user_scene
from ..scenes.held_out import HEIGHT, KINDS, WIDTH
from ..scenes.kinds import scene_of_kind
from . import bridge as cycles
from .paths import DIRECT, LightPaths
from .world import set_world_map

BUDGETS = (1.0, 4.0, 16.0)
REFERENCE_SPP = 1024
#: a render that took more than this times its budget is marked over_budget (its ratio is not at equal time)
OVER_BUDGET = 1.25
#: our methods: Settings overrides on the defaults (F12's method and settings)
OURS: dict[str, dict] = {
    "default": {},
    "ris": {"method": "ris"},
    # candidates for the still path (render/still_method.py): RIS with BSDF candidates, and ReSTIR variants meant for
    # convergence: spatial reuse of fresh reservoirs every frame, temporal reuse with a short history
    "ris_bsdf": {"method": "ris", "bsdf_sampling": "on"},
    # RIS with a BSDF sample of its own shadow ray, by MIS (direct/bsdf_mis.h), with 8 and 4 light candidates
    "ris_mis": {"method": "ris", "bsdf_mis_sample": True},
    "ris_mis4": {"method": "ris", "bsdf_mis_sample": True, "candidates": 4},
    "spatial": {"temporal": False},
    "spatial_bsdf": {"temporal": False, "bsdf_sampling": "on"},
    "short_history": {"m_cap": 2.0},
    "auto": {},  # through still_settings (STILL_PATH)
    # F12's still path with random numbers (sampler random: F12 before the Sobol sampler), and RIS with the Sobol
    # sampler at 2 and 8 light candidates (the measurement behind still_method's FEW_LIGHTS rule)
    "auto_random": {"sampler": "random"},
    "ris_c2": {"method": "ris", "candidates": 2},
    "ris_c8": {"method": "ris", "candidates": 8},
    # F12's still path with the light array's pick instead of the per-pixel table (lights/pick_table.py), and RIS
    # with the table at 1 and 4 light candidates
    "auto_array": {"light_proposal": "array"},
    "ris_c1": {"method": "ris", "candidates": 1},
    "ris_c4": {"method": "ris", "candidates": 4},
    # F12's still path with solid-angle sampling of area lights (everywhere; where they look large)
    "auto_solid": {"area_sampling": "solid_angle"},
    "auto_solid_near": {"area_sampling": "auto"},
    # the light tree as the candidates' proposal (lights/tree.py)
    "default_tree": {"light_proposal": "tree"},
    "ris_tree": {"method": "ris", "light_proposal": "tree"},
    # F12's still path with NEE at path vertices from the light array (the bounced light's pick before the tree)
    "auto_path_array": {"path_light_pick": "array"},
    # the factors in which Cycles' direct light differs from F12's still path on few lights, one at a time: the
    # light tree as the candidates' proposal (Cycles samples its tree), a BSDF sample of its own shadow ray combined
    # with the light sample by MIS (Cycles' light and BSDF sampling), solid-angle sampling of every area light
    "auto_tree": {"light_proposal": "tree"},
    "auto_mis": {"bsdf_mis_sample": True},
    # F12's still path with more BSDF-sampled candidates at glossy pixels (a glint of a small lamp in rough metal is
    # found by a BSDF candidate alone: docs/measurements/temporal-stability.md, "Where the flythrough's fireflies
    # come from")
    "auto_bsdf2": {"bsdf_candidates": 2},
    "auto_bsdf4": {"bsdf_candidates": 4},
    # F12's still path with 1 and 2 light candidates at the camera vertex (with bounces, the direct light's share of
    # a frame's variance is small beside its share of the frame's time)
    "auto_c1": {"candidates": 1},
    "auto_c2": {"candidates": 2},
    "auto_c4": {"candidates": 4},
}
#: Cycles as the timed renders' opponent, and with one of its own factors switched off (the scene's Cycles settings
#: changed for its renders): its light tree, which also splits a light sample into several where the tree's
#: importance bound is loose
CYCLES: dict[str, dict] = {"cycles": {}, "cycles_no_tree": {"use_light_tree": False}}
#: our methods whose settings go through still_settings, as F12's and the CLI's still renders do
STILL_PATH = ("auto", "auto_random", "auto_array", "auto_solid", "auto_solid_near", "auto_path_array", "auto_tree",
              "auto_mis", "auto_bsdf2", "auto_bsdf4", "auto_c1", "auto_c2", "auto_c4")
#: what a comparison runs unless told otherwise; any of OURS may be named
METHODS = ("cycles", "default", "auto", "ris")
ALL_METHODS = (*CYCLES, *OURS)
CALIBRATION_SPP = 16


@dataclass
class Row:
    kind: str
    method: str
    budget_s: float
    rep: int
    seconds: float  # wall clock of the whole render call
    setup_s: float  # of which before the first sample: Renderer construction (ours), the 0-sample call (Cycles)
    samples: int
    rel_mse: float
    over_budget: bool = False  # took more than OVER_BUDGET x budget (Cycles' fixed cost above the budget)


@dataclass
class CyclesReference:
    image: np.ndarray  # (H, W, 3) float32: the mean of the two halves
    spp: int  # samples of each half
    seconds: float  # render time of both halves
    est_rel_mse: float  # its own remaining relMSE, from the difference of the halves
    sum_rel_std: float  # relative standard deviation of the image's sum, from the difference of the halves
    path: str


@dataclass
class KindResult:
    kind: str
    reference: CyclesReference
    agreement: dict  # our converged image against the reference: rel_mse, sum_ratio, our image's frames/estimate
    rows: list[Row] = field(default_factory=list)
    cycles_calibration: dict = field(default_factory=dict)  # seconds per sample, fixed seconds per call


def halves_rel_mse(a: np.ndarray, b: np.ndarray) -> float:
    """relMSE of the mean of two independent estimates a, b, estimated from them: per pixel the variance of the
    mean is (a - b)^2 / 4, relative to r^2 + 0.01 as rel_mse is, with r^2 by the still render's rule that a
    firefly in one half cannot inflate (render/half_error.py robust_r2)."""
    a, b = np.asarray(a, np.float64)[..., :3], np.asarray(b, np.float64)[..., :3]
    return rel_mse_from_halves(a, b, 1, 1)


def cycles_reference(kind: str, scene: Scene, bpy_scene, spp: int = REFERENCE_SPP, threads: int = 2,
                     cache_dir: Path | None = None, log: Callable[[str], None] = print,
                     paths: LightPaths = DIRECT) -> CyclesReference:
    """Two Cycles renders of `spp` samples (seeds 101, 102) with the Light Paths `paths`, averaged; cached on disk
    under a name and key that carry the Light Paths (a direct-light reference is never one with bounces)."""
    import bpy

    cache_dir = Path(cache_dir or default_cache_dir())
    cache_dir.mkdir(parents=True, exist_ok=True)
    cam = scene.camera
    assert cam is not None
    key = f"{scene_digest(scene, cache_dir)}_{bpy.app.version_string}{paths.tag}"
    h = hashlib.sha256(key.encode()).hexdigest()[:12]
    path = cache_dir / f"cycles_reference_{kind}_{cam.width}x{cam.height}_2x{spp}{paths.tag}_{h}.npy"
    meta_path = path.with_suffix(".json")
    if path.exists() and meta_path.exists():
        meta = json.loads(meta_path.read_text())
        log(f"{kind}: Cycles reference cached {path}")
        return CyclesReference(np.load(path), spp, meta["seconds"], meta["est_rel_mse"], meta["sum_rel_std"],
                               str(path))
    log(f"{kind}: Cycles reference, 2 x {spp} samples, {paths.describe()} ...")
    halves = [cycles.render(bpy_scene, samples=spp, seed=seed, threads=threads, paths=paths.cycles())
              for seed in (101, 102)]
    img = ((halves[0].image + halves[1].image) / 2).astype(np.float32)
    est = halves_rel_mse(halves[0].image, halves[1].image)
    # pixels are independent estimates: the variance of the sum is the sum of the pixels' (a - b)^2 / 4
    diff = halves[0].image.astype(np.float64) - halves[1].image
    sum_std = float(np.sqrt(np.sum(diff * diff) / 4) / max(float(img.sum()), 1e-30))
    seconds = sum(r.total_seconds for r in halves)
    np.save(path, img)
    meta_path.write_text(json.dumps({"kind": kind, "spp": spp, "seconds": seconds, "est_rel_mse": est,
                                     "sum_rel_std": sum_std, "light_paths": paths.overrides()}, indent=1))
    log(f"{kind}: Cycles reference saved {path} ({seconds:.0f} s, its estimated relMSE {est:.2e})")
    return CyclesReference(img, spp, seconds, est, sum_std, str(path))


def agreement(scene: Scene, ref: CyclesReference, device=None, seconds: float = 60.0,
              cache_dir: Path | None = None, log: Callable[[str], None] = print, paths: LightPaths = DIRECT) -> dict:
    """Our converged render (cached) with the Light Paths `paths` against the Cycles reference: relMSE and the
    ratio of the image sums."""
    ours = get_reference(scene, 0, seconds, device=device, cache_dir=cache_dir, log=log, overrides=paths.overrides())
    cyc = ref.image
    return {"rel_mse": rel_mse(ours.image, cyc), "sum_ratio": float(ours.image.sum() / max(cyc.sum(), 1e-30)),
            "ours_method": ours.method, "ours_frames": ours.frames, "ours_est_rel_mse": ours.est_rel_mse,
            "ours_seconds": ours.seconds, "cycles_est_rel_mse": ref.est_rel_mse}


def calibrate_cycles(bpy_scene, threads: int = 2, paths: LightPaths = DIRECT) -> dict:
    """Seconds per sample and fixed seconds of a render call (sync, set-up, writing), with the Light Paths `paths`,
    after a warm-up call that loads the kernels. The seconds per sample come from Cycles' own render times (its
    metadata, without the synchronisation) of CALIBRATION_SPP and 8 x CALIBRATION_SPP samples: the wall clock of
    whole calls carries a synchronisation that varies by a few tenths of a second from call to call, as much as a
    few samples' time, and Cycles' first samples cost more than its later ones, so two short calls' wall clocks
    overstated the seconds per sample (outdoor with 4 bounces: 2.4x, the samples of a timed render understated as
    much). The fixed cost is a call's wall clock less its render time."""
    p = paths.cycles()
    cycles.render(bpy_scene, samples=1, threads=threads, paths=p)
    one = cycles.render(bpy_scene, samples=1, threads=threads, paths=p)
    few = cycles.render(bpy_scene, samples=CALIBRATION_SPP, threads=threads, paths=p)
    many = cycles.render(bpy_scene, samples=8 * CALIBRATION_SPP, threads=threads, paths=p)
    per = max((many.render_seconds - few.render_seconds) / (7 * CALIBRATION_SPP), 1e-6)
    return {"seconds_per_sample": per, "fixed_seconds": max(one.total_seconds - one.render_seconds, 0.0)}


def time_cycles(bpy_scene, budget: float, calibration: dict, seed: int, threads: int = 2,
                paths: LightPaths = DIRECT) -> tuple[np.ndarray, float, int]:
    """A Cycles render that fills `budget` seconds of wall clock: Cycles' time limit set to the budget less the
    calibrated fixed cost of a call, so the render adapts to the machine's load as it runs (a sample count fixed
    in advance missed the budget by 2x when other jobs came and went). (image, seconds, samples); the samples
    are estimated from Cycles' render time and the calibrated seconds per sample (its metadata gives the sample
    limit, not the count, when a time limit stops it).

    Where the fixed cost leaves less than one sample's time, a time limit would be clamped to nothing and every
    budget would get the same one-sample image (the flat Cycles curve of the first `sky` comparison): Cycles
    renders exactly one sample, and the caller marks the row over budget by its wall clock."""
    limit = budget - calibration["fixed_seconds"]
    if limit < calibration["seconds_per_sample"]:
        res = cycles.render(bpy_scene, samples=1, seed=seed, threads=threads, paths=paths.cycles())
        return res.image, res.total_seconds, 1
    res = cycles.render(bpy_scene, seconds=limit, seed=seed, threads=threads, paths=paths.cycles())
    spp = max(1, round(res.render_seconds / calibration["seconds_per_sample"]))
    return res.image, res.total_seconds, spp


@contextmanager
def cycles_variant(sc, method: str) -> Iterator[None]:
    """Scene sc's Cycles settings as the Cycles method `method` (CYCLES) has them, restored afterwards."""
    old = {k: getattr(sc.cycles, k) for k in CYCLES[method]}
    for k, v in CYCLES[method].items():
        setattr(sc.cycles, k, v)
    try:
        yield
    finally:
        for k, v in old.items():
            setattr(sc.cycles, k, v)


def ours_settings(method: str, scene: Scene, paths: LightPaths = DIRECT) -> Settings:
    """The settings of one of our methods (OURS) for `scene`, with the Light Paths `paths`."""
    s = Settings(**OURS[method], **paths.overrides()).validate()
    return still_settings(s, scene) if method in STILL_PATH else s


def time_ours(scene: Scene, settings: Settings, budget: float, device=None) -> tuple[np.ndarray, float, float, int]:
    """A still render from scratch stopped when `budget` seconds have passed: (image, seconds, setup seconds,
    samples). A frame's first upload waits for the frame before, and the render's last read for all of them, so
    the clock sees the work done (at most one frame past the budget)."""
    t0 = time.perf_counter()
    r = Renderer(scene, settings, device)
    setup = time.perf_counter() - t0
    out = r.render_still(0, 1 << 30, should_stop=lambda: time.perf_counter() - t0 >= budget)
    img = out.color[..., :3].copy()
    return img, time.perf_counter() - t0, setup, int(out.samples)


def scene_pair(kind: str, width: int, height: int) -> tuple[Scene, object]:
    """(restircl Scene, bpy scene) of `kind`: a kind built in Blender (user_scene.py) as it is and as the add-on
    exports it; any other written to bpy from our Scene."""
    if kind in user_scene.KINDS:
        return user_scene.user_scene(width, height)
    scene = scene_of_kind(kind, width, height)
    return scene, cycles.to_bpy(scene)


def run_kind(kind: str, budgets=BUDGETS, reps: int = 3, methods=METHODS, width: int | None = None,
             height: int | None = None, reference_spp: int = REFERENCE_SPP, threads: int = 2, device=None,
             cache_dir: Path | None = None, agreement_seconds: float = 60.0, cycles_world_map: int = 0,
             log: Callable[[str], None] = print, paths: LightPaths = DIRECT) -> KindResult:
    """Every method at every budget, `reps` times (in turn: rep 0 of every method and budget, then rep 1, ...,
    so a change of the machine's load spreads over all of them), every render with the Light Paths `paths`.
    cycles_world_map: the timed Cycles renders' world importance map (cycles_world.set_world_map: 0 = Blender's
    default; the reference keeps the default)."""
    scene, sc = scene_pair(kind, width or WIDTH, height or HEIGHT)
    ref = cycles_reference(kind, scene, sc, reference_spp, threads, cache_dir, log, paths)
    agree = agreement(scene, ref, device, agreement_seconds, cache_dir, log, paths)
    log(f"{kind}: ours converged against Cycles: relMSE {agree['rel_mse']:.2e}, sum ratio {agree['sum_ratio']:.4f}")
    result = KindResult(kind, ref, agree)
    set_world_map(sc, cycles_world_map)
    calibration = {}
    for m in (m for m in methods if m in CYCLES):
        with cycles_variant(sc, m):
            calibration[m] = calibrate_cycles(sc, threads, paths)
    if calibration:
        result.cycles_calibration = dict(calibration.get("cycles", {}))
        result.cycles_calibration.update({f"{m} {k}": v for m in calibration if m != "cycles"
                                          for k, v in calibration[m].items()})
    settings = {m: ours_settings(m, scene, paths) for m in methods if m in OURS}
    for s in settings.values():  # compile the kernels once (F12 after the first)
        Renderer(scene, s, device).render_still(0, 2)
    for rep in range(reps):
        for budget in budgets:
            for m in methods:
                if m in CYCLES:
                    cal = calibration[m]
                    with cycles_variant(sc, m):
                        img, secs, spp = time_cycles(sc, budget, cal, seed=1000 + rep, threads=threads, paths=paths)
                    setup = cal["fixed_seconds"]
                else:
                    settings[m].seed = 1000 + rep
                    img, secs, setup, spp = time_ours(scene, settings[m], budget, device)
                row = Row(kind, m, budget, rep, secs, setup, spp, rel_mse(img, ref.image),
                          secs > OVER_BUDGET * budget)
                result.rows.append(row)
                log(f"{kind:<7} {m:<8} budget {budget:5.1f} s rep {rep}: {secs:6.2f} s, {spp:5d} samples, "
                    f"relMSE {row.rel_mse:.3e}{'  (over budget)' if row.over_budget else ''}")
    return result


def equal_samples(kind: str, samples: int = 64, methods=METHODS, width: int | None = None, height: int | None = None,
                  reference_spp: int = REFERENCE_SPP, threads: int = 2, device=None, cache_dir: Path | None = None,
                  log: Callable[[str], None] = print, paths: LightPaths = DIRECT) -> dict[str, dict]:
    """Every method at the same number of samples (Cycles spp, our frames): {method: {rel_mse, seconds}}. The error
    at equal samples does not depend on the machine's load, and the seconds per sample measured in the same run
    give the cost side: together they separate the estimator from the speed. Needs the cached reference."""
    scene, sc = scene_pair(kind, width or WIDTH, height or HEIGHT)
    ref = cycles_reference(kind, scene, sc, reference_spp, threads, cache_dir, log, paths)
    out = {}
    for m in methods:
        if m in CYCLES:
            with cycles_variant(sc, m):
                cycles.render(sc, samples=1, threads=threads, paths=paths.cycles())
                res = cycles.render(sc, samples=samples, seed=7, threads=threads, paths=paths.cycles())
            img, secs = res.image, res.total_seconds
        else:
            r = Renderer(scene, replace(ours_settings(m, scene, paths), seed=7), device)
            r.render_still(0, 2)
            t0 = time.perf_counter()
            img = r.render_still(0, samples).color[..., :3]
            secs = time.perf_counter() - t0
        out[m] = {"rel_mse": rel_mse(img, ref.image), "seconds": secs, "samples": samples}
        log(f"{kind:<7} {m:<8} {samples} samples: {secs:6.2f} s, relMSE {out[m]['rel_mse']:.3e}")
    return out


def run(kinds=KINDS, **kwargs) -> list[KindResult]:
    return [run_kind(k, **kwargs) for k in kinds]


__all__ = ["ALL_METHODS", "BUDGETS", "CYCLES", "METHODS", "OURS", "OVER_BUDGET", "STILL_PATH", "CyclesReference",
           "KindResult", "Row", "agreement", "calibrate_cycles", "cycles_reference", "cycles_variant", "equal_samples",
           "halves_rel_mse", "ours_settings", "run", "run_kind", "scene_pair", "time_cycles", "time_ours"]
