"""Shared set-up of the Blender tests (add-on registration, EXR reading, test scenes), and tests of it.

The other tests/test_blender_*.py import from here after skipping themselves when bpy is missing.
"""

from __future__ import annotations

import math
import sys
from pathlib import Path

import numpy as np
import pytest

bpy = pytest.importorskip("bpy")

ROOT = Path(__file__).resolve().parent.parent
for _p in (ROOT / "addon", ROOT / "blend"):
    if str(_p) not in sys.path:
        sys.path.insert(0, str(_p))

import scenes  # noqa: E402  (blend/scenes.py)
from restircl.passes import PASSES  # noqa: E402

pytestmark = pytest.mark.blender

CHANNEL_ORDER = {name: p.channels for p in PASSES for name in {p.blender, p.blender_4} if name}


def ensure_registered():
    """Register the add-on once per process (as docs/blender.md says: sys.path + register())."""
    import restircl_blender

    if not hasattr(bpy.types.Scene, "restircl"):
        restircl_blender.register()
    return restircl_blender


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


def cycles_and_ours(tmp_path: Path, sc, cycles_samples: int, our_samples: int, label: str,
                    **settings) -> tuple[float, float]:
    """Render `sc` with Cycles (direct light only) and with restircl's reference method (`settings`: more
    scene.restircl properties); (relMSE, sum ours / sum Cycles)."""
    ensure_registered()
    scenes.cycles_direct_only(sc, samples=cycles_samples, seed=1, threads=2)
    render_to(sc, tmp_path / "cycles.exr")
    sc.render.engine = "RESTIRCL"
    sc.restircl.method = "reference"
    sc.restircl.samples = our_samples
    for name, value in settings.items():
        setattr(sc.restircl, name, value)
    render_to(sc, tmp_path / "ours.exr")
    cyc = read_exr_passes(tmp_path / "cycles.exr")["Combined"]
    ours = read_exr_passes(tmp_path / "ours.exr")["Combined"]
    err = relmse(ours, cyc)
    ratio = float(ours[..., :3].sum() / cyc[..., :3].sum())
    print(f"{label}: relMSE {100 * err:.3f} %  sum ours/cycles {ratio:.4f}")
    assert cyc[..., :3].mean() > 0.01, "the comparison scene is dark: nothing is tested"
    return err, ratio


def render_to(scene, path: Path, animation: bool = False) -> None:
    scenes.exr_output(scene, str(path))
    if animation:
        bpy.ops.render.render(animation=True)
    else:
        bpy.ops.render.render(write_still=True)


LIGHT_KINDS = ("point", "sphere", "sphere_soft", "spot", "sun", "area_square", "area_rectangle", "area_disk",
               "area_ellipse", "emission")


def comparison_scene(kind: str, width: int = 64, height: int = 48):
    """A floor, a wall and a box (for shadows) lit by one kind of light, or every kind for 'mixed'.
    Light objects are hidden from camera rays (restircl does not draw lights; emissive meshes it does)."""
    sc = scenes.new_scene(width, height)
    scenes.quad("Floor", 12.0, 12.0, scenes.diffuse_material("Floor", (0.8, 0.8, 0.8)))
    scenes.quad("Wall", 12.0, 4.0, scenes.diffuse_material("Wall", (0.6, 0.7, 0.5)), location=(0, 3, 2),
                rotation=(math.pi / 2, 0, 0), facing_down=True)
    scenes.box("Box", (0.8, 0.8, 0.8), scenes.diffuse_material("BoxMat", (0.7, 0.3, 0.2)),
               location=(0.3, 0.2, 0.4), rotation=(0, 0, 0.5))
    scenes.camera((0, -5.5, 3.5), (0, 0.5, 0.3), lens=30.0)
    mixed = kind == "mixed"

    def add(*args, **kwargs):
        ob = scenes.light(*args, **kwargs)
        ob.visible_camera = False
        return ob

    if kind == "point" or mixed:
        add("POINT", "Point", (-1.2, -0.5, 1.5), energy=80.0, shadow_soft_size=0.0, color=(1.0, 0.9, 0.8))
    if kind in ("sphere", "sphere_soft"):
        add("POINT", "Sphere", (-1.0, -0.3, 1.2), energy=80.0, shadow_soft_size=0.3,
            use_soft_falloff=kind == "sphere_soft")
    if kind == "spot" or mixed:
        add("SPOT", "Spot", (1.5, -1.0, 2.5), (math.radians(20), math.radians(15), 0), energy=200.0,
            spot_size=math.radians(60), spot_blend=0.4, shadow_soft_size=0.0, color=(0.7, 0.8, 1.0))
    if kind == "sun" or mixed:
        add("SUN", "Sun", (0, 0, 5), (math.radians(30), math.radians(-20), 0), energy=1.5, angle=math.radians(5))
    for shape, sx, sy in (("SQUARE", 1.0, 1.0), ("RECTANGLE", 1.5, 0.5), ("DISK", 1.0, 1.0),
                          ("ELLIPSE", 1.5, 0.6)):
        if kind == "area_" + shape.lower() or (mixed and shape in ("RECTANGLE", "DISK")):
            loc = (-0.5, -0.5, 2.0) if shape != "DISK" or not mixed else (-2.0, 1.0, 1.8)
            add("AREA", "Area" + shape.title(), loc, (math.radians(15), 0, 0.3), energy=120.0, shape=shape,
                size=sx, size_y=sy)
    if kind == "emission" or mixed:
        scenes.quad("Lamp", 0.8, 0.4, scenes.emission_material("Glow", (1.0, 0.6, 0.3), 12.0),
                    location=(1.0, 0.8, 1.8), rotation=(math.radians(-30), 0, 0), facing_down=True)
    return sc


# ---- tests of the helpers -------------------------------------------------------------------------------


def test_new_scene_is_empty_with_black_world():
    sc = scenes.new_scene(32, 24)
    assert len(sc.objects) == 0
    bg = sc.world.node_tree.nodes["Background"]
    assert bg.inputs["Strength"].default_value == 0.0
    assert (sc.render.resolution_x, sc.render.resolution_y) == (32, 24)


def test_read_exr_passes_roundtrip(tmp_path):
    """Blender 5 writes multilayer EXRs as multi-part files; the reader must see every part."""
    sc = comparison_scene("sun", 16, 12)
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
