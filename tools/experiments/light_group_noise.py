"""What a light group's pass costs in noise: the group's plane of a render of the whole scene (the same samples
split by the light each came from) against a render of that group's emitters alone, at equal samples per pixel,
both against a converged render of the group alone. The scene is tests/lights/linking_scene.py (unlinked) with two
groups: "warm" (the point light and the emissive panel), "cool" (the area light).

    PYTHONPATH=python python tools/experiments/light_group_noise.py [samples] [reference_samples]
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))

from restircl import Material, Renderer, Settings  # noqa: E402

from tests.lights.linking_scene import linking_scene, rel_mse  # noqa: E402

GROUPS = {"warm": ("key", "glow"), "cool": ("fill",)}


def grouped_scene(only: str | None = None):
    sc = linking_scene(linked=False)
    sc.light_groups = list(GROUPS)
    for name, members in GROUPS.items():
        for lt in sc.lights:
            if lt.name in members:
                lt.lightgroup = name
        for m in sc.meshes:
            if m.name in members:
                m.lightgroup = name
    if only is not None:  # the other group's emitters out: lights removed, the panel black
        sc.lights = [lt for lt in sc.lights if lt.lightgroup == only]
        if "glow" not in GROUPS[only]:  # the panel black, as its material is but for its emission
            sc.materials[1] = Material(name="off", albedo=(0.0, 0.0, 0.0))
    return sc


def main() -> None:
    samples = int(sys.argv[1]) if len(sys.argv) > 1 else 16
    ref_samples = int(sys.argv[2]) if len(sys.argv) > 2 else 2048
    for method in ("ris", "restir"):
        st = Settings(method=method, seed=5)
        seeds = range(4)
        whole = [Renderer(grouped_scene(), Settings(method=method, seed=s)).render_still(0, samples=samples)
                 for s in seeds]
        for group in GROUPS:
            ref = Renderer(grouped_scene(group), Settings(method="reference", seed=99)).render_still(
                0, samples=ref_samples).color[..., :3]
            alone = [Renderer(grouped_scene(group), Settings(method=method, seed=s)).render_still(
                0, samples=samples).color[..., :3] for s in seeds]
            e_split = np.mean([rel_mse(f.light_groups[group], ref) for f in whole])
            e_alone = np.mean([rel_mse(a, ref) for a in alone])
            mean = np.mean([f.light_groups[group].mean() for f in whole]) / ref.mean()
            print(f"{st.method:7s} {group}: relMSE of the group's pass {e_split:.3e}, of the group rendered alone "
                  f"{e_alone:.3e}, ratio {e_split / e_alone:.2f}; the pass's mean / the reference's {mean:.4f} "
                  f"({samples} spp, 4 seeds)")


if __name__ == "__main__":
    main()
