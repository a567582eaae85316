"""Install the extension zip with Blender's own installer into an empty user folder, enable it, and F12 one small
scene with restircl and with Cycles, then with restircl's Denoise. Run by tests/blender/test_blender_extension.py
in a process of its own:

    python -S tests/blender/extension_install_script.py ZIP OUTDIR SITE

SITE holds only bpy and the modules bpy needs (-S leaves out the rest of site-packages), so restircl, pyopencl,
PoCL, OpenEXR, Pillow and pyoidn (the denoiser) can come only from the wheels in the zip; so does the scene
builder this uses (restircl.eval.blender_scenes, part of the restircl wheel). The caller points BLENDER_USER_* at
empty folders before this starts, since bpy reads them when it is imported. Prints one JSON line last.
"""

from __future__ import annotations

import json
import sys
import time
from pathlib import Path

zip_path, outdir, site = sys.argv[1], Path(sys.argv[2]), sys.argv[3]
sys.path.insert(0, site)
import bpy  # noqa: E402

report: dict = {"blender": bpy.app.version_string, "python": sys.version.split()[0]}
bpy.ops.wm.read_factory_settings(use_empty=True)  # before installing: factory settings disable extensions
repo = Path(bpy.utils.user_resource("EXTENSIONS")) / "user_default"
report["installed_before"] = sorted(p.name for p in repo.glob("*")) if repo.is_dir() else []
t0 = time.perf_counter()
report["install"] = sorted(bpy.ops.extensions.package_install_files(
    filepath=zip_path, repo="user_default", enable_on_install=True))
report["install_s"] = time.perf_counter() - t0
report["enabled"] = "bl_ext.user_default.restircl" in bpy.context.preferences.addons
engines = {getattr(c, "bl_idname", None) for c in bpy.types.RenderEngine.__subclasses__()}
report["engine"] = "RESTIRCL" in engines
import pyoidn  # noqa: E402  (the denoiser: bundled, so Denoise works without a pip install)
import pyopencl  # noqa: E402
import restircl  # noqa: E402
from restircl.eval import blender_scenes as scenes  # noqa: E402

report["modules"] = {m.__name__: m.__file__ for m in (restircl, pyopencl, scenes, pyoidn)}
report["extensions_dir"] = bpy.utils.user_resource("EXTENSIONS")

sc = scenes.comparison_scene("mixed", 48, 36, reset=False)
scenes.cycles_direct_only(sc, samples=256, seed=1, threads=2)
scenes.exr_output(sc, str(outdir / "cycles.exr"))
bpy.ops.render.render(write_still=True)
sc.render.engine = "RESTIRCL"
sc.restircl.method = "reference"
sc.restircl.samples = 64
scenes.exr_output(sc, str(outdir / "ours.exr"))
t0 = time.perf_counter()
bpy.ops.render.render(write_still=True)
report["f12_s"] = time.perf_counter() - t0
sc.restircl.denoise = True  # with the bundled pyoidn: the Noisy Image pass beside a denoised Combined
scenes.exr_output(sc, str(outdir / "denoised.exr"))
bpy.ops.render.render(write_still=True)
print(json.dumps(report))
