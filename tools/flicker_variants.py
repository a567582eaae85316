"""Flicker statistics (eval/flicker.py) of ReSTIR with and without each anti-flicker option, on many_lights
(160x90, still and slowed moving camera) and the cornell box (96x96, still): docs/temporal-stability.md."""

from restircl import Settings, scenes
from restircl.eval import flicker as fl

VARIANTS = {"restir": Settings(), "restir boiling 0.2": Settings(boiling_filter=0.2),
            "restir permutation": Settings(temporal_permutation=True),
            "restir boiling+permutation": Settings(boiling_filter=0.2, temporal_permutation=True),
            "restir real-time filter": Settings(realtime_filter=True)}


def main() -> None:
    print(fl.HEADER)
    for name, sc, moving in (("many_lights", scenes.many_lights(160, 90, frames=8), False),
                             ("many_lights", scenes.many_lights(160, 90, frames=8), True),
                             ("cornell_box", scenes.cornell_box(96, 96), False)):
        for label, base in VARIANTS.items():
            res = fl.run_flicker(sc, ["restir"], frames=16, warmup=16, moving=moving, steps=8, cache_dir="out/refs",
                                 reference_seconds=10.0, base=base, log=lambda s: None)[0]
            res.method = f"{name}: {label}"
            print(res.row(), flush=True)


if __name__ == "__main__":
    main()
