"""Shared helpers of the rendering tests: small test scenes, per-frame sample collection, and the values of
constants on the device."""

from __future__ import annotations

import math

import numpy as np
from restircl import Camera, Light, Material, Mesh, Renderer, Scene, Settings, look_at, scenes, translation
from scipy import stats


def mixed_lights_scene(width: int = 32, height: int = 24) -> Scene:
    """A floor and a wall lit by every light type, with powers spanning 1e-6..1e6, a light touching the floor,
    a grazing sun, lights below the floor (no contribution) and an occluding block."""
    fv, ft = scenes.quad(4, 4)
    wv, wt = scenes.quad(4, 2)
    wall = wv @ np.array([[1, 0, 0], [0, 0, 1], [0, -1, 0]]).T + (0, 1.5, 1)  # wall in the XZ plane at y = 1.5
    bv, bt = scenes.box((0.4, 0.4, 0.6))
    lv, lt = scenes.quad(0.1, 0.1)  # two emissive triangles each, two-sided
    materials = [
        Material("floor", (0.7, 0.7, 0.7)),
        Material("wall", (0.4, 0.6, 0.8)),
        Material("lamp", (0, 0, 0), (1.0, 0.8, 0.6), 40.0),
        Material("faint", (0, 0, 0), (0.5, 1.0, 0.5), 1e-6),
    ]
    meshes = [
        Mesh("floor", fv, ft, 0),
        Mesh("wall", wall, wt, 1),
        Mesh("block", bv + (0.6, 0.3, 0.3), bt, 0),
        Mesh("lamp", lv @ np.array([[1, 0, 0], [0, 0, 1], [0, 1, 0]]).T + (-0.8, 0.6, 0.5), lt, 2),
        Mesh("faint", lv + (0.9, -0.9, 0.3), lt, 3),
    ]
    lights = [
        Light("big", "point", (1, 1, 1), 1e6, translation(0.0, -1.2, 25.0), radius=0.3, soft_falloff=False),
        Light("tiny", "point", (1, 0.5, 0.2), 1e-6, translation(0.5, 0.5, 0.2)),
        Light("soft", "point", (0.6, 0.7, 1.0), 80.0, translation(-1.0, -0.5, 0.8), radius=0.2),
        Light("spot", "spot", (1, 1, 1), 300.0, look_at((1.0, -1.0, 1.5), (0.8, -0.6, 0)), spot_size=0.6,
              spot_blend=0.3),
        Light("touching", "area", (1, 1, 1), 5.0, translation(-1.2, -1.2, 0.03), shape="SQUARE", size=0.3),
        Light("disk", "area", (1, 0.9, 0.8), 60.0, translation(1.2, 1.0, 1.2), shape="DISK", size=0.4),
        Light("grazing_sun", "sun", (1, 1, 0.9), 2.0, look_at((0, -100, 1.745), (0, 0, 0)), angle=0.02),
        Light("below", "point", (1, 1, 1), 500.0, translation(0, 0, -0.5)),
        Light("below_area", "area", (1, 1, 1), 500.0, translation(0.3, 0.2, -0.3) @ np.diag([1, -1, -1, 1]),
              shape="SQUARE", size=1.0),
    ]
    cam = Camera(look_at((0.0, -3.2, 2.6), (0.0, 0.1, 0.3)), width, height, lens=28.0)
    return Scene(meshes, materials, lights, cam, name="mixed_lights")


def below_only_scene(width: int = 16, height: int = 12) -> Scene:
    """Every light is behind the lit surface: the image must be exactly 0 (not NaN)."""
    fv, ft = scenes.quad(4, 4)
    lights = [
        Light("below", "point", (1, 1, 1), 500.0, translation(0, 0, -0.5), radius=0.1),
        Light("below_area", "area", (1, 1, 1), 500.0, translation(0.3, 0.2, -0.3) @ np.diag([1, -1, -1, 1]),
              shape="SQUARE", size=1.0),
        Light("below_sun", "sun", (1, 1, 1), 3.0, look_at((0, 0, -1), (0, 0, 0)), angle=0.1),
    ]
    cam = Camera(look_at((0.0, -3.0, 2.0), (0.0, 0.0, 0.0)), width, height, lens=35.0)
    return Scene([Mesh("floor", fv, ft, 0)], [Material("floor", (0.7, 0.7, 0.7))], lights, cam, name="below")


def occluder_scene(width: int = 32, height: int = 24) -> Scene:
    """Many small lights above a floor, partly hidden behind blocks: visibility differs between neighbours."""
    rng = np.random.default_rng(3)
    fv, ft = scenes.quad(6, 6)
    parts_v, parts_t = [], []
    base = 0
    for x, y in [(-1.0, 0.0), (0.5, -0.5), (1.2, 0.8), (-0.3, 1.2)]:
        bv, bt = scenes.box((0.5, 0.5, 1.0))
        parts_v.append(bv + (x, y, 0.5))
        parts_t.append(bt + base)
        base += len(bv)
    lights = [Light(f"p{k}", "point", tuple(rng.uniform(0.3, 1.0, 3)), float(np.exp(rng.uniform(0, 5))),
                    translation(*rng.uniform(-2.5, 2.5, 2), rng.uniform(0.3, 1.8)), radius=0.05)
              for k in range(40)]
    cam = Camera(look_at((0.0, -4.0, 3.0), (0.0, 0.0, 0.3)), width, height, lens=30.0)
    return Scene([Mesh("floor", fv, ft, 0), Mesh("blocks", np.concatenate(parts_v), np.concatenate(parts_t), 0)],
                 [Material("grey", (0.7, 0.7, 0.7))], lights, cam, name="occluders")


def collect(scene: Scene, settings: Settings, frames: int, device=None, warmup: int = 0) -> np.ndarray:
    """(frames, H, W, 3) noisy per-frame estimates of a still camera (ReSTIR keeps its history between them)."""
    r = Renderer(scene, settings, device)
    for _ in range(warmup):
        r.render_frame(0, still=True)
    return np.stack([r.render_frame(0, still=True).noisy for _ in range(frames)]).astype(np.float64)


def batch_stats(samples: np.ndarray, batches: int = 16) -> tuple[np.ndarray, np.ndarray]:
    """Mean and standard error from batch means (robust to heavy-tailed per-frame samples)."""
    n = samples.shape[0] // batches * batches
    b = samples[:n].reshape(batches, n // batches, *samples.shape[1:]).mean(axis=1)
    return b.mean(axis=0), b.std(axis=0, ddof=1) / math.sqrt(batches)


def constant(sigma: np.ndarray, mean: np.ndarray) -> np.ndarray:
    """Pixels whose estimate does not vary (a light the camera sees, black): a standard error of rounding only,
    far below any Monte Carlo noise. Comparing them by a t-statistic would weigh rounding differences."""
    return sigma <= 1e-9 * np.abs(mean)


def allowed_outliers(n: int, batches: int = 16, z: float = 4.0) -> int:
    """How many of n independent t-statistics (batches - 1 dof) may exceed z: the expected count plus four of
    its standard deviations (binomial), plus one."""
    p = 2 * stats.t.sf(z, batches - 1)
    return int(math.ceil(n * p + 4 * math.sqrt(n * p * (1 - p)) + 1))


def assert_mean_equals_reference(samples: np.ndarray, reference: np.ndarray, batches: int, label: str) -> None:
    """The per-frame estimates `samples` (frames, H, W, 3) and the exhaustive `reference` agree in the mean: per
    pixel (luminance) within 4 standard errors of the batch means but for the allowed outliers, exactly where
    neither varies, and over the image per channel."""
    m, se = batch_stats(luminance(samples), batches)
    mr, ser = batch_stats(luminance(reference), batches)
    sigma = np.sqrt(se**2 + ser**2)
    exact = constant(sigma, mr)
    z = np.abs(m - mr) / np.where(exact, 1.0, sigma)
    assert np.all(np.abs(m - mr)[exact] <= 1e-5 * np.abs(mr[exact]) + 1e-12), label
    n_out = int((z[~exact] > 4).sum())
    mi, si = batch_stats(samples.mean(axis=(1, 2)), batches)
    mr2, sr2 = batch_stats(reference.mean(axis=(1, 2)), batches)
    print_power(label, mi / mr2 - 1.0, np.sqrt(si**2 + sr2**2) / mr2)
    print(f"{label}: {n_out} pixels beyond 4 standard errors, allowed {allowed_outliers(int((~exact).sum()), batches)}")
    assert n_out <= allowed_outliers(int((~exact).sum()), batches), (label, "outliers", n_out,
                                                                     np.sort(z.ravel())[-5:])
    assert np.all(np.abs(mi - mr2) <= 4 * np.sqrt(si**2 + sr2**2)), (label, "image means", mi, mr2, si, sr2)


def print_power(label: str, bias, se) -> None:
    """The image mean's relative bias and the smallest relative bias its 4-standard-error bound rejects: the power
    of the check, in the test's output (pytest -s, or the captured output of a failure)."""
    b, e = np.atleast_1d(bias), np.atleast_1d(se)
    print(f"{label}: image mean {' '.join(f'{x:+.2%}' for x in b)}, rejects |bias| > "
          f"{' '.join(f'{4 * x:.2%}' for x in e)}")


def rel_mse(x: np.ndarray, ref: np.ndarray) -> float:
    """mean of (x - r)^2 / (r^2 + 0.01), over pixels and channels (the issue's relMSE)."""
    return float(np.mean((x - ref) ** 2 / (ref * ref + 0.01)))


def luminance(x: np.ndarray) -> np.ndarray:
    return x @ np.array([0.2126, 0.7152, 0.0722])


__all__ = ["Renderer", "Settings", "allowed_outliers", "assert_mean_equals_reference", "batch_stats",
           "below_only_scene", "collect", "luminance", "mean_and_se", "mixed_lights_scene", "occluder_scene", "rel_mse",
           "run_means"]


def run_means(scene: Scene, settings: Settings, runs: int, frames: int, device=None) -> np.ndarray:
    """(runs, H, W, 3) means of `frames` frames of a still camera, each run with a fresh renderer and its own seed:
    the runs are independent even where the frames of one run are correlated (ReSTIR's temporal reuse)."""
    out = []
    for k in range(runs):
        s = Settings(**{**settings.__dict__, "seed": settings.seed * 1000 + k})
        out.append(collect(scene, s, frames, device).mean(axis=0))
    return np.stack(out)


def mean_and_se(runs: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    return runs.mean(axis=0), runs.std(axis=0, ddof=1) / math.sqrt(runs.shape[0])


def device_ints(device, header: str, names: list[str]) -> list[int]:
    """The values on the device of the int constants (macros) `names` that `header` defines."""
    import pyopencl as cl
    from restircl.core.program import build_program

    writes = "\n".join(f"    out[{k}] = {name};" for k, name in enumerate(names))
    src = f'#include "{header}"\n__kernel void codes(__global int* out)\n{{\n{writes}\n}}\n'
    prog = build_program(device, {}, source=src)
    out = np.full(len(names), -1, np.int32)
    buf = cl.Buffer(device.context, cl.mem_flags.WRITE_ONLY, out.nbytes)
    prog.codes(device.queue, (1,), None, buf)
    cl.enqueue_copy(device.queue, out, buf)
    return out.tolist()
