"""Run by tests/blender/test_viewport_draw.py in a Python of its own: the add-on's drawing code (viewport.draw_frame and
view_draw) drawing into a GPU offscreen in background bpy, the pixels read back into a .npz for the test.

bpy in background starts without a GPU context ("GPU functions for drawing are not available in background
mode"); a Workbench render makes one (EGL; Mesa's llvmpipe on a machine without a GPU), and from then on the gpu
module works. The drawing runs inside RenderEngine.render of a probe engine: bind_display_space_shader needs a
real RenderEngine instance, which Python cannot make on its own. The offscreen gets the pixel-space matrices
Blender sets up for view_draw (an orthographic projection over the region, identity model-view).

    python tests/blender/viewport_draw_script.py OUT.npz     (prints one line: "viewport-draw: ok|skip <why>")

restircl comes from the environment, as in the tests; the add-on through restircl.io.blend.addon_module.
"""

from __future__ import annotations

import sys
from types import SimpleNamespace

import bpy
import numpy as np

W, H = 8, 6  # the region drawn into


def gpu_context() -> str | None:
    """Make the GPU context with a tiny Workbench render; the GPU's name, or None."""
    import gpu

    sc = bpy.context.scene
    sc.render.engine = "BLENDER_WORKBENCH"
    sc.render.resolution_x = sc.render.resolution_y = 4
    bpy.ops.render.render()
    try:
        return f"{gpu.platform.backend_type_get()} {gpu.platform.renderer_get()}"
    except SystemError:
        return None


def pixel_space(width: int, height: int):
    """The projection Blender's 3D view sets for view_draw: pixel (0, 0) to (width, height)."""
    from mathutils import Matrix

    p = Matrix.Identity(4)
    p[0][0], p[1][1], p[0][3], p[1][3] = 2.0 / width, 2.0 / height, -1.0, -1.0
    return p


def draw(draw_call, width: int = W, height: int = H) -> np.ndarray:
    """(height, width, 4) float32 read back from an RGBA16F offscreen (the 3D view's colour buffer format) after
    draw_call() drew into it, rows bottom first."""
    import gpu
    from mathutils import Matrix

    off = gpu.types.GPUOffScreen(width, height, format="RGBA16F")
    try:
        with off.bind():
            fb = gpu.state.active_framebuffer_get()
            fb.clear(color=(0.0, 0.0, 0.0, 0.0))
            with gpu.matrix.push_pop(), gpu.matrix.push_pop_projection():
                gpu.matrix.load_matrix(Matrix.Identity(4))
                gpu.matrix.load_projection_matrix(pixel_space(width, height))
                draw_call()
            buf = fb.read_color(0, 0, width, height, 4, 0, "FLOAT")
        return np.array(buf.to_list(), np.float32).reshape(height, width, 4)
    finally:
        off.free()


def probe(engine, depsgraph) -> dict:
    import gpu
    from restircl import look_at
    from restircl_blender import viewport
    from restircl_blender.viewport_session import ViewFrame

    rng = np.random.default_rng(3)
    out: dict = {}
    scene = depsgraph.scene

    def frame(h: int, w: int, index: int) -> ViewFrame:
        rgba = np.ones((h, w, 4), np.float32)
        rgba[..., :3] = rng.uniform(0.0, 4.0, (h, w, 3))  # HDR: values above 1 must survive
        out[f"frame{index}"] = rgba
        return ViewFrame(rgba=rgba, samples=1, ms=1.0, index=index, cut=False)

    vp = viewport.Viewport(None, (), frozenset())
    f1, f2 = frame(H, W, 1), frame(H // 2, W // 2, 2)
    out["same_size"] = draw(lambda: viewport.draw_frame(engine, scene, vp, f1, W, H))
    out["blend_after"] = np.array(gpu.state.blend_get() == "NONE")
    texture = vp.texture
    stale = ViewFrame(rgba=np.zeros_like(f1.rgba), samples=1, ms=1.0, index=1, cut=False)
    out["same_index"] = draw(lambda: viewport.draw_frame(engine, scene, vp, stale, W, H))
    out["texture_kept"] = np.array(vp.texture is texture)
    out["half_size"] = draw(lambda: viewport.draw_frame(engine, scene, vp, f2, W, H))
    out["texture_size"] = np.array([vp.texture.width, vp.texture.height])

    # view_update and view_draw of a real session: what is drawn is the session's newest frame
    viewport.view_update(engine, None, depsgraph)
    session = engine.viewport.session
    if session is None:
        raise RuntimeError(engine.viewport.message)
    window = np.array([[2.0, 0, 0, 0], [0, 2.0 * W / H, 0, 0], [0, 0, -1.002, -0.2], [0, 0, -1.0, 0]])
    ctx = SimpleNamespace(region=SimpleNamespace(width=W, height=H),
                          region_data=SimpleNamespace(view_matrix=np.linalg.inv(look_at((0.0, -5.0, 2.5),
                                                                                          (0.0, 0.0, 0.3))),
                                                      window_matrix=window, is_perspective=True,
                                                      view_perspective="PERSP"),
                          space_data=SimpleNamespace(clip_end=100.0))
    try:
        viewport.view_draw(engine, ctx, depsgraph)  # hands the view over: the first frame starts
        latest = session.wait(1)
        if session.error is not None or latest is None:
            raise RuntimeError(f"the session failed: {session.error}")
        out["session_frame"] = latest.rgba
        out["view_draw"] = draw(lambda: viewport.view_draw(engine, ctx, depsgraph))
    finally:
        viewport.free(engine)
    return out


RESULT: dict = {}


class DrawProbe(bpy.types.RenderEngine):
    bl_idname = "RESTIRCL_DRAW_PROBE"
    bl_label = "restircl draw probe"

    def render(self, depsgraph):
        try:
            RESULT.update(probe(self, depsgraph))
        except Exception as exc:  # reported by the test
            import traceback

            traceback.print_exc()
            RESULT["error"] = f"{type(exc).__name__}: {exc}"


def main(out_path: str) -> None:
    device = gpu_context()
    if device is None:
        print("viewport-draw: skip bpy made no GPU context in background mode")
        return
    from restircl.eval import blender_scenes as scenes
    from restircl.io.blend import addon_module

    addon_module().register()
    bpy.utils.register_class(DrawProbe)
    sc = scenes.new_scene(W, H, engine="RESTIRCL")
    scenes.quad("Floor", 10.0, 10.0, scenes.diffuse_material("Floor", (0.8, 0.8, 0.8)))
    scenes.box("Box", (0.8, 0.8, 0.8), scenes.diffuse_material("Red", (0.8, 0.2, 0.1)), location=(0.3, 0, 0.4))
    scenes.light("POINT", "Point", (-1.0, -0.5, 1.5), energy=60.0)
    scenes.camera((0.0, -5.0, 2.5), (0.0, 0.0, 0.3), lens=28.0)
    sc.restircl.viewport_samples, sc.restircl.viewport_pixel_size = 1, 1
    sc.render.engine = DrawProbe.bl_idname
    bpy.ops.render.render()
    if "error" in RESULT:
        print(f"viewport-draw: error {RESULT['error']}")
        sys.exit(1)
    np.savez(out_path, device=np.array(device), **RESULT)
    print(f"viewport-draw: ok {device}")


if __name__ == "__main__":
    main(sys.argv[1])
