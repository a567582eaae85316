"""TAA relMSE of a moving many_lights camera (160x90, 24 frames) with each TAA / reuse option, against per-frame
references (every 4th frame), 3 seeds: docs/measurements/temporal-stability.md.

    python -m tools.experiments.taa_variants [--methods ris,restir] [--variants 0,3] [--cache-dir out/refs]
        [--define NAME]

--variants: indexes into VARIANTS (default all); --define: a kernel -D of a probe for every render of the run
(restircl.eval.probe_defines), e.g. PROBE_PERMUTATION_FALLBACK (camera/reproject.h).
"""

import argparse

import numpy as np
from restircl import Renderer, Settings, scenes
from restircl.eval.metrics import rel_mse
from restircl.eval.probe_defines import add_probe_defines
from restircl.eval.report.reference import get_reference

VARIANTS = (
    {},
    {"taa_filter": "catmull_rom"},
    {"taa_dilation": True},
    {"temporal_permutation": True},
    {"boiling_filter": 0.2},
)
RESTIR_ONLY = ("temporal_permutation", "boiling_filter")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--methods", default="ris,restir")
    ap.add_argument("--variants", default=None, help="comma-separated indexes into VARIANTS (default: all)")
    ap.add_argument("--cache-dir", default="out/refs")
    ap.add_argument("--define", action="append", default=[], metavar="NAME=VALUE")
    a = ap.parse_args()
    if a.define:
        add_probe_defines(a.define)
    chosen = [VARIANTS[int(i)] for i in a.variants.split(",")] if a.variants else list(VARIANTS)
    sc = scenes.many_lights(160, 90, frames=24)
    every = list(range(4, 24, 4))
    refs = {f: get_reference(sc, f, 15.0, cache_dir=a.cache_dir, log=lambda s: None).image for f in every}
    for method in a.methods.split(","):
        for kw in chosen:
            if method == "ris" and any(k in kw for k in RESTIR_ONLY):
                continue
            errs = []
            for seed in range(3):
                r = Renderer(sc, Settings(method=method, seed=seed, **kw))
                out = {f: r.render_frame(f, aovs=False).color for f in range(24)}
                errs.append(np.mean([rel_mse(out[f], refs[f]) for f in every]))
            print(
                method,
                kw,
                a.define or "",
                "relMSE per seed:",
                " ".join(f"{e:.4f}" for e in errs),
                f"mean {np.mean(errs):.4f}",
                flush=True,
            )


if __name__ == "__main__":
    main()
