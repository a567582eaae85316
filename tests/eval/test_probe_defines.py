"""eval/probe_defines.py: a probe's define reaches the compiler of the programs built after it (a tiny kernel prints
its value), a bare name is defined as 1, one of a setting's names replaces the setting's value, and a test's patch is
gone after the test (the same kernel no longer builds)."""

from __future__ import annotations

import numpy as np
import pyopencl as cl
import pytest
from restircl.core import program
from restircl.core.program import KernelBuildError, build_program
from restircl.eval.probe_defines import add_probe_defines, parse_defines
from restircl.settings.table import kernel_defines

SRC = """
__kernel void probe(__global int* out)
{
    out[0] = PROBE_VALUE;
    out[1] = PROBE_FLAG;
}
"""


def probe_values(device) -> list[int]:
    prog = build_program(device, {}, source=SRC)
    out = np.zeros(2, np.int32)
    buf = cl.Buffer(device.context, cl.mem_flags.WRITE_ONLY, out.nbytes)
    cl.Kernel(prog, "probe")(device.queue, (1,), None, buf)
    cl.enqueue_copy(device.queue, out, buf)
    return out.tolist()


def test_parse_defines():
    assert parse_defines(["A=2", "B", "C=0.98f", "D="]) == {"A": "2", "B": True, "C": "0.98f", "D": ""}
    for bad in ("", "=1", "1A=2", "A B=1"):
        with pytest.raises(ValueError):
            parse_defines([bad])


def test_defines_reach_the_build_and_go_with_the_test(device):
    with pytest.MonkeyPatch.context() as mp:
        add_probe_defines(["PROBE_VALUE=7"], mp.setattr)
        add_probe_defines(["PROBE_FLAG"], mp.setattr)  # calls add up
        assert probe_values(device) == [7, 1]
    with pytest.raises(KernelBuildError):  # undone with the patch: PROBE_VALUE is undeclared again
        build_program(device, {}, source=SRC)


def test_a_define_of_the_settings_name_replaces_its_value(monkeypatch):
    name, value = next(iter(kernel_defines().items()))
    add_probe_defines([f"{name}={value}0", "PROBE_FLAG"], monkeypatch.setattr)
    got = program.kernel_defines()
    assert got[name] == f"{value}0" and got["PROBE_FLAG"] is True
    assert {k: v for k, v in got.items() if k not in (name, "PROBE_FLAG")} == \
        {k: v for k, v in kernel_defines().items() if k != name}
