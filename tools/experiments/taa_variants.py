"""TAA relMSE of a moving many_lights camera (160x90, 24 frames) with each TAA / reuse option, against per-frame
references (every 4th frame), 3 seeds: docs/measurements/temporal-stability.md.

    python -m tools.experiments.taa_variants
"""

import numpy as np
from restircl import Renderer, Settings, scenes
from restircl.eval.metrics import rel_mse
from restircl.eval.report.reference import get_reference

VARIANTS = ({}, {"taa_filter": "catmull_rom"}, {"taa_dilation": True}, {"temporal_permutation": True},
            {"boiling_filter": 0.2})
RESTIR_ONLY = ("temporal_permutation", "boiling_filter")


def main() -> None:
    sc = scenes.many_lights(160, 90, frames=24)
    every = list(range(4, 24, 4))
    refs = {f: get_reference(sc, f, 15.0, cache_dir="out/refs", log=lambda s: None).image for f in every}
    for method in ("ris", "restir"):
        for kw in VARIANTS:
            if method == "ris" and any(k in kw for k in RESTIR_ONLY):
                continue
            errs = []
            for seed in range(3):
                r = Renderer(sc, Settings(method=method, seed=seed, **kw))
                out = {f: r.render_frame(f, aovs=False).color for f in range(24)}
                errs.append(np.mean([rel_mse(out[f], refs[f]) for f in every]))
            print(method, kw, "relMSE per seed:", " ".join(f"{e:.4f}" for e in errs), f"mean {np.mean(errs):.4f}",
                  flush=True)


if __name__ == "__main__":
    main()
