"""Animations of .blend files in chunks: Blender's own command line per chunk, as Flamenco runs it (`blender -b
file.blend -E RESTIRCL -s A -e B -a`, here bpy.ops.render.render(animation=True) with frame_start/frame_end), and
restircl's farm with bpy workers (each opens the file and exports it once with the add-on)."""

from __future__ import annotations

import logging
from dataclasses import asdict

import numpy as np
import pytest

bpy = pytest.importorskip("bpy")
distributed = pytest.importorskip("distributed")

from restircl import (  # noqa: E402
    Settings,
    read_exr,
)
from restircl.farm.chunks import FrameRange, plan_chunks  # noqa: E402
from restircl.farm.cluster import run_farm  # noqa: E402
from restircl.farm.worker import Job, SceneSource, render_chunk  # noqa: E402

from .test_blender_render import small_scene  # noqa: E402
from .test_blender_support import ensure_registered, needs_renderer, read_exr_passes, render_to  # noqa: E402

pytestmark = [pytest.mark.blender, needs_renderer]


def _moving(sc, frames=(1, 6)):
    cam = sc.camera
    for f, x in zip(frames, (0.0, 0.5), strict=True):
        cam.location.x = x
        cam.keyframe_insert("location", frame=f)


def _render_range(sc, path, first, last, warmup):
    sc.frame_start, sc.frame_end = first, last
    sc.restircl.warmup_frames = warmup
    render_to(sc, path, animation=True)


def test_flamenco_chunks_draw_the_same_noise_as_one_render(tmp_path):
    """RIS without reuse: a frame's Noisy Direct pass depends on its camera and random stream only, so frames 4-5
    rendered as a chunk (2 warm-up frames) equal frames 4-5 of the whole range 1-5, bit for bit: the stream is
    keyed by the Blender frame number, not by the frame's place in the job."""
    ensure_registered()
    sc = small_scene(method="ris")
    # the bounced light (Cycles' default Light Paths) without ReSTIR GI's reuse, which carries history as ReSTIR DI's
    sc.restircl.gi_reuse = False
    _moving(sc)
    _render_range(sc, tmp_path / "all_", 1, 5, 0)
    _render_range(sc, tmp_path / "chunk_", 4, 5, 2)
    for f in (4, 5):
        a = read_exr_passes(tmp_path / f"all_000{f}.exr")["Noisy Direct"]
        b = read_exr_passes(tmp_path / f"chunk_000{f}.exr")["Noisy Direct"]
        assert np.array_equal(a, b), f
    assert not np.array_equal(read_exr_passes(tmp_path / "all_0004.exr")["Noisy Direct"],
                              read_exr_passes(tmp_path / "all_0005.exr")["Noisy Direct"])


@pytest.mark.parametrize("warmup", [0, 3])
def test_first_kept_frame_of_a_chunk_has_its_warmup_history(tmp_path, warmup):
    """A still camera: the TAA history length of every pixel at the chunk's first frame is 1 + the warm-up frames
    rendered before it (1 without: no history)."""
    from restircl_blender import engine

    ensure_registered()
    sc = small_scene()
    sc.view_layers[0].use_pass_vector = False  # the Vector pass would ask for one frame before the first
    seen = []

    def record(*_args):
        s = engine._SESSIONS.get((sc.name, sc.view_layers[0].name))
        seen.append(s.renderer.history_length())

    bpy.app.handlers.render_post.append(record)
    try:
        _render_range(sc, tmp_path / "c_", 7, 8, warmup)
    finally:
        bpy.app.handlers.render_post.remove(record)
    assert len(seen) == 2
    assert np.all(seen[0] == 1 + warmup) and np.all(seen[1] == 2 + warmup)


def test_blend_on_bpy_workers(tmp_path):
    """A .blend on a local cluster of 2 bpy workers, 2 chunks with a warm-up frame each: the frames are written,
    and equal those of the same chunks rendered in this process (the same export, the same streams)."""
    ensure_registered()
    sc = small_scene()
    sc.render.resolution_x, sc.render.resolution_y = 24, 16
    _moving(sc, (1, 4))
    blend = tmp_path / "anim.blend"
    bpy.ops.wm.save_as_mainfile(filepath=str(blend))
    frames, warmup = FrameRange(1, 4), 1
    settings = asdict(Settings(warmup_frames=warmup))
    chunks = plan_chunks(frames, 2, warmup, earliest=frames.first - warmup)

    def job(out):
        return Job("anim", str(out), SceneSource.of_path(blend), settings, index_offset=frames.first - warmup,
                   export_last=frames.last)

    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None,
                                  silence_logs=logging.ERROR) as cluster:
        res = run_farm(job(tmp_path / "farm"), chunks, scheduler=cluster.scheduler_address)
    assert res.written == 4 and [r.rendered for r in res.reports] == [3, 3]
    local = job(tmp_path / "local")
    for c in chunks:
        render_chunk(local, c)
    for f in frames.frames():
        a = read_exr(tmp_path / "farm" / f"anim_000{f}.exr")
        b = read_exr(tmp_path / "local" / f"anim_000{f}.exr")
        assert a.keys() == b.keys() and all(np.array_equal(a[k], b[k]) for k in a), f


def test_farm_honours_the_render_region(tmp_path):
    """A .blend with a Render Region on a local cluster of 2 bpy workers: the workers render the region alone
    (its camera, its size) and write it where the frame has it, empty elsewhere (alpha 0, depth 1e10: nothing
    there); with Crop to Render Region the frames are the region alone, the same pixels. The region's depth is the
    whole frame's there: the region's camera is the whole camera's, in part."""
    ensure_registered()
    sc = small_scene()
    sc.render.resolution_x, sc.render.resolution_y = 32, 24
    _moving(sc, (1, 2))
    r = sc.render
    r.use_border, r.use_crop_to_border = True, False
    # Blender truncates the border to whole pixels: columns 8..23, rows 6..17 from the bottom (6..17 from the top)
    r.border_min_x, r.border_max_x, r.border_min_y, r.border_max_y = 0.25, 0.75, 0.25, 0.75
    cols, rows = slice(8, 24), slice(6, 18)
    paths = {}
    for name, border, crop in (("whole", False, False), ("placed", True, False), ("cropped", True, True)):
        r.use_border, r.use_crop_to_border = border, crop
        paths[name] = tmp_path / f"{name}.blend"
        bpy.ops.wm.save_as_mainfile(filepath=str(paths[name]))
    frames = FrameRange(1, 2)
    chunks = plan_chunks(frames, 1, 0, earliest=frames.first)

    def job(name):
        return Job(name, str(tmp_path / "out"), SceneSource.of_path(paths[name]), asdict(Settings()),
                   index_offset=frames.first, export_last=frames.last)

    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None,
                                  silence_logs=logging.ERROR) as cluster:
        res = run_farm(job("placed"), chunks, scheduler=cluster.scheduler_address)
    assert res.written == 2
    for c in chunks:  # the same job's reference renders, in this process
        render_chunk(job("whole"), c)
        render_chunk(job("cropped"), c)
    inside = np.zeros((24, 32), bool)
    inside[rows, cols] = True
    for f in frames.frames():
        whole = read_exr(tmp_path / "out" / f"whole_000{f}.exr")
        placed = read_exr(tmp_path / "out" / f"placed_000{f}.exr")
        cropped = read_exr(tmp_path / "out" / f"cropped_000{f}.exr")
        assert whole["R"].shape == placed["R"].shape == (24, 32) and cropped["R"].shape == (12, 16)
        assert placed.keys() == cropped.keys() == whole.keys()
        for k in placed:  # the cropped frame is the placed frame's region, bit for bit
            assert np.array_equal(placed[k][rows, cols], cropped[k], equal_nan=True), k
        assert all(np.all(placed[c][~inside] == 0.0) for c in "RGBA"), "pixels outside the region were written"
        assert np.all(placed["A"][inside] == 1.0) and placed["R"][inside].mean() > 0.01
        assert np.all(placed["Depth.Z"][~inside] == 1e10)
        assert np.allclose(placed["Depth.Z"][rows, cols], whole["Depth.Z"][rows, cols], rtol=1e-4)
