"""Deformation blur in a still (Mesh.deform, render/shutter.py): each sample sees the mesh deformed as it is at its
own time, its BVH built again, so that the still is the average over the shutter of the sharp images. Checked
against that average taken independently: sharp stills of meshes built at evenly spaced times by hand (no
deformation steps), compared in the image's column profile (the edge's blur), where ignoring the deformation (the
mesh at the frame) fails: the profiles' summed absolute difference over the sharp average's sum, 0.6 % when
written against 19 % for the mesh at the frame."""

from __future__ import annotations

import numpy as np
from restircl import Camera, Material, Mesh, Renderer, Scene, Settings, translation

W, H = 48, 24
OPEN, CLOSE = -0.5, 0.5  # the shutter, frames around frame 0
EDGE = (-0.2, 1.0)  # x of the quad's right edge at the shutter's opening and closing


def quad(right: float, deform: bool = False) -> Mesh:
    verts = np.array([[-1.0, -0.5, 0.0], [right, -0.5, 0.0], [right, 0.5, 0.0], [-1.0, 0.5, 0.0]])
    mesh = Mesh("quad", verts, [[0, 1, 2], [0, 2, 3]], 0)
    if deform:
        steps = np.stack([verts, verts])
        steps[:, 1:3, 0] = np.array(EDGE)[:, None]
        mesh.deform, mesh.deform_times = steps, np.array([OPEN, CLOSE])
    return mesh


def render(mesh: Mesh, shutter: tuple[float, float], samples: int, seed: int = 5) -> tuple[np.ndarray, Renderer]:
    sc = Scene([mesh], [Material("glow", (0, 0, 0), (1, 1, 1), 2.0)], [],
               Camera(translation(0, 0, 4), W, H, lens=35.0, shutter=shutter))
    r = Renderer(sc, Settings(method="reference", seed=seed))
    image = r.render_still(0, samples).color
    return image, r


def profile(image: np.ndarray) -> np.ndarray:
    return image[..., 0].sum(axis=0)


def test_a_deforming_mesh_is_the_average_of_its_shapes_over_the_shutter(device):
    blurred, r = render(quad(sum(EDGE) / 2, deform=True), (OPEN, CLOSE), 256)
    assert r.device_scene.uploads["geometry"] >= 256  # a BVH per sample
    times = (np.arange(16) + 0.5) / 16
    sharp = np.mean([render(quad(EDGE[0] + (EDGE[1] - EDGE[0]) * t), (0.0, 0.0), 8, seed=k)[0]
                     for k, t in enumerate(times)], axis=0)
    at_frame = render(quad(sum(EDGE) / 2), (0.0, 0.0), 64)[0]
    want = profile(sharp)
    err = np.abs(profile(blurred) - want).sum() / want.sum()
    err_frame = np.abs(profile(at_frame) - want).sum() / want.sum()
    print(f"deformation blur profile: {100 * err:.2f} %, at the frame {100 * err_frame:.2f} %")
    assert err < 0.01, err
    assert err_frame > 0.05, err_frame
