"""Device choice on machines without PoCL, with a faked pyopencl platform list: the GPU driver's OpenCL first, then
any CPU runtime, in whatever order the platforms come; where nothing builds, one message naming what to install
on that system."""

from __future__ import annotations

from dataclasses import dataclass, field

import pyopencl as cl
import pytest
from restircl import DeviceError, choose_device, list_devices
from restircl.core import device as device_mod
from restircl.core import install_hint as hint_mod


@dataclass(eq=False)
class FakeDevice:
    name: str
    type: int
    builds: bool = True
    int_ptr: int = field(default_factory=lambda: id(object()))


@dataclass
class FakePlatform:
    name: str
    devices: list[FakeDevice]

    def get_devices(self) -> list[FakeDevice]:
        return self.devices


GPU, CPU, ACC = cl.device_type.GPU, cl.device_type.CPU, cl.device_type.ACCELERATOR


def _fake(monkeypatch, platforms: list[FakePlatform] | Exception, system: str = "Windows") -> None:
    def get_platforms():
        if isinstance(platforms, Exception):
            raise platforms
        return platforms

    monkeypatch.setattr(cl, "get_platforms", get_platforms)
    monkeypatch.setattr(device_mod, "build_problem", lambda d: None if d.builds else "cannot build kernels: fake")
    monkeypatch.setattr(hint_mod._platform, "system", lambda: system)
    monkeypatch.delenv("RESTIRCL_DEVICE", raising=False)


def test_windows_gpu_driver_is_taken_before_the_intel_cpu_runtime(monkeypatch):
    _fake(monkeypatch, [FakePlatform("Intel(R) OpenCL", [FakeDevice("Intel(R) Core(TM) i7-12700", CPU)]),
                        FakePlatform("NVIDIA CUDA", [FakeDevice("NVIDIA GeForce RTX 4070", GPU)])])
    info, dev = choose_device()
    assert (info.platform_index, info.device_index, info.device_type) == (1, 0, "GPU")
    assert dev.name == "NVIDIA GeForce RTX 4070"


def test_a_gpu_that_cannot_build_falls_back_to_the_cpu_runtime(monkeypatch):
    _fake(monkeypatch, [FakePlatform("AMD Accelerated Parallel Processing", [FakeDevice("gfx1100", GPU, False)]),
                        FakePlatform("Intel(R) OpenCL", [FakeDevice("AMD Ryzen 9 7950X", CPU)])])
    with pytest.warns(RuntimeWarning, match="skipped OpenCL device 0:0 AMD Accelerated .*gfx1100"):
        info, _ = choose_device()
    assert (info.platform_index, info.device_type) == (1, "CPU")


def test_macos_takes_the_apple_gpu_over_the_cpu_listed_first(monkeypatch):
    _fake(monkeypatch, [FakePlatform("Apple", [FakeDevice("Apple M2 CPU", CPU), FakeDevice("Apple M2", GPU)])],
          system="Darwin")
    assert choose_device()[0].label == "0:1 Apple / Apple M2 (GPU)"


def test_an_accelerator_only_when_no_gpu_or_cpu_builds(monkeypatch):
    _fake(monkeypatch, [FakePlatform("X", [FakeDevice("fpga", ACC), FakeDevice("cpu", CPU, False)])])
    with pytest.warns(RuntimeWarning, match="cpu"):
        assert choose_device()[0].device_type == "ACCELERATOR"


@pytest.mark.parametrize(("system", "words"), [
    ("Windows", ("graphics driver", "Intel's CPU Runtime for OpenCL")),
    ("Darwin", ("built in", "no install needed")),
    ("Linux", ("pip install pocl-binary-distribution", "apt-get install pocl-opencl-icd")),
])
def test_nothing_builds_one_message_naming_what_to_install(monkeypatch, system, words):
    _fake(monkeypatch, [FakePlatform("P", [FakeDevice("gpu", GPU, False), FakeDevice("cpu", CPU, False)])], system)
    with pytest.raises(DeviceError) as err:
        choose_device()
    text = str(err.value)
    assert text.startswith("no OpenCL device can build kernels; ")
    assert all(w in text.splitlines()[0] for w in words), text
    assert "0:0 P / gpu (GPU): cannot build kernels: fake" in text and "0:1 P / cpu (CPU)" in text
    others = {"Windows": "graphics driver", "Darwin": "built in", "Linux": "pocl"}
    assert not any(w in text for s, w in others.items() if s != system), text  # no other system's advice


def test_no_platform_or_no_device_names_what_to_install(monkeypatch):
    _fake(monkeypatch, cl.LogicError("clGetPlatformIDs failed: PLATFORM_NOT_FOUND_KHR"), "Windows")
    with pytest.raises(DeviceError, match="no OpenCL platform found .*PLATFORM_NOT_FOUND_KHR.*graphics driver"):
        list_devices()
    _fake(monkeypatch, [FakePlatform("Empty", [])], "Darwin")
    with pytest.raises(DeviceError, match="no OpenCL device found; macOS has OpenCL built in"):
        list_devices()


def test_an_unknown_system_gets_the_general_advice():
    assert "OpenCL driver for your GPU or CPU" in hint_mod.install_hint("FreeBSD")
