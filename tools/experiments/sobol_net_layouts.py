"""Which Sobol dimensions of the camera vertex's 6D group (opencl/sampling/qmc.h QMC_CAMERA) should carry the pixel
jitter, the point on the light, the pick and the resampling choice: the mean squared error over `runs` scrambles
(each coordinate Owen-scrambled, the index shuffled, as qmc.h does it, here with numpy's random bits) of N-point
estimates of three integrands over (jitter x, jitter y, pick, u, v):

- edge: a pixel cut by a straight edge; the covered part lit by one of five lights (the pick) with a shadow over part
  of each light (u, v), the rest by another shadowed light at 0.3;
- flat: the same light without the edge (a pixel inside a surface);
- aa: the edge alone (plain antialiasing);

and the layouts' t-values (the smallest t such that 2^k points are a (t, k, s)-net) of the projections that matter.
`old`: the jitter a pair of its own (another shuffle), the light (pick, u, v) on dimensions (2, 0, 1) of its group.

    PYTHONPATH=python python tools/experiments/sobol_net_layouts.py [N [runs]]
"""

from __future__ import annotations

import sys

import numpy as np
from restircl.eval.nets import t_value
from restircl.upload.sobol_table import direction_numbers

M32 = np.uint64(0xFFFFFFFF)
#: name -> dimensions of (jitter x, jitter y, pick, u, v); None: the former independent pairing
LAYOUTS: dict[str, tuple[int, ...] | None] = {
    "old": None, "J23_p4": (2, 3, 4, 0, 1), "J34_p2": (3, 4, 2, 0, 1), "J45_p2": (4, 5, 2, 0, 1),
    "J01_p2_uv34": (0, 1, 2, 3, 4), "J01_p4_uv23": (0, 1, 4, 2, 3),
}
LIGHT_WEIGHTS = np.array([1.0, 3.0, 0.5, 2.0, 1.5])


def matrix(dim: int) -> list[int]:
    """Direction numbers of Sobol dimension `dim` (0: the bit-reversed index; 1: x + 1, m = 1)."""
    if dim == 0:
        return [1 << (31 - k) for k in range(32)]
    if dim == 1:
        m = [1]
        for k in range(1, 32):
            m.append(m[k - 1] ^ (m[k - 1] << 1))
        return [m[k] << (31 - k) for k in range(32)]
    return direction_numbers(dim)


def sobol(index: np.ndarray, dim: int) -> np.ndarray:
    out = np.zeros(len(index), np.uint64)
    for k, v in enumerate(matrix(dim)):
        out ^= np.where((index >> np.uint64(k)) & np.uint64(1), np.uint64(v), np.uint64(0))
    return out


def reverse(x: np.ndarray) -> np.ndarray:
    r = np.zeros_like(x)
    for k in range(32):
        r |= ((x >> np.uint64(k)) & np.uint64(1)) << np.uint64(31 - k)
    return r


def lk_hash(x: np.ndarray, seed: int) -> np.ndarray:
    """qmc.h qmc_lk_hash: each bit flipped by a function of the bits below it."""
    x = (x + np.uint64(seed)) & M32
    for c in (0x6C50B47C, 0xB82F1E52, 0xC7AFE638, 0x8D22F6E6):
        x ^= (x * np.uint64(c)) & M32
    return x


def points(n: int, dims: tuple[int, ...], seeds: np.ndarray) -> list[np.ndarray]:
    """n points of `dims` under one index shuffle (seeds[0]), each coordinate scrambled (seeds[1:]), in [0, 1)."""
    i = reverse(lk_hash(reverse(np.arange(n, dtype=np.uint64)), int(seeds[0])))
    return [reverse(lk_hash(reverse(sobol(i, d)), int(s))).astype(np.float64) / 2.0**32
            for d, s in zip(dims, seeds[1:], strict=True)]


def light(p: np.ndarray, u: np.ndarray, v: np.ndarray, side: int) -> np.ndarray:
    k = np.minimum((p * len(LIGHT_WEIGHTS)).astype(int), len(LIGHT_WEIGHTS) - 1)
    lit = (u + 0.7 * v < 0.8 + 0.02 * k) if side == 0 else (v > 0.4)
    return LIGHT_WEIGHTS[k] * (1 + 0.5 * np.sin(6.28 * u + k)) * lit


def covered(jx: np.ndarray, jy: np.ndarray) -> np.ndarray:
    return (0.8 * jx + 0.6 * jy) < 0.7


INTEGRANDS = {
    "edge": lambda jx, jy, p, u, v: np.where(covered(jx, jy), light(p, u, v, 0), 0.3 * light(p, u, v, 1)),
    "flat": lambda jx, jy, p, u, v: light(p, u, v, 0),
    "aa": lambda jx, jy, p, u, v: covered(jx, jy) * 1.0,
}


def layout_t(dims: tuple[int, ...], k: int) -> int:
    """The t-value of the first 2^k unscrambled points of Sobol dimensions `dims`."""
    return t_value(np.column_stack([sobol(np.arange(1 << k, dtype=np.uint64), d) for d in dims]), k)


def main() -> None:
    n = int(sys.argv[1]) if len(sys.argv) > 1 else 256
    runs = int(sys.argv[2]) if len(sys.argv) > 2 else 300
    rng = np.random.default_rng(1)
    refs = {name: float(np.mean(f(*rng.random((4_000_000, 5)).T))) for name, f in INTEGRANDS.items()}
    for name, lay in LAYOUTS.items():
        err: dict[str, list[float]] = {k: [] for k in INTEGRANDS}
        for _ in range(runs):
            s = rng.integers(0, 2**32, 10, dtype=np.uint64)
            if lay is None:
                p, u, v = points(n, (2, 0, 1), s[0:4])
                jx, jy = points(n, (0, 1), s[4:7])
            else:
                jx, jy, p, u, v = points(n, lay, s[0:6])
            for key, f in INTEGRANDS.items():
                err[key].append(float(np.mean(f(jx, jy, p, u, v))) - refs[key])
        tv = "" if lay is None else (f"; t (k = 4..10): jitter {max(layout_t(lay[:2], k) for k in range(4, 11))}, "
                                     f"point {max(layout_t(lay[3:], k) for k in range(4, 11))}, (pick, point) "
                                     f"{max(layout_t(lay[2:], k) for k in range(4, 11))}, (jitter, point) "
                                     f"{max(layout_t(lay[:2] + lay[3:], k) for k in range(4, 11))}")
        print(f"N={n} {name:12s} " + " ".join(f"{k} {np.mean(np.square(e)):.3e}" for k, e in err.items()) + tv,
              flush=True)


if __name__ == "__main__":
    main()
