"""What plan_frame (render/plan.py) needs to know of a frame: its scene as uploaded and the renderer's history."""

from __future__ import annotations

from typing import Protocol

from ..lights.pick_table import PickTable
from ..scene.camera import Camera
from ..scene.scene import Scene
from ..upload.device_scene import DeviceScene
from .camera import camera_moved
from .history import History
from .plan import FrameSituation


class RendererState(Protocol):
    """The parts of a renderer (render/pipeline.py Renderer, which imports this module) that a frame's situation
    reads."""

    scene: Scene
    device_scene: DeviceScene
    history: History
    uses_light_tree: bool
    path_light_tree: bool
    pick_table: PickTable


def frame_situation(r: RendererState, frame: int, still: bool, sobol: bool, last_frame: int | None,
                    prev_view: Camera | None) -> FrameSituation:
    """The situation of frame `frame` of renderer r, whose last frame was `last_frame` (None: none since its history
    was dropped) and last view `prev_view` (Renderer.render_view's), in a still's frame where `still`, with Sobol
    samples where `sobol`."""
    ds, cam, flags = r.device_scene, r.scene.camera, r.device_scene.material_flags
    assert cam is not None
    return FrameSituation(
        frame=frame, last_frame=last_frame, frame_count=ds.frame_count, cut_at_frame=frame in cam.cuts,
        history_valid=r.history.valid, lights_reindexed=ds.light_indices_changed,
        lights_switched=ds.lights_switched, light_count=ds.sampled_light_count,
        environment=ds.lights.environment is not None, glossy=flags.get("HAS_GLOSSY", False),
        analytic_lights=ds.analytic_lights, triangle_lights=ds.triangle_lights, sobol=sobol,
        light_tree=r.uses_light_tree, path_light_tree=r.path_light_tree, pick_table=r.pick_table.active,
        still=still, camera_moved=camera_moved(cam, frame, last_frame, prev_view),
        scene_moves=ds.moving_lights or ds.moving_objects or ds.edited, gi_history_valid=r.history.gi_valid,
        transmission=flags.get("HAS_TRANSMISSION", False))
