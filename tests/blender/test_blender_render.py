"""Rendering through bpy.ops.render.render with the RESTIRCL engine: EXR outputs and passes, a still's Target Error
and stats line, animation history, and bad scenes that must give a report (RuntimeError from the operator), never
an unhandled exception."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

bpy = pytest.importorskip("bpy")

from restircl.eval import blender_scenes as scenes  # noqa: E402

from .test_blender_support import (  # noqa: E402
    guard_engine,
    needs_renderer,
    read_exr_passes,
    record_engine,
    render_to,
)

pytestmark = [pytest.mark.blender, needs_renderer]

W, H = 48, 32


@pytest.fixture(autouse=True)
def _addon(monkeypatch):
    crashes = guard_engine(monkeypatch)
    yield
    assert not crashes, "the engine hit an unexpected exception (caught by its last-resort handler)"


def small_scene(method: str = "restir", samples: int = 4):
    sc = scenes.new_scene(W, H, engine="RESTIRCL")
    scenes.quad("Floor", 10.0, 10.0, scenes.diffuse_material("Floor", (0.8, 0.8, 0.8)))
    scenes.quad("Wall", 10.0, 4.0, scenes.diffuse_material("Wall", (0.5, 0.6, 0.7)), location=(0, 2.5, 2),
                rotation=(math.pi / 2, 0, 0), facing_down=True)
    scenes.box("Box", (0.8, 0.8, 0.8), scenes.diffuse_material("Red", (0.8, 0.2, 0.1)), location=(0.3, 0, 0.4))
    scenes.light("POINT", "Point", (-1.0, -0.5, 1.5), energy=60.0)
    scenes.light("AREA", "Area", (1.0, 0.0, 2.2), energy=80.0, shape="DISK", size=0.8)
    scenes.quad("Lamp", 0.6, 0.3, scenes.emission_material("Glow", (1.0, 0.7, 0.4), 6.0), location=(0, 1.0, 1.8),
                facing_down=True)
    scenes.camera((0.0, -5.0, 2.5), (0.0, 0.5, 0.6), lens=28.0)
    vl = sc.view_layers[0]
    vl.use_pass_z = vl.use_pass_normal = vl.use_pass_vector = True
    sc.restircl.method = method
    sc.restircl.samples = samples
    return sc


def check_passes(p: dict, moving: bool = False) -> None:
    for name, ch in (("Combined", 4), ("Depth", 1), ("Normal", 3), ("Vector", 4), ("Noisy Direct", 3)):
        assert name in p, f"pass {name} missing from {sorted(p)}"
        assert p[name].shape == (H, W, ch), name
        assert np.all(np.isfinite(p[name])), name
    rgba = p["Combined"]
    assert np.all(rgba[..., 3] == 1.0)
    assert rgba[..., :3].min() >= 0.0 and rgba[..., :3].mean() > 0.01
    depth = p["Depth"][..., 0]
    hit = depth < 1e9
    assert hit.mean() > 0.9 and np.all(depth[hit] > 0)
    n = np.linalg.norm(p["Normal"][hit], axis=-1)
    assert np.allclose(n, 1.0, atol=1e-3)
    noisy = p["Noisy Direct"]
    assert noisy.min() >= 0.0 and noisy.mean() > 0.01
    if moving:
        assert np.abs(p["Vector"][..., :2]).max() > 0.05


def test_still_render_writes_all_passes(tmp_path):
    sc = small_scene(samples=8)
    render_to(sc, tmp_path / "still.exr")
    p = read_exr_passes(tmp_path / "still.exr")
    check_passes(p)
    assert np.all(p["Vector"] == 0.0)  # a still scene does not move
    # the accumulated image is an average of the noisy estimates: close in the mean, smoother per pixel
    c, nz = p["Combined"][..., :3], p["Noisy Direct"]
    assert abs(c.mean() - nz.mean()) < 0.25 * c.mean()


def test_still_rows_and_depth_match_cycles(tmp_path):
    """Rows come out top-first like Cycles (Blender's render result is bottom-first) and Depth means the same."""
    sc = small_scene(method="reference", samples=4)
    render_to(sc, tmp_path / "ours.exr")
    scenes.cycles_direct_only(sc, samples=16, threads=2)
    render_to(sc, tmp_path / "cycles.exr")
    ours, cyc = read_exr_passes(tmp_path / "ours.exr"), read_exr_passes(tmp_path / "cycles.exr")
    d_o, d_c = ours["Depth"][..., 0], cyc["Depth"][..., 0]
    both = (d_o < 1e9) & (d_c < 1e9)
    assert both.mean() > 0.85
    rel = np.abs(d_o - d_c)[both] / d_c[both]
    assert np.median(rel) < 0.01
    assert np.mean((d_o < 1e9) == (d_c < 1e9)) > 0.97  # misses (1e10 in both) in the same place
    dot = np.sum(ours["Normal"] * cyc["Normal"], axis=-1)[both]
    assert np.median(dot) > 0.999


def test_second_still_render_reuses_the_renderer(tmp_path):
    from restircl_blender import engine

    sc = small_scene(samples=2)
    render_to(sc, tmp_path / "a.exr")
    first = engine._SESSIONS[(sc.name, sc.view_layers[0].name)].renderer
    render_to(sc, tmp_path / "b.exr")
    assert engine._SESSIONS[(sc.name, sc.view_layers[0].name)].renderer is first
    bpy.data.objects["Point"].location.x += 0.5
    render_to(sc, tmp_path / "c.exr")
    assert engine._SESSIONS[(sc.name, sc.view_layers[0].name)].renderer is not first


def test_still_render_uses_the_still_estimator_and_the_user_can_override_it(tmp_path):
    import restircl
    from restircl_blender import engine

    sc = small_scene(samples=2)  # ReSTIR, with an emissive lamp: auto renders stills with RIS + BSDF candidates
    key = (sc.name, sc.view_layers[0].name)
    render_to(sc, tmp_path / "auto.exr")
    used = engine._SESSIONS[key].renderer.settings
    assert used == restircl.still_settings(restircl.Settings(**sc.restircl.settings_kwargs()),
                                           engine._SESSIONS[key].export.scene)
    assert (used.method, used.bsdf_sampling) == ("ris", "on")
    sc.restircl.still_method = "as_set"
    render_to(sc, tmp_path / "as_set.exr")
    assert engine._SESSIONS[key].renderer.settings.method == "restir"
    check_passes(read_exr_passes(tmp_path / "as_set.exr"))


def test_target_error_and_stats_line(tmp_path, monkeypatch):
    """The add-on's Target Error stops a still render (F12), and the stats line shows the estimate and the
    compiled features (the estimate itself: tests/render/test_error_estimate.py)."""
    reports, stats = record_engine(monkeypatch)
    sc = small_scene("ris", samples=20_000)
    sc.restircl.target_error = 3e-3
    render_to(sc, tmp_path / "target.exr")
    assert np.all(np.isfinite(read_exr_passes(tmp_path / "target.exr")["Combined"]))
    stopped = [m for m in reports if "stopped after" in m]
    assert stopped, reports
    assert int(stopped[0].split("stopped after ")[1].split()[0]) < 20_000
    assert any("est. relMSE" in s for s in stats), stats[-3:]
    assert any("compiled:" in s for s in stats), stats[-3:]
    est = float(stats[-1].split("est. relMSE ")[1].split()[0])
    assert est <= 3e-3 and math.isfinite(est)


def test_animation_without_gbuffer_passes_writes_the_image(tmp_path):
    sc = small_scene()
    vl = sc.view_layers[0]
    vl.use_pass_z = vl.use_pass_normal = vl.use_pass_vector = False
    sc.frame_start, sc.frame_end = 1, 2
    render_to(sc, tmp_path / "anim_", animation=True)
    for f in sorted(tmp_path.glob("anim_*.exr")):
        p = read_exr_passes(f)
        assert "Depth" not in p and p["Combined"].shape == (H, W, 4)
        assert np.all(np.isfinite(p["Combined"])) and p["Combined"][..., :3].mean() > 0.01


def test_film_transparent_alpha(tmp_path):
    sc = small_scene(samples=1)
    sc.render.film_transparent = True
    bpy.data.objects.remove(bpy.data.objects["Wall"])
    scenes.point_at(sc.camera, (0.0, 4.0, 1.5))  # the sky above the floor's far edge
    render_to(sc, tmp_path / "t.exr")
    p = read_exr_passes(tmp_path / "t.exr")
    miss = p["Depth"][..., 0] > 1e9
    assert miss.any() and (~miss).any()
    assert np.all(p["Combined"][..., 3][miss] == 0.0) and np.all(p["Combined"][..., 3][~miss] == 1.0)


def test_animation_carries_history(tmp_path):
    from restircl_blender import engine

    sc = small_scene()
    cam, box = sc.camera, bpy.data.objects["Box"]
    sc.frame_start, sc.frame_end = 1, 3
    for f in (1, 3):
        cam.location.x = 0.0 if f == 1 else 0.6
        cam.keyframe_insert("location", frame=f)
        box.location.x = 0.3 if f == 1 else -0.3
        box.keyframe_insert("location", frame=f)
    seen = []

    def record(*_args):
        s = engine._SESSIONS.get((sc.name, sc.view_layers[0].name))
        seen.append((sc.frame_current, id(s.renderer) if s else None, s.last_frame if s else None))

    bpy.app.handlers.render_post.append(record)
    try:
        render_to(sc, tmp_path / "anim_", animation=True)
    finally:
        bpy.app.handlers.render_post.remove(record)
    files = sorted(tmp_path.glob("anim_*.exr"))
    assert [f.name for f in files] == ["anim_0001.exr", "anim_0002.exr", "anim_0003.exr"]
    for i, f in enumerate(files):  # keyframes at 1 and 3 ease in: frame 1 has no motion from frame 0
        check_passes(read_exr_passes(f), moving=i > 0)
    # one renderer for the three frames: the ReSTIR and TAA history went from frame to frame
    assert [s[0] for s in seen] == [1, 2, 3]
    assert len({s[1] for s in seen}) == 1 and seen[0][1] is not None
    assert [s[2] for s in seen] == [1, 2, 3]
    assert (sc.name, sc.view_layers[0].name) not in engine._SESSIONS  # dropped when the job completed


def test_animation_warmup_and_camera_cut(tmp_path):
    sc = small_scene()
    sc.restircl.warmup_frames = 2
    cam_b = scenes.camera((3.0, -3.0, 2.0), (0, 0, 0.5), name="CamB", make_active=False)
    sc.timeline_markers.new("A", frame=1).camera = sc.camera
    sc.timeline_markers.new("B", frame=3).camera = cam_b
    sc.frame_start, sc.frame_end = 1, 3
    render_to(sc, tmp_path / "cut_", animation=True)
    frames = [read_exr_passes(tmp_path / f"cut_000{i}.exr") for i in (1, 2, 3)]
    for p in frames:
        check_passes(p)
    # frame 3 is seen from the other camera
    assert not np.allclose(frames[2]["Depth"], frames[1]["Depth"])


@pytest.mark.parametrize("name", ["many_lights", "area_interior"])
def test_example_scenes_render(tmp_path, name):
    path = scenes_dir() / f"{name}.blend"
    if bpy.app.version < (5, 0, 0):  # the files are written by Blender 5.0, which older releases cannot read
        getattr(scenes, f"{name}_scene")()
        bpy.context.scene.render.engine = "RESTIRCL"
    elif not path.exists():
        pytest.skip(f"{path} not built (python -m restircl.eval.blender_scenes)")
    else:
        bpy.ops.wm.open_mainfile(filepath=str(path))
    sc = bpy.context.scene
    assert sc.render.engine == "RESTIRCL"
    sc.render.resolution_percentage = 15
    sc.restircl.samples = 1
    render_to(sc, tmp_path / f"{name}.exr")
    c = read_exr_passes(tmp_path / f"{name}.exr")["Combined"]
    assert np.all(np.isfinite(c)) and c[..., :3].mean() > 0.005


def scenes_dir() -> Path:
    """The checkout's blend/ folder, which holds the example .blend files."""
    return Path(__file__).resolve().parents[2] / "blend"


# ---- bad scenes: a report, not an exception -------------------------------------------------------------


def render_error(sc) -> str:
    with pytest.raises(RuntimeError) as info:
        bpy.ops.render.render(write_still=False)
    return str(info.value)


def test_nan_transform_reports():
    sc = small_scene()
    bpy.data.objects["Box"].location = (float("nan"), 0.0, 0.0)
    msg = render_error(sc)
    assert "restircl:" in msg and "NaN" in msg and "unexpected" not in msg


def test_no_device_that_builds_is_one_report_naming_what_to_install(monkeypatch, capfd):
    """On a machine where no OpenCL device builds the kernels (a Windows PC without a GPU driver's OpenCL, say),
    F12 gives one error report that says what to install on this system, and no traceback."""
    import sys

    from restircl.core import device as device_mod
    from restircl.core.install_hint import install_hint

    sc = small_scene()
    sc.restircl.device = ""
    monkeypatch.delenv("RESTIRCL_DEVICE", raising=False)
    monkeypatch.setattr(device_mod, "build_problem", lambda dev: "cannot build kernels: test")
    for name, module in list(sys.modules.items()):  # no renderer kept from an earlier F12 of the same scene
        if name.endswith("restircl_blender.engine"):
            module.clear_sessions()
    capfd.readouterr()
    msg = render_error(sc)
    assert "restircl: no OpenCL device can build kernels; " + install_hint() in msg and "unexpected" not in msg
    assert "Traceback" not in "".join(capfd.readouterr())


def test_negative_light_and_emission_strength_render(tmp_path):
    """Negative strengths are left out (a warning at export: blender/test_blender_export.py), never a failed render."""
    sc = small_scene(samples=2)
    bpy.data.objects["Point"].data.energy = -10.0
    if bpy.data.objects["Point"].data.energy >= 0:
        pytest.skip("this Blender clamps light power at 0")
    glow = bpy.data.materials["Glow"].node_tree.nodes
    next(n for n in glow if n.bl_idname == "ShaderNodeEmission").inputs["Strength"].default_value = -6.0
    render_to(sc, tmp_path / "neg.exr")
    rgba = read_exr_passes(tmp_path / "neg.exr")["Combined"]
    assert np.all(np.isfinite(rgba)) and rgba[..., :3].min() >= 0.0 and rgba[..., :3].mean() > 0.01


def test_no_camera_reports():
    sc = small_scene()
    sc.camera = None
    for ob in [o for o in sc.objects if o.type == "CAMERA"]:
        bpy.data.objects.remove(ob)
    msg = render_error(sc)
    assert "camera" in msg.lower()


def test_missing_device_reports():
    sc = small_scene()
    sc.restircl.device = "no-such-opencl-device"
    msg = render_error(sc)
    assert "restircl:" in msg and "no-such-opencl-device" in msg


def test_kernel_build_failure_reports(monkeypatch):
    import restircl

    def broken(*_args, **_kwargs):
        raise restircl.KernelBuildError("OpenCL build failed: lights/lights.h:12: error: boom", "log",
        "lights/lights.h:12")

    sc = small_scene()
    sc.restircl.seed = 12345  # a fresh session: the cached renderer of an identical scene is not reused
    monkeypatch.setattr(restircl, "Renderer", broken)
    msg = render_error(sc)
    assert "restircl:" in msg and "lights/lights.h:12" in msg


def test_empty_scene_renders_black_with_a_warning(tmp_path, capfd):
    sc = scenes.new_scene(W, H, engine="RESTIRCL")
    scenes.camera()
    sc.restircl.samples = 1
    render_to(sc, tmp_path / "empty.exr")
    out = capfd.readouterr()
    assert "empty" in (out.out + out.err)
    p = read_exr_passes(tmp_path / "empty.exr")
    assert np.all(p["Combined"][..., :3] == 0.0)
