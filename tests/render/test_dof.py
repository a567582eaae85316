"""Depth of field (a thin lens, opencl/camera/lens.h): a pinhole compiles no lens code and renders as before; the
rays of a pixel meet on the plane in focus and spread elsewhere by the thin lens' geometry."""

from __future__ import annotations

import numpy as np
import pytest
from restircl import Camera, Light, Material, Mesh, Renderer, Scene, Settings, look_at, scenes, translation

from ..helpers import occluder_scene

DEPTH = 4.0  # the wall's distance from the camera, along its view axis


def wall_scene(radius: float, focus: float, blades: int = 0) -> Scene:
    """A wall facing the camera DEPTH in front of it, lit by a point light."""
    v, t = scenes.quad(20, 20)
    wall = v @ np.array([[1, 0, 0], [0, 0, 1], [0, -1, 0]]).T + (0, DEPTH, 0)  # the XZ plane at y = DEPTH
    cam = Camera(look_at((0.0, 0.0, 0.0), (0.0, 1.0, 0.0)), 24, 16, lens=35.0, aperture_radius=radius,
                 focus_distance=focus, aperture_blades=blades)
    return Scene([Mesh("wall", wall, t, 0)], [Material("grey", (0.7, 0.7, 0.7))],
                 [Light("p", "point", (1, 1, 1), 50.0, translation(0.0, 1.0, 0.5))], cam, name="wall")


def hit_points(scene: Scene, device, frames: int, frame: int = 0) -> np.ndarray:
    """(frames, H, W, 3): the primary hits of `frames` renders of `frame` (no jitter: only the lens point
    changes)."""
    r = Renderer(scene, Settings(method="light_array", jitter=False), device)
    out = []
    for _ in range(frames):
        r.render_frame(frame)
        out.append(np.array(r.read_gbuffer()["pos"][..., :3], dtype=np.float64))
    return np.stack(out)


def test_a_pinhole_compiles_no_lens(device):
    sc = occluder_scene(16, 12)
    assert not Renderer(sc, Settings(method="light_array"), device).flags["HAS_DOF"]
    sc.camera.aperture_radius = 0.05
    assert Renderer(sc, Settings(method="light_array"), device).flags["HAS_DOF"]


def test_a_pinhole_renders_the_same_in_a_build_with_the_lens(device):
    """The general build (every feature, HAS_DOF with it) renders a pinhole camera bit for bit as the specialised
    build without the lens code does."""
    images = []
    for specialise in (True, False):
        r = Renderer(occluder_scene(16, 12), Settings(method="ris", specialise=specialise), device)
        images.append(r.render_still(0, 4).color)
    assert np.array_equal(images[0], images[1])


def test_rays_meet_on_the_plane_in_focus(device):
    pinhole = hit_points(wall_scene(0.0, DEPTH), device, 1)[0]
    lens = hit_points(wall_scene(0.3, DEPTH), device, 6)
    assert np.abs(lens - pinhole).max() < 1e-4 * DEPTH


def test_a_focus_pull_focuses_each_frame_where_it_says(device):
    """Focus 2 m away at frame 0, on the wall at frame 1: the rays of frame 1 meet on the wall."""
    pinhole = hit_points(wall_scene(0.0, DEPTH), device, 1)[0]
    sc = wall_scene(0.3, DEPTH)
    sc.camera.transforms = np.stack([sc.camera.transforms[0]] * 2)
    sc.camera.focus_per_frame = np.array([2.0, DEPTH])
    assert np.abs(hit_points(sc, device, 4, frame=1) - pinhole).max() < 1e-4 * DEPTH
    assert np.abs(hit_points(sc, device, 4, frame=0) - pinhole).max() > 0.1


@pytest.mark.parametrize("blades", [0, 5])
def test_rays_spread_by_the_thin_lens_geometry(device, blades):
    """Focused at half the wall's depth, a pixel's ray from lens point l (|l| <= radius) crosses the pinhole ray at
    the focus and meets the wall at l (1 - DEPTH / focus) from the pinhole's hit: up to one radius here."""
    radius, focus = 0.3, DEPTH / 2
    pinhole = hit_points(wall_scene(0.0, DEPTH), device, 1)[0]
    spread = np.linalg.norm(hit_points(wall_scene(radius, focus, blades), device, 16) - pinhole, axis=-1)
    reach = radius * abs(1.0 - DEPTH / focus)
    assert spread.max() <= reach * (1 + 1e-4)
    assert np.median(spread) > 0.3 * reach  # a disc's median radius is 0.71 of it, a pentagon's not much less
    # the points of one pixel over the frames are not all one point: each frame draws another lens point
    assert np.all(spread.std(axis=0) > 0.05 * reach)


def test_the_lens_and_the_shutter_survive_the_scene_file(tmp_path):
    sc = wall_scene(0.25, 3.5, blades=6)
    sc.camera.aperture_rotation, sc.camera.aperture_ratio, sc.camera.shutter = 0.3, 1.5, (-0.25, 0.25)
    sc.save(tmp_path / "wall.npz")
    cam = Scene.load(tmp_path / "wall.npz").camera
    assert (cam.aperture_radius, cam.focus_distance, cam.aperture_blades) == (0.25, 3.5, 6)
    assert (cam.aperture_rotation, cam.aperture_ratio, cam.shutter) == (0.3, 1.5, (-0.25, 0.25))
    assert cam.focus_per_frame is None
    sc.camera.focus_per_frame = np.array([2.0, 3.0])
    sc.save(tmp_path / "pull.npz")
    assert np.array_equal(Scene.load(tmp_path / "pull.npz").camera.focus_per_frame, [2.0, 3.0])
