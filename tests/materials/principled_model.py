"""An independent numpy (float64) statement of the Principled BSDF model the device implements (Cycles 4.x/5.0's,
without coat, sheen, subsurface, transmission): closures resolved for a view, then f(wo, wi) at a normal +z.
Written from the model's definition, not from the OpenCL code, so the tests can hold the device to it."""

from __future__ import annotations

import numpy as np
from restircl.upload import ggx_tables as T

from .bsdf_kernels import Closure

ALPHA_MIN = 1e-4


def _lerp_table(flat: np.ndarray, n: int, coords: list[float]) -> float:
    """Multilinear interpolation on an n^d grid (last coordinate slowest), grid point i at i / (n - 1)."""
    grid = flat.reshape((n,) * len(coords))  # index [..., y, x]
    pos = [min(max(c, 0.0), 1.0) * (n - 1) for c in coords]
    lo = [min(int(p), n - 2) for p in pos]
    t = [p - i for p, i in zip(pos, lo, strict=True)]
    total = 0.0
    for corner in range(1 << len(coords)):
        w, idx = 1.0, []
        for d in range(len(coords)):
            bit = (corner >> d) & 1
            w *= t[d] if bit else 1.0 - t[d]
            idx.append(lo[d] + bit)
        total += w * float(grid[tuple(reversed(idx))])
    return total


def tables() -> dict[str, np.ndarray]:
    t = T.ggx_tables().astype(np.float64)
    return {"E": t[T.E_OFFSET:T.E_AVG_OFFSET], "Eavg": t[T.E_AVG_OFFSET:T.S_OFFSET], "s": t[T.S_OFFSET:]}


def fresnel_dielectric(c: np.ndarray, eta: float) -> np.ndarray:
    return T.fresnel_dielectric(c, eta)


def f82(c: np.ndarray, f0: np.ndarray, b: np.ndarray) -> np.ndarray:
    m = np.clip(1.0 - c, 0.0, 1.0)[..., None]
    return np.clip(f0 + (1.0 - f0) * m ** 5 - b * c[..., None] * m ** 6, 0.0, 1.0)


def ms_factor(fss: np.ndarray, e: float, e_avg: float) -> np.ndarray:
    fms = fss * e_avg / (1.0 - fss * (1.0 - e_avg))
    return 1.0 + fms * (1.0 - e) / e


def smith_lambda(alpha2: float, c: np.ndarray) -> np.ndarray:
    return 0.5 * (np.sqrt(1.0 + alpha2 * np.maximum(1.0 / np.maximum(c * c, 1e-12) - 1.0, 0.0)) - 1.0)


def resolve(closures: list[Closure], mu: float) -> tuple[np.ndarray, list[dict]]:
    """(diffuse albedo, lobes) at view cosine mu."""
    tab = tables()
    diffuse = np.zeros(3)
    lobes = []
    for c in closures:
        w = max(c.weight, 0.0)
        base = np.maximum(np.asarray(c.base, float), 0.0)
        if w <= 1e-5:
            continue
        if c.kind == "diffuse":
            diffuse += base * w
            continue
        r = min(max(c.roughness, 0.0), 1.0)
        alpha = max(r * r, ALPHA_MIN)
        e = max(_lerp_table(tab["E"], T.E_SIZE, [r, mu]), 1e-3) if c.multiscatter else 1.0
        e_avg = max(_lerp_table(tab["Eavg"], T.E_SIZE, [r]), 1e-3) if c.multiscatter else 1.0
        lobe = {"alpha": alpha, "metal_f0": np.zeros(3), "b": np.zeros(3), "metal_w": np.zeros(3), "eta": 1.0,
                "diel_f0": np.zeros(3), "diel_w": np.zeros(3)}
        if c.kind == "glossy":
            lobe.update(metal_f0=np.ones(3), metal_w=base * w * (ms_factor(base, e, e_avg) if c.multiscatter else 1))
            lobes.append(lobe)
            continue
        metallic = min(max(c.metallic, 0.0), 1.0)
        tint = np.maximum(np.asarray(c.tint, float), 0.0)
        has = False
        if metallic > 1e-5:
            f0 = np.clip(base, 0.0, 1.0)
            k = np.minimum(tint, 1.0)
            m = 6.0 / 7.0
            b = np.zeros(3) if np.all(k == 1.0) else (f0 + (1 - f0) * m ** 5) * (7.0 / m ** 6) * (1.0 - k)
            fss = f0 + (1.0 - f0) / 21.0 - b / 126.0
            lobe.update(metal_f0=f0, b=b, metal_w=w * metallic * (ms_factor(fss, e, e_avg) if c.multiscatter else 1))
            has = True
        wr = w * (1.0 - metallic)
        f0s = ((c.ior - 1.0) / (c.ior + 1.0)) ** 2
        eta = c.ior
        if c.specular != 0.5:
            f0s *= 2.0 * max(c.specular, 0.0)
            eta = float(T.ior_from_f0(f0s))
        dw = wr
        if wr > 1e-5 and eta > 1.0:
            df0 = np.clip(f0s * tint, 0.0, 1.0)
            f0_eta = ((eta - 1.0) / (eta + 1.0)) ** 2
            s_avg = min(max(((eta - 1.0) / (4.08567 + 1.00071 * eta) - f0_eta) / (1.0 - f0_eta), 0.0), 1.0)
            comp = ms_factor(df0 + (1.0 - df0) * s_avg, e, e_avg) if c.multiscatter else np.ones(3)
            dark = comp * e if c.multiscatter else np.ones(3)
            s = _lerp_table(tab["s"], T.S_SIZE, [r, mu, np.sqrt(abs((eta - 1.0) / (eta + 1.0)))])
            albedo = dark * (df0 + (1.0 - df0) * s)
            dw = wr * min(max(1.0 - albedo.max(), 0.0), 1.0)
            lobe.update(eta=eta, f0_eta=f0_eta, diel_f0=df0, diel_w=wr * comp)
            has = True
        diffuse += base * dw
        if has:
            lobes.append(lobe)
    return diffuse, lobes


def eval_f(closures: list[Closure], wo: np.ndarray, wi: np.ndarray) -> np.ndarray:
    """f(wo, wi) (N x 3) for unit directions wi (N x 3) above or below the normal +z."""
    diffuse, lobes = resolve(closures, float(np.clip(wo[2], 0.0, 1.0)))
    f = np.broadcast_to(diffuse / np.pi, wi.shape).copy()
    co, ci = wo[2], wi[:, 2]
    ok = (co > 1e-6) & (ci > 1e-6)
    h = wi + wo
    h /= np.linalg.norm(h, axis=1, keepdims=True)
    chi = np.clip(h @ wo, 0.0, 1.0)
    for lb in lobes:
        a2 = lb["alpha"] ** 2
        c2 = np.minimum(h[:, 2] ** 2, 1.0)
        d = a2 / (np.pi * ((1.0 - c2) + a2 * c2) ** 2)
        g2 = 1.0 / (1.0 + smith_lambda(a2, co) + smith_lambda(a2, ci))
        F = lb["metal_w"] * f82(chi, lb["metal_f0"], lb["b"])
        if lb["eta"] > 1.0:
            s = np.clip((fresnel_dielectric(chi, lb["eta"]) - lb["f0_eta"]) / (1.0 - lb["f0_eta"]), 0.0, 1.0)
            F = F + lb["diel_w"] * (lb["diel_f0"] + (1.0 - lb["diel_f0"]) * s[:, None])
        spec = F * (d * g2 / (4.0 * co * np.maximum(ci, 1e-12)))[:, None]
        f += np.where(ok[:, None], spec, 0.0)
    return f
