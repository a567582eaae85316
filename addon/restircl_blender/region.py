"""Render Region (Output > Format > Render Region, `render.use_border`) and Crop to Render Region: which pixels
of the frame are rendered, as Blender places them, and the camera that sees only those.

Blender truncates the border's fractions to whole pixels of the scaled resolution, x from the left and y from the
bottom; the engine writes a result of the region's size at that offset, and Blender itself either keeps the
full frame around it (empty elsewhere) or, with Crop, writes the region alone."""

from __future__ import annotations

from typing import NamedTuple


class Region(NamedTuple):
    x: int  # first column, from the left
    y: int  # first row, from the bottom (Blender's)
    width: int
    height: int
    full_height: int

    @property
    def top(self) -> int:
        """The first row from the top (restircl's images)."""
        return self.full_height - self.y - self.height


def render_region(scene, width: int, height: int) -> Region | None:
    """The region of a `width` x `height` frame that the scene renders; None: the whole frame (no region, or one
    that covers it)."""
    r = scene.render
    if not r.use_border:
        return None
    x0, x1 = int(r.border_min_x * width), int(r.border_max_x * width)
    y0, y1 = int(r.border_min_y * height), int(r.border_max_y * height)
    x0, y0 = max(0, min(x0, width - 1)), max(0, min(y0, height - 1))
    x1, y1 = max(x0 + 1, min(x1, width)), max(y0 + 1, min(y1, height))
    if (x0, y0, x1, y1) == (0, 0, width, height):
        return None
    return Region(x0, y0, x1 - x0, y1 - y0, height)


def region_camera(camera, region: Region | None):
    """The exported camera (restircl.Camera) of the whole frame -> the camera of `region`."""
    if region is None:
        return camera
    return camera.region(region.x, region.top, region.x + region.width, region.top + region.height)
