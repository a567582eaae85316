"""Rules for r^2, the denominator of the reference-free error estimate (render/still.py error_estimate), compared
offline on half buffers saved by tools/experiments/error_estimate_halves.py: per file, check and rule the ratio
estimate / true relMSE over the seeds (median, geometric mean, min, max). The true relMSE is against the file's own
reference render (its own error, estimated by the same rule, taken out, as tests/render/test_error_estimate.py
does) or, for the scene kinds, against a leave-one-out reference: the mean of the other seeds' last check, with the
kind's Cycles reference (--cycles) averaged in by sample count; the reference's own error, K / N with K the relMSE
x frames of the seeds at the last check, taken out. "oracle" weighs the same halves by the true r (the reference):
what any rule for r^2 can reach at best.

    python -m tools.experiments.error_estimate_rules garden.npz --rules old,new --cycles REF.npy
    python -m tools.experiments.error_estimate_rules ml_uniform.npz --rules old,new --reference-from ml_ris.npz
"""

from __future__ import annotations

import argparse
from typing import Any

import numpy as np
from restircl.render.half_error import R2_FLOOR, R2Rule, neighbours_max, rel_mse_from_halves, robust_r2


def med3(x: np.ndarray, axis: int) -> np.ndarray:
    """Median of each value and its two neighbours along `axis` (edges repeated)."""
    p = np.concatenate([np.take(x, [0], axis), x, np.take(x, [-1], axis)], axis)
    n = x.shape[axis]
    lo, mid, hi = (np.take(p, range(i, i + n), axis) for i in range(3))
    return np.maximum(np.minimum(lo, mid), np.minimum(np.maximum(lo, mid), hi))


def harmonic(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    s = a + b
    return np.divide(2 * a * b, s, out=np.zeros_like(s), where=s > 0)


def old(a, b, m):
    """The rule before: the harmonic mean of the halves, floored at (mean / 2)^2."""
    return np.maximum(harmonic(a, b) ** 2, R2_FLOOR * m * m)


def median3x3(a, b, m):
    """As old, its floor from min(mean, separable 3 x 3 median of the mean): rejected (a lamp a pixel or two wide
    is not in the median, and its term grew 100x)."""
    return np.maximum(harmonic(a, b) ** 2, R2_FLOOR * np.minimum(m, med3(med3(m, 0), 1)) ** 2)


def harmonic_capped(a, b, m):
    """robust_r2 with the harmonic mean^2 in place of a * b."""
    near = neighbours_max(m)
    low = np.minimum(a, b)
    x = np.minimum(harmonic(a, b), np.maximum(near, low))
    floor = np.where(low > 0, np.minimum(m, near), m)
    return np.maximum(x * x, R2_FLOOR * floor * floor)


def product(a, b, m):
    """a * b floored at (mean / 2)^2, without the neighbours' cap."""
    return np.maximum(np.maximum(a * b, 0.0), R2_FLOOR * m * m)


RULES: dict[str, R2Rule] = {
    "old": old,
    "median3x3": median3x3,
    "harmonic_capped": harmonic_capped,
    "product": product,
    "new": robust_r2,
}


def estimate(a: np.ndarray, b: np.ndarray, na: int, nb: int, rule: R2Rule) -> float:
    return rel_mse_from_halves(a, b, na, nb, rule)


def rel_mse(x: np.ndarray, r: np.ndarray) -> float:
    return float(np.mean((x - r) ** 2 / (r * r + 0.01)))


def load(path: str) -> tuple[tuple[int, ...], dict[int, tuple[np.ndarray, np.ndarray, np.ndarray]], Any]:
    z = np.load(path)
    checks = tuple(int(c) for c in z["checks"])
    data = {n: (z[f"a{n}"].astype(np.float64), z[f"b{n}"].astype(np.float64), z[f"counts{n}"]) for n in checks}
    return checks, data, z


def truths(
    path: str, rule: R2Rule, cycles: str | None, cycles_spp: int, reference_from: str | None = None
) -> tuple[dict[int, np.ndarray], dict]:
    """Per check the true relMSE of each seed's mean, and per check and seed the reference used (for the oracle)."""
    checks, data, z = load(path)
    last = max(checks)
    a, b, c = data[last]
    finals = (c[:, 0, None, None, None] * a + c[:, 1, None, None, None] * b) / c.sum(1)[:, None, None, None]
    s = len(finals)
    out: dict[int, np.ndarray] = {}
    refs: dict = {}
    zr = np.load(reference_from) if reference_from else z
    if "ref_a" in zr.files:
        ra, rb = zr["ref_a"].astype(np.float64), zr["ref_b"].astype(np.float64)
        na, nb = (int(x) for x in zr["ref_counts"])
        ref = (na * ra + nb * rb) / (na + nb)
        own = estimate(ra, rb, na, nb, rule)
        for n in checks:
            a, b, c = data[n]
            out[n] = np.array([rel_mse((c[i, 0] * a[i] + c[i, 1] * b[i]) / c[i].sum(), ref) - own for i in range(s)])
            refs[n] = [ref] * s
        return out, refs
    cyc = np.load(cycles)[..., :3].astype(np.float64) if cycles else None
    n_ref = last * (s - 1) + (cycles_spp if cyc is not None else 0)
    loo = []
    for i in range(s):
        tot = (finals.sum(0) - finals[i]) * last + (cyc * cycles_spp if cyc is not None else 0)
        loo.append(tot / n_ref)
    k = last * np.mean([rel_mse(finals[i], loo[i]) for i in range(s)]) / (1 + last / n_ref)
    for n in checks:
        a, b, c = data[n]
        out[n] = np.array(
            [rel_mse((c[i, 0] * a[i] + c[i, 1] * b[i]) / c[i].sum(), loo[i]) - k / n_ref for i in range(s)]
        )
        refs[n] = loo
    return out, refs


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("files", nargs="+")
    ap.add_argument("--cycles", help="the kind's Cycles reference (.npy), averaged into the leave-one-out one")
    ap.add_argument("--cycles-spp", type=int, default=512, help="its samples (both halves)")
    ap.add_argument("--rules", default=",".join(RULES))
    ap.add_argument("--reference-from", help="a file of the same scene whose reference render (--reference) to use")
    a = ap.parse_args()
    for path in a.files:
        checks, data, _ = load(path)
        for name in ["oracle", *a.rules.split(",")]:
            rule = RULES.get(name, old)
            true, refs = truths(path, rule, a.cycles, a.cycles_spp, a.reference_from)
            cells = []
            for n in checks:
                aa, bb, c = data[n]
                est = []
                for i in range(len(aa)):
                    r = refs[n][i]
                    rl: R2Rule = (lambda _a, _b, _m, r=r: r * r) if name == "oracle" else rule
                    est.append(estimate(aa[i], bb[i], int(c[i, 0]), int(c[i, 1]), rl))
                ratio = np.array(est) / true[n]
                cells.append(
                    f"{n}: med {np.median(ratio):.2f} gm {np.exp(np.mean(np.log(ratio))):.2f} "
                    f"[{ratio.min():.2f}, {ratio.max():.2f}] true {np.mean(true[n]):.2e}"
                )
            print(f"{path.split('/')[-1]:24s} {name:16s} " + " | ".join(cells))


if __name__ == "__main__":
    main()
