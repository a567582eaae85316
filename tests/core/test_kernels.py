"""Kernel launches by argument name (core/kernels.py): the names come from the kernels' declarations, and a launch
that misses, misspells or adds an argument is an error naming the kernel and the argument."""

import numpy as np
import pyopencl as cl
import pytest
from restircl import Renderer, Settings, scenes
from restircl.core.kernels import KernelArgumentError, declared_parameters, parse_kernel_parameters


def test_parameters_parsed_from_the_declaration():
    src = """/* __kernel void not_this(int a) */
    __kernel void k(const __global float4* in, // the input
                    __global float4* out, FrameParams frame_params, int in_half) { }"""
    assert parse_kernel_parameters(src) == {"k": ("in", "out", "frame_params", "in_half")}


def test_declared_names_match_the_built_kernels(device):
    """Every kernel of opencl/ (the renderer builds them all) has as many parsed names as the compiler counts
    arguments."""
    declared = declared_parameters()
    bounced = {"path_trace", "gi_initial", "gi_temporal", "gi_boiling_tiles", "gi_boiling_filter", "gi_spatial",
               "gi_shade"}
    r = Renderer(scenes.cornell_box(width=8, height=8), Settings(method="restir"), device)
    # the default build leaves the path pass and ReSTIR GI out (max_bounces 0): every other kernel is there
    assert set(r.kernels.parameters) == set(declared) - bounced and "taa" in declared
    with_bounces = Renderer(scenes.cornell_box(width=8, height=8), Settings(method="restir", max_bounces=1), device)
    assert set(with_bounces.kernels.parameters) == set(declared)
    for kernels in (r.kernels, with_bounces.kernels):
        for name in kernels.parameters:
            assert len(declared[name]) == kernels.kernel(name).num_args, name
    # the film kernels read no feature flag: both builds launch them from the device's one film program, and the
    # feature builds do not compile them again
    film = r.kernels.program_of["accumulate"]
    assert r.kernels.program is not with_bounces.kernels.program and film is not r.kernels.program
    for name in ("accumulate", "accumulate_holdout", "accumulate_light_passes", "layer_add", "accumulate_cryptomatte"):
        assert r.kernels.program_of[name] is film and with_bounces.kernels.program_of[name] is film, name
        assert name not in r.kernels.program.get_info(cl.program_info.KERNEL_NAMES).split(";"), name


def test_side_kernels_are_shared_by_variants_and_built_at_their_first_launch(device):
    """taa is a side program's (core/side_programs.py): two builds differing in a flag it does not read (HAS_PATHS)
    launch it from the same program, which the main programs do not have, and a renderer builds it only when it
    first runs (a still runs no TAA)."""
    scene = scenes.cornell_box(width=8, height=8)
    a = Renderer(scene, Settings(method="restir"), device)
    b = Renderer(scene, Settings(method="restir", max_bounces=1), device)
    assert a.flags.get("HAS_PATHS") != b.flags.get("HAS_PATHS") and a.kernels.program is not b.kernels.program
    assert "taa" not in a.kernels.program_of and a.kernels.max_local["taa"] is None
    a.render_still(0, samples=1)
    assert "primary" in a.kernels.program_of and "taa" not in a.kernels.program_of
    for name in ("taa",):
        a.kernels.kernel(name)
        b.kernels.kernel(name)
        assert a.kernels.program_of[name] is b.kernels.program_of[name], name
        for r in (a, b):
            assert name not in r.kernels.program.get_info(cl.program_info.KERNEL_NAMES).split(";"), name


@pytest.fixture(scope="module")
def renderer(device):
    return Renderer(scenes.cornell_box(width=8, height=8), Settings(method="restir"), device)


def _accumulate_args(r: Renderer) -> dict:
    return {"sample": r.buffers.sample, "sum": r.still.sum, "sum_half": r.still.sum_half,
            "frame_params": r.frame_params(), "in_half": np.int32(0)}


def test_a_named_launch_runs(renderer):
    renderer.kernels.launch("accumulate", (renderer.pixels,), **_accumulate_args(renderer))
    renderer.device.queue.finish()


def test_missing_argument_is_named(renderer):
    args = _accumulate_args(renderer)
    del args["sum_half"]
    with pytest.raises(KernelArgumentError, match=r"kernel accumulate: missing sum_half"):
        renderer.kernels.launch("accumulate", (renderer.pixels,), **args)


def test_misspelled_and_extra_arguments_are_named(renderer):
    args = _accumulate_args(renderer)
    args["sum_halve"] = args.pop("sum_half")
    args["extra"] = np.int32(1)
    with pytest.raises(KernelArgumentError, match=r"kernel accumulate: missing sum_half; unknown sum_halve, extra"):
        renderer.kernels.launch("accumulate", (renderer.pixels,), **args)


def test_unknown_kernel_is_named(renderer):
    with pytest.raises(KernelArgumentError, match="no kernel named 'acumulate'"):
        renderer.kernels.launch("acumulate", (1,))
