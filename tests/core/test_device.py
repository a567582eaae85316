"""Device choice (deterministic, overridable by argument and env var), hand-in contexts, and build errors."""

import pyopencl as cl
import pytest
from restircl import Device, DeviceError, KernelBuildError, Renderer, Settings, choose_device, list_devices, scenes
from restircl.core.program import build_program


def test_choice_is_deterministic_and_prefers_gpu():
    devices = list_devices()
    info, _ = choose_device()
    assert info == choose_device()[0]
    gpus = [i for i, _ in devices if i.device_type == "GPU"]
    assert info == (gpus[0] if gpus else next(i for i, _ in devices if i.device_type == "CPU"))


def test_a_device_that_cannot_build_is_skipped_with_a_warning(monkeypatch):
    """The pyopencl wheel's PoCL (LLVM 14) cannot build for CPUs newer than its LLVM; the default choice then takes
    the next device that builds and says which one it skipped; if none builds, the error names each and why."""
    from restircl.core import device as device_mod

    devices = list_devices()
    first = choose_device()[0]
    broken = {first.label}
    real = device_mod.build_problem
    monkeypatch.setattr(device_mod, "build_problem",
                        lambda dev: "cannot build kernels: test" if _label_of(devices, dev) in broken else real(dev))
    others = [i for i, d in devices if i != first and real(d) is None]
    if others:
        with pytest.warns(RuntimeWarning, match="skipped OpenCL device .*cannot build kernels: test"):
            assert choose_device()[0] != first
    broken.update(i.label for i, _ in devices)
    with pytest.raises(DeviceError, match="no OpenCL device can build kernels"):
        choose_device()
    spec = f"{first.platform_index}:{first.device_index}"
    assert choose_device(spec)[0] == first  # an explicit choice is taken as it is


def _label_of(devices, dev):
    return next(i.label for i, d in devices if d == dev)


def test_the_chosen_device_passes_the_probe():
    from restircl.core import device as device_mod

    info, dev = choose_device()
    assert device_mod.build_problem(dev) is None
    assert device_mod._probe(dev) is None


def test_override_by_argument_and_environment(monkeypatch):
    info, _ = list_devices()[-1]
    spec = f"{info.platform_index}:{info.device_index}"
    assert choose_device(spec)[0] == info
    monkeypatch.setenv("RESTIRCL_DEVICE", spec)
    assert choose_device()[0] == info
    needle = info.device_name[:6]
    monkeypatch.setenv("RESTIRCL_DEVICE", needle)
    first_match = next(i for i, _ in list_devices() if needle.lower() in f"{i.platform_name} / {i.device_name}".lower())
    assert choose_device()[0] == first_match  # the first device in order whose name holds the substring
    monkeypatch.setenv("RESTIRCL_DEVICE", "9:9")
    with pytest.raises(DeviceError, match="no OpenCL device matches '9:9'"):
        choose_device()


def test_script_can_hand_in_its_own_queue(device):
    ctx = cl.Context([device.device])
    queue = cl.CommandQueue(ctx)
    own = Device(queue=queue)
    r = Renderer(scenes.cornell_box(width=16, height=16), Settings(method="ris"), own)
    assert r.device.queue is queue and r.render_frame(0).color.shape == (16, 16, 4)


def test_build_error_names_file_and_line(device):
    with pytest.raises(KernelBuildError) as e:
        build_program(device, {}, source='#include "types.h"\n__kernel void k(__global int* a) { a[0] = nope; }\n')
    assert "nope" in str(e.value)
    assert e.value.location is not None and ":2" in e.value.location


def test_fast_math_is_refused(device):
    with pytest.raises(ValueError, match="NaN/Inf guards"):
        build_program(device, {}, source="__kernel void k() {}", extra_options=("-cl-fast-relaxed-math",))


def test_programs_flush_denormals(device):
    """Programs are built with -cl-denorms-are-zero (program.BASE_OPTIONS): a denormal operand reads as 0. On the
    CPU, denormal operands (the int bits in our float4 w lanes) cost ~100 cycles each; PoCL honours the option."""
    import numpy as np

    prog = build_program(device, {}, source="__kernel void k(__global float* a) { a[get_global_id(0)] *= 3.0f; }")
    a = np.array([1e-40, -1e-39, 1.5], np.float32)
    buf = cl.Buffer(device.context, cl.mem_flags.READ_WRITE | cl.mem_flags.COPY_HOST_PTR, hostbuf=a)
    prog.k(device.queue, (3,), None, buf)
    cl.enqueue_copy(device.queue, a, buf)
    if "Portable Computing Language" not in device.label:
        pytest.skip("flushing is optional for other OpenCL devices")
    assert a[0] == 0.0 and a[1] == 0.0 and a[2] == 4.5


def test_smaller_work_groups_give_the_same_images(device):
    """A device may allow a kernel fewer than 64 work-items per group (CL_KERNEL_WORK_GROUP_SIZE); the launches then
    use the largest power of two it allows, and since every random number is keyed by the pixel, not the group,
    the images are bit-identical to the 64 / 8x8 launches."""
    import numpy as np

    scene = scenes.moving_box(width=37, height=23, frames=4)  # sizes that no local size divides
    outs = []
    for limit in (None, 16, 3):
        r = Renderer(scene, Settings(method="restir", candidates=2), device)
        if limit is not None:
            r.max_local = dict.fromkeys(r.max_local, limit)
        frames = [r.render_frame(f) for f in range(3)]
        outs.append(np.stack([np.concatenate([f.color[..., :3], f.noisy], axis=-1) for f in frames]))
    assert outs[0].max() > 0
    for other in outs[1:]:
        np.testing.assert_array_equal(outs[0], other)
