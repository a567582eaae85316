"""Deformation within an animation frame's shutter: an animation exports whole frames (their transforms), and each
frame renders at one time of its shutter (render/shutter.py), so the objects that deform have their vertices (and
smooth corner normals) read at their deformation steps over the shutters of the frames a sequence renders, between
the whole frames, and carried as Mesh.deform at scene times (the exported frames' indices plus the step's fraction),
which the renderer interpolates to each frame's time (scene/deformation.py)."""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np

from .mesh import read_step
from .scene import Export


def read_frame_deformation(depsgraph, exp: Export, frame: int, step: float, times_of: Callable[[object], list[float]],
                           frame_set: Callable[[int, float], None], warn: Callable[[str], None]) -> None:
    """Give the meshes of the deforming objects of export `exp` (an animation's, rendering Blender frame `frame`,
    its exported frames `step` frames apart) their deformation at the Blender times `times_of(ob)` (empty: not
    blurred, as Cycles' settings ask); `frame_set(frame, subframe)` moves the depsgraph there, and back to `frame`
    at the end. Objects read (or left unblurred by their settings) join exp.deform_handled."""
    scene = depsgraph.scene
    wanted: dict[str, list[float]] = {}
    for name in exp.deforming:
        ob = scene.objects.get(name)
        if ob is None:
            continue
        times = times_of(ob)
        if len(times) > 1:
            wanted[name] = times
        else:
            exp.deform_handled.append(name)
    if not wanted:
        return
    meshes = {name: [m for m in exp.scene.meshes if m.name == name] for name in wanted}
    read: dict[str, list] = {name: [] for name in wanted}
    for t in sorted({t for times in wanted.values() for t in times}):
        whole = math.floor(t + 1e-9)
        frame_set(whole, max(0.0, t - whole))
        for name, times in wanted.items():
            ob = depsgraph.objects.get(name)
            if t in times:
                read[name].append(None if ob is None else read_step(ob, any(m.normals is not None
                                                                             for m in meshes[name])))
    frame_set(frame, 0.0)
    origin = exp.index_of(frame)
    for name, times in wanted.items():
        exp.deform_handled.append(name)
        steps = read[name]
        scene_times = np.array([origin + (t - frame) / step for t in times], np.float64)
        for mesh in meshes[name]:
            if any(s is None or s[0].shape != mesh.vertices.shape for s in steps):
                warn(f"object {name!r} changes its vertex count within the shutter: its deformation is not "
                     "blurred (as in Cycles)")
                break
            mesh.deform = np.stack([s[0] for s in steps]).astype(np.float64)
            mesh.deform_times = scene_times
            normals = [s[1] for s in steps]
            if mesh.normals is not None and all(n is not None and n.shape == mesh.normals.shape for n in normals):
                mesh.deform_normals = np.stack(normals).astype(np.float64)
