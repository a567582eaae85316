"""The main thread's time of a viewport material edit (bpy): re-reading the materials alone
(export.export_materials) against the whole re-export (export.export_scene) that such an edit cost before, on a
scene of smooth UV spheres sharing one Principled material: docs/blender.md ("Edits").

    python -m tools.experiments.viewport_edit_cost --spheres 4      # 4 x 65,024 triangles
"""

from __future__ import annotations

import argparse
import json
import os
import time

import bpy
import numpy as np
from restircl.eval import blender_scenes as scenes
from restircl.io.blend import addon_module


def build(spheres: int) -> None:
    scenes.new_scene(32, 24, engine="RESTIRCL")
    scenes.quad("Floor", 10.0, 10.0, scenes.diffuse_material("Floor", (0.8, 0.8, 0.8)))
    paint = scenes.principled_material("Paint", (0.8, 0.05, 0.05))
    for i in range(spheres):
        bpy.ops.mesh.primitive_uv_sphere_add(segments=256, ring_count=128, location=(2.0 * i, 0.0, 1.0))
        bpy.context.active_object.data.materials.append(paint)
        bpy.ops.object.shade_smooth()
    scenes.light("POINT", "Point", (-1.0, -1.5, 2.5), energy=200.0)
    scenes.camera((0.0, -5.0, 2.5), (0.0, 0.5, 0.6), lens=28.0)


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--spheres", type=int, default=4)
    ap.add_argument("--repeats", type=int, default=5)
    a = ap.parse_args(argv)
    addon = addon_module()
    export = addon.export
    if not hasattr(bpy.types.Scene, "restircl"):
        addon.register()
    build(a.spheres)
    bpy.context.view_layer.update()
    dg = bpy.context.evaluated_depsgraph_get()
    exp = export.export_scene(dg, None)
    load_before = os.getloadavg()
    ms: dict[str, list[float]] = {"export_scene": [], "export_materials": []}
    for _ in range(a.repeats):
        t = time.perf_counter()
        export.export_scene(dg, None)
        ms["export_scene"].append((time.perf_counter() - t) * 1e3)
        t = time.perf_counter()
        export.export_materials(dg, exp.material_reads)
        ms["export_materials"].append((time.perf_counter() - t) * 1e3)
    print(json.dumps({"triangles": exp.scene.triangle_count, "materials": len(exp.scene.materials),
                      "median_ms": {k: float(np.median(v)) for k, v in ms.items()}, "load_before": load_before,
                      "load_after": os.getloadavg()}, indent=1))


if __name__ == "__main__":
    main()
