"""What plan_frame (render/plan.py) needs to know of a frame: its scene as uploaded and the renderer's history."""

from __future__ import annotations

from typing import Any

from .camera import camera_moved
from .plan import FrameSituation


def frame_situation(r: Any, frame: int, still: bool, sobol: bool) -> FrameSituation:
    """The situation of frame `frame` of renderer r (render/pipeline.py Renderer, not imported here: it imports this
    module) in a still's frame where `still`, with Sobol samples where `sobol`."""
    ds, cam, flags = r.device_scene, r.scene.camera, r.device_scene.material_flags
    assert cam is not None
    return FrameSituation(
        frame=frame, last_frame=r._last_frame, frame_count=ds.frame_count, cut_at_frame=frame in cam.cuts,
        history_valid=r.history.valid, lights_reindexed=ds.light_indices_changed,
        lights_switched=ds.lights_switched, light_count=ds.sampled_light_count,
        environment=ds.lights.environment is not None, glossy=flags.get("HAS_GLOSSY", False),
        analytic_lights=ds.analytic_lights, triangle_lights=ds.triangle_lights, sobol=sobol,
        light_tree=r.uses_light_tree, path_light_tree=r.path_light_tree, pick_table=r.pick_table.active,
        still=still, camera_moved=camera_moved(cam, frame, r._last_frame, r._prev_view),
        scene_moves=ds.moving_lights or ds.moving_objects or ds.edited, gi_history_valid=r.history.gi_valid,
        transmission=flags.get("HAS_TRANSMISSION", False))
