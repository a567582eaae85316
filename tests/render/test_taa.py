"""Reprojection and TAA: exact motion vectors for a known camera and object motion; a still camera converges as
1/n; no ghost trail behind a moving object under a panning camera; off-screen and disoccluded pixels restart;
a camera cut resets everything; a NaN injected into the history is gone the next frame and counted."""

import math

import numpy as np
import pyopencl as cl
import pytest
from restircl import Renderer, Scene, Settings, look_at, scenes
from restircl.render.camera import camera_record

from ..helpers import rel_mse

W, H = 64, 48
FRAMES = 8


def moving_box_scene(frames: int = FRAMES, pan: float = 0.08, speed: float = 0.3) -> Scene:
    """The built-in moving box with its lights hidden from the camera: these tests measure surfaces, and the sun's
    disk in the sky (radiance ~1e3) would outweigh every error they compare (lights/test_camera_visible.py: lights)."""
    scene = scenes.moving_box(W, H, frames, pan, speed)
    for lt in scene.lights:
        lt.visible_camera = False
    return scene


def project_numpy(cam_rec: np.ndarray, p: np.ndarray) -> np.ndarray:
    """Independent numpy projection of world points (..., 3) to continuous pixel coordinates."""
    c = cam_rec[0]
    d = p - c["origin"][:3]
    z = d @ c["forward"][:3]
    x = (d @ c["right"][:3]) / z
    y = (d @ c["up"][:3]) / z
    tx, ty, sx, sy = c["lens"]
    nx, ny = (x - sx) / tx, (y - sy) / ty
    return np.stack([(nx + 1) * 0.5 * c["width"], (1 - ny) * 0.5 * c["height"]], -1)


def test_motion_vectors_are_exact_for_camera_and_object_motion(device):
    scene = moving_box_scene()
    scene.camera.shift_x = 0.1  # exercise lens shift too
    r = Renderer(scene, Settings(method="light_array", jitter=False), device)
    r.render_frame(2)
    r.render_frame(3)
    g = r.read_gbuffer()
    from restircl.core.layouts import float_bits_to_int

    hit = float_bits_to_int(g["normal"][..., 3]) >= 0
    obj = float_bits_to_int(g["albedo"][..., 3])
    pos = g["pos"][..., :3].astype(np.float64)
    prev_pos = pos.copy()
    moving = hit & (obj == 1)
    prev_pos[moving] -= np.array([0.3, 0.0, 0.0])  # the box moved +0.3 in x between frames 2 and 3
    expect = project_numpy(camera_record(scene.camera, 2), prev_pos)
    ys, xs = np.mgrid[0:H, 0:W]
    centres = np.stack([xs + 0.5, ys + 0.5], -1)
    got = centres + g["motion"][..., :2]
    assert moving.sum() > 20 and (hit & ~moving).sum() > 200
    err = np.abs(got - expect)[hit]
    assert err.max() < 2e-3, err.max()  # sub-pixel exact (float32 round-off only)
    # the hit points really are where the pixel centres project (no jitter): current projection is exact too
    cur = project_numpy(camera_record(scene.camera, 3), pos)
    assert np.abs(cur - centres)[hit].max() < 2e-3
    # the Vector pass (Blender's convention: y up): xy to the previous frame, zw to the next
    vec = r.read_frame(r.sample_buf, r.gbuf[r.last_slot], 3).vector
    next_pos = pos.copy()
    next_pos[moving] += np.array([0.3, 0.0, 0.0])
    expect_next = project_numpy(camera_record(scene.camera, 4), next_pos)
    np.testing.assert_allclose(vec[..., 0][hit], (expect - centres)[..., 0][hit], atol=2e-3)
    np.testing.assert_allclose(vec[..., 1][hit], -(expect - centres)[..., 1][hit], atol=2e-3)
    np.testing.assert_allclose(vec[..., 2][hit], (expect_next - centres)[..., 0][hit], atol=2e-3)
    np.testing.assert_allclose(vec[..., 3][hit], -(expect_next - centres)[..., 1][hit], atol=2e-3)


def test_still_camera_converges_as_one_over_n(device):
    scene = moving_box_scene(frames=1)
    ref = Renderer(scene, Settings(method="ris", candidates=16, seed=1), device).render_still(0, 512).color[..., :3]
    errors = {}
    reps = 6
    for n in (1, 4, 16):
        e = []
        for k in range(reps):
            r = Renderer(scene, Settings(method="ris", taa=True, alpha_min=0.0, seed=100 + k), device)
            for _ in range(n):
                f = r.render_frame(0)
            e.append(rel_mse(f.color[..., :3], ref))
        errors[n] = float(np.mean(e))
    print("relMSE by history length:", errors)
    # a = 1/n makes the output the plain mean of n samples: error ~ 1/n (the reference's own error is ~1/512)
    assert 2.0 < errors[1] / errors[4] < 8.0
    assert 2.0 < errors[4] / errors[16] < 8.0


def render_sequence(scene: Scene, settings: Settings, device) -> tuple[Renderer, list]:
    r = Renderer(scene, settings, device)
    return r, [r.render_frame(f) for f in range(scene.frames)]


def test_no_ghost_trail_behind_a_moving_object(device):
    scene = moving_box_scene()
    last = scene.frames - 1
    refs = Renderer(scene, Settings(method="reference", seed=3), device)
    ref = refs.render_still(last, 256)
    red = lambda img: (img[..., 0] > 0.5) & (img[..., 1] < 0.2)  # noqa: E731
    # pixels that showed the box at some of the last frames but show the floor now
    covered_before = np.zeros((H, W), bool)
    for f in range(last - 3, last):
        covered_before |= red(refs.render_still(f, 1).albedo)
    left = covered_before & ~red(ref.albedo) & np.isfinite(ref.depth)
    assert left.sum() > 15
    settings = Settings(method="ris", candidates=8, seed=5)
    _, taa = render_sequence(scene, settings, device)
    _, ghosty = render_sequence(scene, Settings(method="ris", candidates=8, seed=5, gamma=1e6, depth_tolerance=1e6,
                                                normal_angle=180.0, alpha_min=0.02), device)
    want = ref.color[..., :3]
    noisy = taa[-1].noisy

    def region_err(img: np.ndarray, mask: np.ndarray) -> float:
        # absolute MSE: the region lies in the box's shadow, where relMSE would weigh noise in the dark above all
        return float(np.mean((img[mask] - want[mask]) ** 2))

    e_taa, e_off, e_ghost = (region_err(taa[-1].color[..., :3], left), region_err(noisy, left),
                             region_err(ghosty[-1].color[..., :3], left))
    e_taa_all, e_off_all = region_err(taa[-1].color[..., :3], ~left), region_err(noisy, ~left)
    print(f"left region MSE: taa {e_taa:.4f}, taa off {e_off:.4f}, no rejection/clipping {e_ghost:.4f}; "
          f"elsewhere: taa {e_taa_all:.4f}, off {e_off_all:.4f}")
    assert e_taa <= 1.5 * e_off  # no worse than no TAA where the object was
    assert e_ghost > 2 * e_taa  # the test can see a ghost: without rejection and clipping there is one
    assert e_taa_all < 0.7 * e_off_all  # and TAA does reduce the error elsewhere


def last_depth(r: Renderer) -> np.ndarray:
    g = r.read_gbuffer()
    return np.where(g["normal"][..., 3].view(np.int32) >= 0, g["pos"][..., 3], np.inf)


def test_offscreen_and_disoccluded_pixels_restart(device):
    scene = moving_box_scene(pan=0.4)
    r = Renderer(scene, Settings(method="light_array", seed=1), device)
    for f in range(4):
        r.render_frame(f)
    n3 = r.history_length()
    r.render_frame(4)
    n = r.history_length()
    # the camera pans right by 0.4 m per frame: the rightmost columns of the floor come from off-screen (the sky,
    # at infinity, does not move under a pan and keeps its history)
    hit = np.isfinite(last_depth(r))
    assert np.all(n[:, -2:][hit[:, -2:]] == 1.0) and hit[:, -2:].sum() > 20
    assert np.median(n[~hit]) == 5.0
    assert np.median(n[:, : W // 2]) >= 4.0
    # the box moves right: floor pixels just left of it are newly visible, and restart
    prev = r  # noqa: F841
    del n3
    f4 = r.render_frame(5)
    n5 = r.history_length()
    box_now = (f4.albedo[..., 0] > 0.5) & (f4.albedo[..., 1] < 0.2)
    cols = np.where(box_now.any(axis=0))[0]
    assert len(cols) > 0
    left_edge = cols.min()
    strip = n5[:, max(left_edge - 3, 0):left_edge]
    rows = box_now.any(axis=1)
    assert np.any(strip[rows] == 1.0)


def test_camera_cut_resets_all_history(device):
    scene = moving_box_scene()
    scene.camera.cuts = (3,)
    r = Renderer(scene, Settings(method="light_array", seed=1), device)
    for f in range(3):
        r.render_frame(f)
    assert r.history_length().max() >= 3
    f3 = r.render_frame(3)
    assert np.all(r.history_length() == 1.0)
    np.testing.assert_array_equal(f3.color[..., :3], f3.noisy)


def test_nan_in_history_is_gone_next_frame_and_counted(device):
    scene = moving_box_scene(frames=1)
    r = Renderer(scene, Settings(method="light_array", seed=1), device)
    for _ in range(3):
        r.render_frame(0)
    hist = np.empty((H, W, 4), np.float32)
    buf = r.taa_history[r.last_slot]
    cl.enqueue_copy(device.queue, hist, buf)
    hist[10:20, 10:20, :3] = np.nan
    hist[30, 30, 0] = np.inf
    cl.enqueue_copy(device.queue, buf, hist)
    before = r.guard_totals["nonfinite_history"]
    f = r.render_frame(0)
    assert np.all(np.isfinite(f.color))
    counted = f.guards["nonfinite_history"] - before
    assert counted >= 101, counted
    f2 = r.render_frame(0)
    assert np.all(np.isfinite(f2.color)) and f2.guards["nonfinite_history"] == f.guards["nonfinite_history"]
    n = r.history_length()
    assert n[15, 15] == 2.0 and n[5, 5] > 3.0  # the poisoned pixels restarted, the others kept going


@pytest.mark.parametrize("angle", [0.0, 30.0])
def test_reprojection_rejects_nothing_for_a_still_scene(device, angle):
    scene = moving_box_scene(frames=1)
    scene.camera.transforms = look_at((0, -5, 3), (math.tan(math.radians(angle)), 0, 0.3))
    r = Renderer(scene, Settings(method="light_array", seed=1), device)
    for _ in range(5):
        r.render_frame(0)
    n = r.history_length()
    assert np.all(n == 5.0)


def test_frames_without_aovs_give_the_same_image(device):
    """render_frame(aovs=False) skips the G-buffer read-back only: same colours, frame for frame."""
    scene = scenes.moving_box(24, 16, frames=4)
    a = Renderer(scene, Settings(method="restir", seed=4), device)
    b = Renderer(scene, Settings(method="restir", seed=4), device)
    for f in range(4):
        fa, fb = a.render_frame(f), b.render_frame(f, aovs=False)
        np.testing.assert_array_equal(fa.color, fb.color)
        np.testing.assert_array_equal(fa.noisy, fb.noisy)
        assert fa.depth is not None and fa.vector is not None
        assert fb.depth is None and fb.normal is None and fb.vector is None and fb.albedo is None
