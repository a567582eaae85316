"""restircl: many-light direct lighting (light array, RIS, ReSTIR DI) and TAA in OpenCL C.

Public API::

    import restircl
    scene = restircl.scenes.cornell_box(width=160, height=120)
    renderer = restircl.Renderer(scene, restircl.Settings(method="restir"))
    frame = renderer.render_frame(0)          # restircl.Frame: .color (H, W, 4) float32 and AOVs
    still = restircl.Renderer(scene, restircl.still_settings(restircl.Settings(), scene)).render_still(0, 64)
    restircl.write_exr("out/frame.exr", frame)
"""

from . import scenes
from .core.device import Device, DeviceError, choose_device, get_device, list_devices
from .core.program import KernelBuildError
from .environment.world import Environment
from .io.images import read_exr, write_exr, write_png
from .materials.material import Material
from .materials.textures import (
    Attribute,
    Bump,
    CheckerTexture,
    ColorRamp,
    CombineColor,
    HueSaturationValue,
    ImageTexture,
    Invert,
    Math,
    MixColor,
    NormalMap,
    RGBCurves,
    SeparateColor,
    VectorMath,
)
from .render.frame import Frame
from .render.pipeline import Renderer
from .render.still_method import still_settings
from .scene.camera import Camera
from .scene.errors import SceneError, SceneFileError
from .scene.light import Light
from .scene.mesh import Mesh
from .scene.scene import Scene
from .scene.transforms import look_at, translation
from .settings.spec import SettingError
from .settings.table import Settings

__all__ = [
    "Attribute", "Bump", "Camera", "CheckerTexture", "ColorRamp", "CombineColor", "Device", "DeviceError",
    "Environment", "Frame", "HueSaturationValue", "ImageTexture", "Invert", "KernelBuildError", "Light", "Material",
    "Math", "Mesh", "MixColor", "NormalMap", "Renderer", "RGBCurves",
    "SeparateColor", "VectorMath",
    "Scene", "SceneError", "SceneFileError", "SettingError", "Settings", "choose_device", "get_device", "list_devices",
    "look_at", "read_exr", "scenes", "still_settings", "translation", "write_exr", "write_png",
]
__version__ = "0.1.0"
