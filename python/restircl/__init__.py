"""restircl: many-light direct lighting (light array, RIS, ReSTIR DI) and TAA in OpenCL C.

Public API::

    import restircl
    scene = restircl.scenes.cornell_box(width=160, height=120)
    renderer = restircl.Renderer(scene, restircl.Settings(method="restir"))
    frame = renderer.render_frame(0)          # restircl.Frame: .color (H, W, 4) float32 and AOVs
    restircl.write_exr("out/frame.exr", frame)
"""

from .device import Device, DeviceError, choose_device, get_device, list_devices
from .program import KernelBuildError
from .scene import Camera, Light, Material, Mesh, Scene, SceneError, SceneFileError, look_at, translation

__all__ = [
    "Camera", "Device", "DeviceError", "KernelBuildError", "Light", "Material", "Mesh", "Scene", "SceneError",
    "SceneFileError", "choose_device", "get_device", "list_devices", "look_at", "translation",
]
__version__ = "0.1.0"
