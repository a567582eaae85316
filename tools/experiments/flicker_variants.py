"""Flicker statistics (eval/report/flicker.py) of ReSTIR with and without each anti-flicker option, on many_lights
(160x90, still and slowed moving camera), the cornell box (96x96, still and panning) and material_balls
(glossy, 160x90, still):
docs/measurements/temporal-stability.md. The variants include the boiling filter's two measures and lower history
caps (m_cap).

    python -m tools.experiments.flicker_variants \
        [--scenes many_lights_still,many_lights_moving,cornell_box,material_balls]
"""

import argparse

import numpy as np
from restircl import Settings, scenes
from restircl.eval.report import flicker as fl

VARIANTS = {"restir": Settings(), "restir boiling 0.2": Settings(boiling_filter=0.2),
            "restir boiling 0.7": Settings(boiling_filter=0.7),
            "restir boiling contribution 0.5": Settings(boiling_filter=0.5, boiling_mode="contribution"),
            "restir boiling contribution 0.7": Settings(boiling_filter=0.7, boiling_mode="contribution"),
            "restir boiling contribution 0.8": Settings(boiling_filter=0.8, boiling_mode="contribution"),
            "restir boiling forget 0.5": Settings(boiling_filter=0.5, boiling_mode="forget"),
            "restir boiling forget 0.7": Settings(boiling_filter=0.7, boiling_mode="forget"),
            "restir boiling forget 0.9": Settings(boiling_filter=0.9, boiling_mode="forget"),
            "restir history cap 10": Settings(m_cap=10.0), "restir history cap 5": Settings(m_cap=5.0),
            "restir history cap 2": Settings(m_cap=2.0),
            "restir permutation": Settings(temporal_permutation=True),
            "restir contribution 0.7 + permutation": Settings(boiling_filter=0.7, boiling_mode="contribution",
                                                              temporal_permutation=True),
            "restir real-time filter": Settings(realtime_filter=True),
            "restir contribution 0.7 + real-time filter": Settings(boiling_filter=0.7,
                                                                   boiling_mode="contribution",
                                                                   realtime_filter=True)}
def cornell_box_moving():
    """The cornell box with its camera panning 0.3 m sideways over 4 frames (33 once slowed 8x)."""
    sc = scenes.cornell_box(96, 96, frames=5)
    m = sc.camera.transforms.copy()
    m[:, 0, 3] += np.linspace(-0.15, 0.15, m.shape[0])
    sc.camera.transforms = m
    sc.frame_count = m.shape[0]
    return sc


CASES = {"many_lights_still": ("many_lights", lambda: scenes.many_lights(160, 90, frames=8), False),
         "many_lights_moving": ("many_lights", lambda: scenes.many_lights(160, 90, frames=8), True),
         "cornell_box": ("cornell_box", lambda: scenes.cornell_box(96, 96), False),
         "cornell_box_moving": ("cornell_box", cornell_box_moving, True),
         "material_balls": ("material_balls", lambda: scenes.material_balls(160, 90), False)}


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--scenes", default=",".join(CASES))
    ap.add_argument("--variants", default=",".join(VARIANTS), help="comma-separated names of VARIANTS")
    a = ap.parse_args()
    print(fl.HEADER)
    for case in a.scenes.split(","):
        name, make, moving = CASES[case]
        sc = make()
        for label in a.variants.split(","):
            base = VARIANTS[label]
            res = fl.run_flicker(sc, ["restir"], frames=16, warmup=16, moving=moving, steps=8, cache_dir="out/refs",
                                 reference_seconds=10.0, base=base, log=lambda s: None)[0]
            res.method = f"{name}: {label}"
            print(res.row(), flush=True)


if __name__ == "__main__":
    main()
