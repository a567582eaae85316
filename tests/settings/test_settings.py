"""The settings table: Settings keeps its fields, every field is declared once with a range or choices and a
command-line flag, and validate(), the command line and the kernels' -D limits agree with it. (The add-on's side
is tests/blender/test_blender_addon.py.)"""

from __future__ import annotations

import argparse
import math
import re
from dataclasses import fields
from pathlib import Path

import numpy as np
import pytest
from restircl import SettingError, Settings
from restircl.cli.arguments import settings_from_args
from restircl.cli.main import build_parser
from restircl.core.program import build_program, opencl_dir
from restircl.settings.spec import Range, declared
from restircl.settings.table import JOINT_LIMITS, METHODS, kernel_defines

# the fields, defaults and order of Settings before the table (scripts pass them by keyword and by position); new
# fields come last
BEFORE = (
    ("method", "restir"), ("candidates", 8), ("temporal", True), ("spatial", True), ("spatial_neighbours", 2),
    ("spatial_radius", 5.0), ("spatial_passes", 1), ("bias_correction", "pairwise"), ("m_cap", 5.0),
    ("visibility_reuse", True), ("taa", True), ("alpha_min", 0.1), ("gamma", 1.0), ("max_history", 256),
    ("depth_tolerance", 0.1), ("normal_angle", 25.0), ("slots_per_light", 4.0), ("light_tiles", "auto"),
    ("light_tile_count", 128), ("light_tile_size", 1024), ("light_change_ratio", 2.0), ("jitter", True),
    ("seed", 0), ("specialise", True), ("bake_resolution", 512),
    ("bsdf_sampling", "auto"), ("bsdf_candidates", 1), ("warmup_frames", 0),
    ("boiling_filter", 0.0), ("temporal_permutation", True),
    ("taa_filter", "bilinear"), ("taa_dilation", False),
    ("realtime_filter", False), ("filter_iterations", 4), ("disocclusion_boost", 8), ("fresh_candidates", 64),
    ("denoise", False), ("light_passes", False),
    ("still_method", "auto"),
    ("area_sampling", "area"),
    ("light_proposal", "auto"),
    ("boiling_mode", "weight"),
    ("bsdf_mis_sample", False),
    ("sampler", "auto"),
    ("visibility_max_age", 0), ("visibility_max_distance", 2.0),
    ("max_bounces", 0), ("diffuse_bounces", 4), ("glossy_bounces", 4), ("min_light_bounces", 0),
    ("clamp_direct", 0.0), ("clamp_indirect", 0.0), ("light_threshold", 0.0),
    ("gi_reuse", True), ("gi_temporal", True), ("gi_spatial_neighbours", 4), ("gi_radius", 10.0), ("gi_m_cap", 8.0),
    ("gi_bias_correction", "pairwise"), ("gi_boiling_filter", 0.0), ("gi_disocclusion_boost", 0),
    ("path_light_pick", "auto"), ("texture_filter", "auto"), ("transmission_bounces", 12),
    ("transparent_max_bounces", 8), ("cryptomatte_levels", 0), ("taa_fresh_fill", True),
    ("taa_clip_surface", False),
    ("gi_temporal_permutation", False))
NUMBERS = [d for d in declared(Settings) if d.spec.range is not None]


def test_fields_defaults_and_order_unchanged():
    assert [(f.name, f.default) for f in fields(Settings)] == list(BEFORE)
    assert Settings.names() == [n for n, _ in BEFORE]
    assert METHODS == ("uniform", "light_array", "ris", "restir", "reference")


def test_every_field_is_declared_once_with_its_checks_and_a_flag():
    decl = declared(Settings)
    assert [d.name for d in decl] == Settings.names()
    annotations = {f.name: f.type for f in fields(Settings)}
    for d in decl:
        assert annotations[d.name] == d.kind.__name__, d.name  # the annotation agrees with the default
        assert d.spec.label and d.spec.description and d.spec.flag, d.name
        if d.kind in (int, float):
            assert d.spec.range is not None and d.spec.range.kind is d.kind, d.name
        if d.kind is str:
            assert d.default in d.spec.choice_ids(), d.name
    flags = [d.spec.flag for d in decl]
    assert len(set(flags)) == len(flags)


def _parse(*argv: str) -> argparse.Namespace:
    return build_parser().parse_args(["render", "cornell_box", *argv])


def test_default_options_give_default_settings():
    assert settings_from_args(_parse()) == Settings()


def _partners(name: str) -> dict[str, int | float]:
    """The settings limited together with `name`, at their minimum (so that its own limits can be reached)."""
    return {d.name: d.spec.range.lowest() for d in NUMBERS for group in JOINT_LIMITS
            if name in group and d.name in group and d.name != name}


@pytest.mark.parametrize("d", NUMBERS, ids=[d.name for d in NUMBERS])
def test_command_line_and_validate_agree_at_the_limits(d, capsys):
    r = d.spec.range
    partners = _partners(d.name)
    partner_argv = [a for n, v in partners.items() for a in (next(x.spec.flag for x in NUMBERS if x.name == n),
                                                              str(v))]
    for value in (r.lowest(), r.highest(), r.off):
        if value is None:
            continue
        value = d.kind(value)
        Settings(**{d.name: value, **partners}).validate()
        assert getattr(settings_from_args(_parse(d.spec.flag, repr(value), *partner_argv)), d.name) == value
    outside = [math.nan]
    if r.min is not None:
        outside.append(r.min if r.min_open else r.min - 1)
    if r.max is not None:
        outside.append(r.max + 1)
    if d.kind is int:
        outside = [v for v in outside if not math.isnan(v)] + [(r.lowest() or 0) + 0.5]
    for value in outside:
        with pytest.raises(SettingError, match=rf"setting {d.name}=.* is out of range: must be "):
            Settings(**{d.name: value}).validate()
        with pytest.raises(SystemExit) as e:
            _parse(d.spec.flag, str(int(value) if d.kind is int and float(value).is_integer() else value))
        assert e.value.code == 2
        assert f"argument {d.spec.flag}: " in capsys.readouterr().err


def test_choices_and_booleans():
    with pytest.raises(SettingError, match="setting method='nope' is not one of uniform, light_array"):
        Settings(method="nope").validate()
    with pytest.raises(SettingError, match="bias_correction"):
        Settings(bias_correction="biased").validate()
    s = settings_from_args(_parse("--no-temporal", "--no-jitter", "--general", "--bias-correction", "z_count"))
    assert (s.temporal, s.jitter, s.specialise, s.bias_correction) == (False, False, False, "z_count")
    with pytest.raises(SettingError, match="must be an integer"):
        Settings(candidates="8").validate()  # a string is not a number


def test_joint_limit_names_both_settings(capsys):
    with pytest.raises(SettingError) as e:
        Settings(light_tile_count=4096, light_tile_size=65536).validate()
    assert e.value.names == JOINT_LIMITS[0]
    from restircl.cli.main import main

    with pytest.raises(SystemExit) as ex:
        main(["render", "cornell_box", "--light-tile-count", "4096", "--light-tile-size", "2048"])
    assert ex.value.code == 2
    assert "argument --light-tile-count/--light-tile-size: " in capsys.readouterr().err


def test_range_texts():
    assert Range(int, 1, 4096).text() == "an integer in [1, 4096]"
    assert Range(float, 0, min_open=True, finite=True).text() == "a finite number > 0"
    assert Range(float, 1, min_open=True, off=0.0).text() == "0 (off) or a number > 1"
    assert Range(float, 0, 1, max_open=True).text() == "a number in [0, 1)"
    assert Range(float, 1).contains(math.inf)  # no maximum and not finite: infinity is allowed
    assert not Range(float, 1, finite=True).contains(math.inf)


def test_kernel_limits_come_from_the_table(device):
    limits = kernel_defines()
    assert limits == {"MAX_NEIGHBOURS": next(d.spec.range.max for d in NUMBERS if d.name == "spatial_neighbours"),
                      "MAX_GI_NEIGHBOURS": next(d.spec.range.max for d in NUMBERS if d.name == "gi_spatial_neighbours")}
    # the kernel file may keep a fallback for builds outside restircl (clang checks), never another value
    for name, value in limits.items():
        for path in opencl_dir().rglob("*.[ch]*"):
            for found in re.findall(rf"#define {name} (\d+)", path.read_text()):
                assert int(found) == value, f"{path.name} defines {name} {found}, the table says {value}"
    import pyopencl as cl

    src = "__kernel void k(__global int* out) { out[0] = MAX_NEIGHBOURS; out[1] = MAX_GI_NEIGHBOURS; }"
    prog = build_program(device, {}, source=src)
    out = np.zeros(2, np.int32)
    buf = cl.Buffer(device.context, cl.mem_flags.WRITE_ONLY, out.nbytes)
    prog.k(device.queue, (1,), None, buf)
    cl.enqueue_copy(device.queue, out, buf)
    assert out.tolist() == [limits["MAX_NEIGHBOURS"], limits["MAX_GI_NEIGHBOURS"]]


def test_docs_list_every_setting():
    """docs/blender.md's settings table names each Blender label and each Settings field."""
    text = (Path(__file__).resolve().parents[2] / "docs" / "blender.md").read_text()
    for d in declared(Settings):
        assert d.spec.label in text and f"`{d.name}`" in text, d.name
