"""A render region on the farm (Blender's Output > Format > Render Region of a .blend, and Crop to Render Region):
the workers render only the region's pixels, with the camera that sees exactly them (Camera.region), as a render
in Blender does; each frame is written at the region's size when cropping, else placed in a frame of the full size
that is empty elsewhere (colour, alpha and passes 0, depth infinite: nothing there), as Blender writes it."""

from __future__ import annotations

import dataclasses
import importlib
from dataclasses import dataclass

import numpy as np

from ..render.frame import Frame
from ..scene.scene import Scene


@dataclass(frozen=True)
class FrameRegion:
    x: int  # first column, from the left
    top: int  # first row, from the top (restircl's images)
    width: int
    height: int
    full_width: int
    full_height: int
    crop: bool  # write the region alone

    def apply(self, scene: Scene) -> Scene:
        """`scene` (whose camera sees the full frame) with the camera of the region."""
        assert scene.camera is not None
        scene.camera = scene.camera.region(self.x, self.top, self.x + self.width, self.top + self.height)
        return scene

    def place(self, frame: Frame) -> Frame:
        """The frame as it is written: the region's own, or the full frame with the region at its place."""
        if self.crop:
            return frame
        changes = {}
        for f in dataclasses.fields(frame):
            value = getattr(frame, f.name)
            if isinstance(value, dict):
                changes[f.name] = {k: self._padded(v, f.name) for k, v in value.items()}
            elif isinstance(value, np.ndarray):
                changes[f.name] = self._padded(value, f.name)
        return dataclasses.replace(frame, **changes)

    def _padded(self, image, name: str):
        if not isinstance(image, np.ndarray) or image.shape[:2] != (self.height, self.width):
            return image
        empty = np.inf if name == "depth" else 0
        out = np.full((self.full_height, self.full_width, *image.shape[2:]), empty, dtype=image.dtype)
        out[self.top:self.top + self.height, self.x:self.x + self.width] = image
        return out


def blend_region(bpy_scene, addon) -> FrameRegion | None:
    """The render region of an open .blend's scene (None: the whole frame), by the add-on's own rules
    (restircl_blender.region: Blender's truncation to whole pixels)."""
    width, height = addon.export.render_resolution(bpy_scene)
    region = importlib.import_module(f"{addon.__name__}.region").render_region(bpy_scene, width, height)
    if region is None:
        return None
    return FrameRegion(region.x, region.top, region.width, region.height, width, height,
                       bool(bpy_scene.render.use_crop_to_border))
