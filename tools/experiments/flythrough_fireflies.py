"""Where a firefly of the many_lights flythrough comes from (160x90, ReSTIR DI defaults): renders frames 0..FRAME
of one seed, prints the pixel's reservoir after each reuse stage (its 3x3 neighbourhood: light, M, W, target), the
G-buffer around it, the light of the final sample and the receiver's view angle, and, with --weight, every
initial RIS candidate whose resampling weight target / p_mix exceeds it (the kernel probe PROBE_FLYFIRE in
direct/ris.h and direct/bsdf_candidates.h: strategy, light, target, the light and BSDF densities, distance):
docs/measurements/temporal-stability.md, "Where the flythrough's fireflies come from".

    python -m tools.experiments.flythrough_fireflies SEED FRAME X Y [--weight 200] [--cache-dir /tmp/permute/refs]
"""

from __future__ import annotations

import argparse
import ctypes

import numpy as np
import pyopencl as cl
from restircl import Renderer, Settings, scenes
from restircl.core import layouts as L
from restircl.eval.probe_defines import add_probe_defines
from restircl.eval.report.reference import get_reference

LIBC = ctypes.CDLL(None)
LUMA = np.array([0.2126, 0.7152, 0.0722])


def reservoirs(r: Renderer, buf: cl.Buffer) -> np.ndarray:
    out = np.empty(r.pixels, L.RESERVOIR)
    cl.enqueue_copy(r.device.queue, out, buf)
    return out


def fmt(x: np.void) -> str:
    return f"l{x['light']} M{x['M']:.0f} W{x['W']:.3g} t{x['target']:.3g}"


def trace_stages(r: Renderer, frame: int, pix: int, width: int, log: list[str], now: list[int]) -> None:
    """Wrap the reuse stages so that each logs the pixel's 3x3 reservoirs at `frame`."""
    for name in ("initial", "temporal", "spatial"):
        stage = getattr(r, name)

        def run(*a, _orig=stage.run, _name=name, **k):
            out = _orig(*a, **k)
            if now[0] == frame:
                res = reservoirs(r, out)
                log.append(_name)
                for row in (pix - width, pix, pix + width):
                    log.append("   " + " | ".join(fmt(x) for x in res[row - 1 : row + 2]))
            return out

        stage.run = run


def describe(r: Renderer, fr, ref: np.ndarray, pix: int, width: int) -> None:
    """The G-buffer around the pixel and the final sample's light."""
    g = r.read_gbuffer().reshape(-1)
    noisy, refl = fr.noisy[..., :3].reshape(-1, 3), ref.reshape(-1, 3)
    for d in (-width - 1, -width, -width + 1, -1, 0, 1, width - 1, width, width + 1):
        q = g[pix + d]
        print(
            f"  {d:+4d} pos {np.round(q['pos'], 2)} n {np.round(q['normal'][:3], 2)} "
            f"sample {np.round(noisy[pix + d], 2)} ref {np.round(refl[pix + d], 2)}"
        )
    res = reservoirs(r, r.res_history[r.last_slot])[pix]
    light = int(res["light"])
    if light < 0:
        return
    rec = r.lights.records[light]
    glossy = np.empty(r.pixels, L.GLOSSY_SAMPLE)
    cl.enqueue_copy(r.device.queue, glossy, r.history.glossy(r.history.cur))
    cos_o = float(np.dot(glossy[pix]["wo"][:3], g[pix]["normal"][:3]))
    print(
        f"final: {fmt(res)}; light type {r.lights.types[light]} pick pdf {r.light_array.pdf[light]:.3g} "
        f"(median {np.median(r.light_array.pdf):.3g}), radiance luminance {float(LUMA @ rec['L'][:3]):.1f}, "
        f"{np.linalg.norm(rec['p'][:3] - g[pix]['pos'][:3]):.2f} from the receiver; receiver albedo "
        f"{np.round(g[pix]['albedo'][:3], 2)}, cos(view) {cos_o:.2f}"
    )


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    for name in ("seed", "frame", "x", "y"):
        ap.add_argument(name, type=int)
    ap.add_argument("--weight", type=float, default=0.0, help="print initial candidates above this weight")
    ap.add_argument("--cache-dir", default="out/refs")
    a = ap.parse_args()
    if a.weight > 0:
        add_probe_defines([f"PROBE_FLYFIRE={a.weight!r}"])
    sc = scenes.many_lights(160, 90, frames=24)
    ref = get_reference(sc, a.frame, 15.0, cache_dir=a.cache_dir, log=lambda s: None).image[..., :3]
    r = Renderer(sc, Settings(method="restir", seed=a.seed))
    width, pix, log, now = 160, a.y * 160 + a.x, [], [0]
    trace_stages(r, a.frame, pix, width, log, now)
    for f in range(a.frame + 1):
        now[0] = f
        print(f"frame {f} (pixel id {pix})", flush=True)
        fr = r.render_frame(f, aovs=False)
        r.device.queue.finish()
        LIBC.fflush(None)  # the kernels' printf lines are C stdio's: out before the next frame's marker
    print(f"sample {fr.noisy[a.y, a.x, :3]} shown {fr.color[a.y, a.x, :3]} reference {ref[a.y, a.x]}")
    describe(r, fr, ref, pix, width)
    print("\n".join(log))


if __name__ == "__main__":
    main()
