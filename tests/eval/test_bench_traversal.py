"""`restircl bench traversal` and `python -m restircl.eval.bench.traversal` trace on the device they are given (a
'P:D' index or a name substring), and an unknown device is a clear error, before any scene is built."""

import pytest
from restircl import DeviceError, get_device
from restircl.cli.main import main
from restircl.eval.bench import traversal as bench_traversal

TINY = ["--triangles", "2000", "--width", "16", "--height", "12", "--no-embree"]


@pytest.fixture
def traced_on(monkeypatch):
    """The devices the traversal benchmark's OpenCL tracer was built on."""
    seen = []
    tracer = bench_traversal.OpenCLTracer

    def spy(*args, device=None, **kw):
        seen.append(device)
        return tracer(*args, device=device, **kw)

    monkeypatch.setattr(bench_traversal, "OpenCLTracer", spy)
    return seen


def _specs(device) -> list[str]:
    info = device.info
    return [f"{info.platform_index}:{info.device_index}", info.device_name]


def test_cli_bench_traversal_uses_the_device_given(device, traced_on, capsys):
    for spec in _specs(device):
        assert main(["bench", "traversal", *TINY, "--device", spec]) == 0
        # get_device caches one Device per spec: the tracer got the one for this spec, not the default one
        assert traced_on[-1] is get_device(spec)
        assert f"device: {device.label}" in capsys.readouterr().out


def test_module_main_uses_the_device_given(device, traced_on):
    spec = _specs(device)[0]
    assert bench_traversal.main([*TINY, "--device", spec]) == 0
    assert traced_on[-1] is get_device(spec)


def test_unknown_device_is_a_clear_error(traced_on, capsys, monkeypatch):
    assert main(["bench", "traversal", *TINY, "--device", "no-such-device-xyz"]) == 2
    assert "no OpenCL device matches 'no-such-device-xyz'" in capsys.readouterr().err

    def no_scene(*args, **kw):
        raise AssertionError("the scene was built before the device was checked")

    monkeypatch.setattr(bench_traversal, "make_scene", no_scene)
    with pytest.raises(DeviceError, match="no-such-device-xyz"):
        bench_traversal.run(2000, 16, 12, embree=False, device="no-such-device-xyz")
    with pytest.raises(DeviceError, match="no-such-device-xyz"):
        bench_traversal.main([*TINY, "--device", "no-such-device-xyz"])
    assert traced_on == []
