"""Where the moving camera's darkening comes from (docs/measurements/temporal-stability.md, "The moving camera's
level"): the mean output luminance over the reference's (level, eval/report/flicker.py) of many_lights' slowed
flythrough and of its still frame 0, with TAA on and off, ReSTIR and RIS, and TAA's clip widened; `noisy` is the
level of the 1-sample estimates TAA blends (ReSTIR's own bias), `taa` is the output's over the noisy's (TAA's own). The
deficit is split between the pixels the reference has brightest (the top 1 %: the lamps seen directly) and the rest.

    python -m tools.experiments.level_probe [--seeds 4242,7] [--variants restir,ris,...] [--cameras moving,still]
                                [--define TAA_CLIP_RADIUS=2]   # an -D option for every kernel build
"""

import argparse

import numpy as np
from restircl import Renderer, Settings, scenes
from restircl.eval.probe_defines import add_probe_defines
from restircl.eval.report import flicker as fl
from restircl.eval.report.reference import get_reference

VARIANTS = {
    "restir": Settings(),
    "restir no taa": Settings(taa=False),
    "restir gamma 1e3": Settings(gamma=1e3),
    "restir no jitter": Settings(jitter=False),
    "ris": Settings(method="ris"),
    "ris no taa": Settings(method="ris", taa=False),
    "ris gamma 1e3": Settings(method="ris", gamma=1e3),
    "restir gamma 1.5": Settings(gamma=1.5),
    "restir gamma 2": Settings(gamma=2.0),
    "restir gamma 3": Settings(gamma=3.0),
}


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--seeds", default="4242,7")
    ap.add_argument("--variants", default=",".join(VARIANTS))
    ap.add_argument("--cameras", default="moving,still")
    ap.add_argument("--size", default="160x90")
    ap.add_argument("--define", default="", help="an -D option for every kernel build, e.g. TAA_CLIP_RADIUS=2")
    a = ap.parse_args()
    w, h = (int(v) for v in a.size.split("x"))
    if a.define:
        add_probe_defines([a.define])
    base = scenes.many_lights(w, h, frames=8)
    warmup, frames = 16, 16
    print("| camera | variant | seed | level | noisy level | taa / noisy | deficit top 1 % | deficit rest | flicker "
          "| error |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for camera in a.cameras.split(","):
        moving = camera == "moving"
        sc = fl.slowed(base, 8) if moving else base
        kept = list(range(warmup, warmup + frames)) if moving else [0] * frames
        seq = list(range(warmup)) if moving else [0] * warmup
        refs = {f: get_reference(sc, f, 10.0, cache_dir="out/refs", log=lambda s: None).image for f in set(kept)}
        r_lum = np.stack([fl._lum(refs[f]) for f in kept])
        top = r_lum >= np.quantile(r_lum, 0.99)
        for name in a.variants.split(","):
            for seed in (int(s) for s in a.seeds.split(",")):
                s = Settings(**{**VARIANTS[name].__dict__, "seed": seed})
                r = Renderer(sc, s)
                for f in seq:
                    r.render_frame(f, aovs=False)
                out, noisy, colours = [], [], []
                for f in kept:
                    fr = r.render_frame(f, aovs=False)
                    colours.append(fr.color)
                    out.append(fl._lum(fr.color))
                    noisy.append(fl._lum(fr.noisy))
                st = fl.stats(name, camera, colours, [refs[f] for f in kept])
                x, nz = np.stack(out), np.stack(noisy)
                tot = r_lum.sum()
                d = x - r_lum
                label = f"{name} -D{a.define}" if a.define else name
                print(f"| {camera} | {label} | {seed} | {x.sum() / tot:.3f} | {nz.sum() / tot:.3f} | "
                      f"{x.sum() / nz.sum():.3f} | {d[top].sum() / tot:+.3f} | {d[~top].sum() / tot:+.3f} | "
                      f"{st.flicker:.4f} | {st.error:.4f} |",
                      flush=True)


if __name__ == "__main__":
    main()
