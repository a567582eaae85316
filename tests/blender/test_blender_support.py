"""Shared set-up of the Blender tests (add-on registration, EXR reading, test scenes), and tests of it.

The other tests/blender/test_*.py import from here after skipping themselves when bpy is missing. Importing this
module makes the add-on importable as `restircl_blender` (restircl.io.blend.addon_module: an installed extension,
else the checkout's addon/ folder), so the tests import its modules by name.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

bpy = pytest.importorskip("bpy")

from restircl.eval import blender_scenes as scenes  # noqa: E402
from restircl.io.blend import addon_module  # noqa: E402
from restircl.render.passes import PASSES  # noqa: E402

ADDON = addon_module()

pytestmark = pytest.mark.blender

CHANNEL_ORDER = {name: p.channels for p in PASSES for name in {p.blender, p.blender_4} if name}


def ensure_registered():
    """Register the add-on once per process (its register(), as docs/blender.md says)."""
    if not hasattr(bpy.types.Scene, "restircl"):
        ADDON.register()
    return ADDON


def has_renderer() -> bool:
    try:
        import restircl
    except ImportError:
        return False
    return hasattr(restircl, "Renderer")


needs_renderer = pytest.mark.skipif(not has_renderer(), reason="restircl.Renderer is not available")


def read_exr_passes(path: str | Path) -> dict[str, np.ndarray]:
    """Passes of a (multi-part) multilayer EXR written by Blender: name -> (H, W, C) float32, rows top first."""
    import OpenEXR

    chans: dict[str, np.ndarray] = {}
    with OpenEXR.File(str(path), separate_channels=True) as f:
        for part in f.parts:
            for name, ch in part.channels.items():
                chans[name] = np.asarray(ch.pixels, dtype=np.float32)
    passes: dict[str, dict[str, np.ndarray]] = {}
    for name, px in chans.items():
        parts = name.split(".")
        if len(parts) < 2:
            passes.setdefault("", {})[parts[-1]] = px
            continue
        pass_name, chan = parts[-2], parts[-1]
        passes.setdefault(pass_name, {})[chan] = px
    out = {}
    for pass_name, cs in passes.items():
        order = CHANNEL_ORDER.get(pass_name) or "".join(sorted(cs))
        out[pass_name] = np.stack([cs[c] for c in order if c in cs], axis=-1)
    return out


def relmse(ours: np.ndarray, ref: np.ndarray, eps: float = 1e-2) -> float:
    ours = np.asarray(ours, dtype=np.float64)[..., :3]
    ref = np.asarray(ref, dtype=np.float64)[..., :3]
    return float(np.mean((ours - ref) ** 2 / (ref * ref + eps)))


# Cycles' images of this process by the caller's name for the scene (`shared`) and the sample count. A negative
# control spoils only our side of a comparison that an agreement test of its file has rendered already: the same
# scene, samples and seed give Cycles' same image, so the control reads it instead of rendering it again. The
# scene's fingerprint guards the name against a scene that differs.
_CYCLES_IMAGES: dict[tuple, tuple[str, np.ndarray]] = {}


def scene_fingerprint(sc) -> str:
    """What a misnamed shared scene would most likely differ in: the frame, the resolution and film, the objects and
    where they are, the camera's lens and the shutter."""
    cam = sc.camera.data if sc.camera else None
    lens = (cam.type, cam.lens, cam.dof.use_dof, cam.dof.aperture_fstop, cam.dof.aperture_blades,
            cam.dof.aperture_rotation, cam.dof.aperture_ratio, cam.dof.focus_distance) if cam else None
    r = sc.render
    # the objects' own transforms: matrix_world is stale until the scene is evaluated
    objects = sorted((ob.name, ob.type, ob.visible_camera, ob.is_holdout,
                      tuple(round(v, 6) for v in (*ob.location, *ob.rotation_euler, *ob.scale))) for ob in sc.objects)
    return repr((sc.frame_current, r.resolution_x, r.resolution_y, r.film_transparent, r.use_motion_blur,
                 r.motion_blur_shutter, r.motion_blur_position, lens, objects))


def cycles_image(tmp_path: Path, sc, samples: int, shared: tuple | None = None) -> np.ndarray:
    """Cycles' Combined pass of `sc` (direct light only, seed 1); `shared`: the caller's name for the scene (e.g.
    the builder's arguments), under which the image is kept for the other tests of this process."""
    scenes.cycles_direct_only(sc, samples=samples, seed=1, threads=2)
    key = (shared, samples)
    if shared is not None and key in _CYCLES_IMAGES:
        fingerprint, image = _CYCLES_IMAGES[key]
        assert fingerprint == scene_fingerprint(sc), f"the shared Cycles scene {shared} is not the one rendered"
        return image
    render_to(sc, tmp_path / "cycles.exr")
    image = read_exr_passes(tmp_path / "cycles.exr")["Combined"]
    if shared is not None:
        image.flags.writeable = False
        _CYCLES_IMAGES[key] = (scene_fingerprint(sc), image)
    return image


def cycles_and_ours(tmp_path: Path, sc, cycles_samples: int, our_samples: int, label: str,
                    shared: tuple | None = None, **settings) -> tuple[float, float]:
    """Render `sc` with Cycles (direct light only; `shared`: cycles_image's) and with restircl's reference method
    (`settings`: more scene.restircl properties); (relMSE, sum ours / sum Cycles)."""
    ensure_registered()
    cyc = cycles_image(tmp_path, sc, cycles_samples, shared)
    sc.render.engine = "RESTIRCL"
    sc.restircl.method = "reference"
    sc.restircl.samples = our_samples
    for name, value in settings.items():
        setattr(sc.restircl, name, value)
    render_to(sc, tmp_path / "ours.exr")
    ours = read_exr_passes(tmp_path / "ours.exr")["Combined"]
    err = relmse(ours, cyc)
    ratio = float(ours[..., :3].sum() / cyc[..., :3].sum())
    print(f"{label}: relMSE {100 * err:.3f} %  sum ours/cycles {ratio:.4f}")
    assert cyc[..., :3].mean() > 0.01, "the comparison scene is dark: nothing is tested"
    return err, ratio


def assert_agrees(tmp_path: Path, sc, cycles_samples: int, our_samples: int, label: str, record_property,
                  bound: float = 0.01, shared: tuple | None = None) -> float:
    """cycles_and_ours, asserted: relMSE below `bound`, the image sums within 1 %; returns the relMSE."""
    err, ratio = cycles_and_ours(tmp_path, sc, cycles_samples, our_samples, label, shared)
    record_property("relmse", err)
    assert err < bound, f"{label}: relMSE {100 * err:.3f} % against Cycles"
    assert ratio == pytest.approx(1.0, abs=0.01)
    return err


def guard_engine(monkeypatch) -> list[int]:
    """One entry per unexpected exception that the engine's last-resort handler catches (and prints) from now on:
    a test asserts it stays empty."""
    addon = ensure_registered()
    crashes: list[int] = []
    monkeypatch.setattr(addon.engine.traceback, "print_exc", lambda *a, **k: crashes.append(1))
    return crashes


def record_engine(monkeypatch) -> tuple[list[str], list[str]]:
    """(reports, stats): the messages the engine reports (RenderEngine.report) and the status lines it shows
    (update_stats) in the renders from now on."""
    addon = ensure_registered()
    reports: list[str] = []
    stats: list[str] = []

    class Recorder:
        def __init__(self, engine):
            self._engine = engine

        def update_stats(self, a, b):
            stats.append(b)
            self._engine.update_stats(a, b)

        def report(self, kind, msg):
            reports.append(msg)
            self._engine.report(kind, msg)

        def __getattr__(self, name):
            return getattr(self._engine, name)

    real = addon.engine.render
    monkeypatch.setattr(addon.engine, "render", lambda engine, depsgraph: real(Recorder(engine), depsgraph))
    return reports, stats


def render_to(scene, path: Path, animation: bool = False) -> None:
    scenes.exr_output(scene, str(path))
    if animation:
        bpy.ops.render.render(animation=True)
    else:
        bpy.ops.render.render(write_still=True)


# ---- tests of the helpers -------------------------------------------------------------------------------


def test_new_scene_is_empty_with_black_world():
    sc = scenes.new_scene(32, 24)
    assert len(sc.objects) == 0
    bg = sc.world.node_tree.nodes["Background"]
    assert bg.inputs["Strength"].default_value == 0.0
    assert (sc.render.resolution_x, sc.render.resolution_y) == (32, 24)


def test_read_exr_passes_roundtrip(tmp_path):
    """Blender 5 writes multilayer EXRs as multi-part files; the reader must see every part."""
    sc = scenes.comparison_scene("sun", 16, 12)
    scenes.cycles_direct_only(sc, samples=4, threads=2)
    vl = sc.view_layers[0]
    vl.use_pass_z = True
    vl.use_pass_normal = True
    render_to(sc, tmp_path / "cycles.exr")
    passes = read_exr_passes(tmp_path / "cycles.exr")
    assert passes["Combined"].shape == (12, 16, 4)
    assert passes["Depth"].shape == (12, 16, 1)
    assert passes["Normal"].shape == (12, 16, 3)
    assert np.all(np.isfinite(passes["Combined"]))
