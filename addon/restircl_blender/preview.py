"""Material previews (bl_use_preview): Blender calls RenderEngine.render with is_preview set on its own preview
scene (the preview sphere or another shape with the material, two area lights, a floor and the preview world, at
the preview's size: 128x128 for an icon, the panel's size for the Material tab's preview), once for each preview,
on its preview job's thread.

A preview is a still render of that scene with `preview_samples` frames, and nothing of it is kept: the preview
scene is another Main's (its name and view layer repeat the user's, so it must not reach the F12 sessions), and
the compiled kernels come from restircl's program cache. Its settings are the user's scene's (bpy.context.scene:
the preview scene's own are the defaults), but for the Light Paths: those are the preview scene's Cycles settings
(fewer bounces, no diffuse ones), which Cycles renders previews with too. Warnings are not reported, since every
edit of a material renders its previews again.
"""

from __future__ import annotations

import warnings

from . import export, render_result
from .properties import make_settings


def user_props(depsgraph):
    """scene.restircl of the scene the user works in; the preview scene's where there is no other."""
    import bpy

    try:
        scene = bpy.context.scene
    except AttributeError:  # a context without a scene
        scene = None
    props = getattr(scene, "restircl", None)
    return props if props is not None else depsgraph.scene.restircl


def render_preview(engine, depsgraph, restircl, known: tuple) -> None:
    """RenderEngine.render of a preview job; errors of the scene go to engine.report, others are raised."""
    scene = depsgraph.scene
    props = user_props(depsgraph)
    width, height = export.render_resolution(scene)
    try:
        camera = engine.camera_override  # the preview scene's camera reaches the engine only here
        if camera is not None:
            camera = camera.evaluated_get(depsgraph)
        exp = export.export_scene(depsgraph, [int(scene.frame_current)], camera=camera)
        exp.scene.validate()
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            settings = make_settings(restircl, props, scene)
            if hasattr(restircl, "still_settings"):
                settings = restircl.still_settings(settings, exp.scene)
            if engine.test_break():
                return
            renderer = restircl.Renderer(exp.scene, settings, device=props.device.strip() or None)
            result = renderer.render_still(0, int(props.preview_samples), should_stop=engine.test_break)
    except known as exc:
        engine.report({"ERROR"}, f"restircl: material preview: {exc}")
        return
    if result is not None and not engine.test_break():
        render_result.write_result(engine, result, width, height, depsgraph.view_layer, scene.render.film_transparent)
