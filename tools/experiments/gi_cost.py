"""The cost of the path pass's variants (tools/experiments/gi_variance.py gives their error): F12's still path at
Max Bounces 4 with each variant, and at Max Bounces 0 (the direct light's cost), taking turns (A B C A B C ...) so
that a loaded machine slows all alike; median ms per still frame.

    python -m tools.experiments.gi_cost --kind gi_tuning_room --variant array='{"path_light_pick": "array"}' \\
        --variant tree='{"path_light_pick": "tree"}'
"""

from __future__ import annotations

import argparse
import os

from restircl import Renderer, Settings
from restircl.eval.bench.environment import interleaved_still_ms
from restircl.eval.cycles.paths import LightPaths
from restircl.eval.scenes.kinds import scene_of_kind
from restircl.render import pipeline
from restircl.render.still_method import still_settings

from .gi_variance import parse_variant


def main() -> None:
    p = argparse.ArgumentParser()
    p.add_argument("--kind", default="gi_tuning_room")
    p.add_argument("--max-bounces", type=int, default=4)
    p.add_argument("--frames", type=int, default=4)
    p.add_argument("--repeats", type=int, default=5)
    p.add_argument("--variant", action="append", default=[])
    a = p.parse_args()
    scene = scene_of_kind(a.kind)
    paths = LightPaths.of(a.max_bounces)
    renderers = {"direct_only": Renderer(scene, still_settings(Settings().validate(), scene))}
    build = pipeline.build_program
    for text in a.variant:
        name, overrides, defines = parse_variant(text)
        pipeline.build_program = lambda device, flags=None, d=defines, **kw: build(  # type: ignore[assignment]
            device, flags, extra_options=(*kw.pop("extra_options", ()), *d), **kw)
        renderers[name] = Renderer(scene, still_settings(Settings(**{**paths.overrides(), **overrides}).validate(),
                                                         scene))
        pipeline.build_program = build  # type: ignore[assignment]
    load = os.getloadavg()[0]
    for name, ms in interleaved_still_ms(renderers, a.repeats, a.frames).items():
        print(f"{name:<14} {ms:7.1f} ms per still frame  (load {load:.1f})")


if __name__ == "__main__":
    main()
