"""One place per closure kind (materials/closures/<kind>.py on the host, bsdf/closures/<kind>.h on the device):
each registered kind has its code on the device, its resolve behind the switch of bsdf/resolve.h, a rule and lanes
for every field it reads, lobes the device knows; it validates the fields it reads and ignores the others; and a
closure packed as the renderer packs it resolves on the device into the lobes its entry declares."""

from __future__ import annotations

import re
from dataclasses import fields

import numpy as np
import pytest
from restircl.core.program import opencl_dir
from restircl.materials.check import FIELD_RULES, MaterialError, check_material
from restircl.materials.closures.registry import CLOSURE_KINDS, KINDS
from restircl.materials.material import Material
from restircl.upload.materials import FIELD_LANES, KIND_CODE, pack_materials

from ..helpers import device_ints
from .bsdf_kernels import view
from .lobe_kernels import LobeKernels, device_lobe_kinds, mid_material

NAMES = sorted(KINDS)


def test_codes_agree_on_the_device(device):
    assert KIND_CODE == {k.name: k.code for k in CLOSURE_KINDS}
    assert len({k.code for k in CLOSURE_KINDS}) == len(CLOSURE_KINDS)
    out = device_ints(device, "types.h", [f"CLOSURE_{k.name.upper()}" for k in CLOSURE_KINDS])
    assert out == [k.code for k in CLOSURE_KINDS]


@pytest.mark.parametrize("name", NAMES)
def test_each_kind_has_its_pieces(name):
    kind = KINDS[name]
    path = opencl_dir() / "bsdf" / "closures" / f"{name}.h"
    assert path.exists(), f"closure {name}: no opencl/bsdf/closures/{name}.h"
    assert re.search(rf"^inline float3 {name}_resolve\(", path.read_text(), re.M), f"closure {name}: no {name}_resolve"
    resolve = (opencl_dir() / "bsdf" / "resolve.h").read_text()
    assert f'#include "bsdf/closures/{name}.h"' in resolve, f"closure {name}: not included in bsdf/resolve.h"
    assert re.search(rf"case CLOSURE_{name.upper()}: return {name}_resolve\(", resolve), \
        f"closure {name}: no case in bsdf/resolve.h"
    material_fields = {f.name for f in fields(Material)}
    for f in kind.fields:
        assert f in material_fields, f"closure {name}: reads {f!r}, no field of Material"
        assert f in FIELD_RULES, f"closure {name}: field {f!r} has no rule in materials/check.py"
        assert f in FIELD_LANES, f"closure {name}: field {f!r} has no lanes in upload/materials.py"
    assert "albedo" in kind.fields  # the diffuse-only albedo and textured albedo sum every closure's colour
    for lobe in kind.lobes:
        assert lobe in device_lobe_kinds(), f"closure {name}: lobe {lobe!r} is not registered in bsdf/lobes.h"


def test_every_lobe_kind_is_made_by_some_closure_kind():
    made = {lobe for k in CLOSURE_KINDS for lobe in k.lobes}
    assert made == set(device_lobe_kinds())


@pytest.mark.parametrize("name", NAMES)
def test_each_kind_checks_the_fields_it_reads_and_ignores_the_others(name):
    kind = KINDS[name]
    check_material(mid_material(name))
    for f in FIELD_RULES:
        bad = mid_material(name)
        setattr(bad, f, object())
        if f in kind.fields:
            with pytest.raises(MaterialError, match=f):
                check_material(bad)
        else:
            check_material(bad)
            pack_materials([bad])


@pytest.fixture(scope="module")
def kernels(device):
    return LobeKernels(device)


@pytest.mark.parametrize("name", NAMES)
def test_each_kind_resolves_into_the_lobes_it_declares(kernels, name):
    """A closure packed by upload/materials.py and resolved on the device gives a lobe exactly where its kind's
    has_lobe says (the HAS_GLOSSY flag relies on it), of a kind its entry declares."""
    kind = KINDS[name]
    codes = {lobe: int(re.search(rf"#define {code} (\d+)", (opencl_dir() / "bsdf" / f"{lobe}.h").read_text())[1])
             for lobe, code in device_lobe_kinds().items()}
    plain = mid_material(name, "plain")
    plain.metallic = plain.specular = 0.0
    for m in (mid_material(name), plain):
        w_lambert, lobes = kernels.surface(m, view(30.0))
        assert len(lobes) == int(kind.has_lobe(m)), (m.name, lobes)
        assert {lb["kind"] for lb in lobes} <= {codes[lobe] for lobe in kind.lobes}
        assert np.isfinite(w_lambert) and all(lb["weight"] > 0 for lb in lobes)
