"""Cryptomatte's ranking (render/cryptomatte.py): ids by coverage, largest first, ids of one asset merged, empty
ranks 0, the float bits of the hashes; and a still's layers against the G-buffer's objects (interior pixels: one
id, coverage 1)."""

from __future__ import annotations

import numpy as np
from restircl import Renderer, Settings
from restircl.render.cryptomatte import name_id, ranked

from ..lights.linking_scene import linking_scene


def _f32(x: float) -> int:
    return int(np.array([x], np.float32).view(np.uint32)[0])


def test_ranks_by_coverage_and_merges_assets():
    slots = np.zeros((1, 2, 3, 2), np.uint32)
    slots[0, 0] = [(1, 2), (2, 5), (3, 1)]  # ids 0, 1, 2 (+1) seen 2, 5 and 1 times of 8
    slots[0, 1] = [(2, 8), (0, 0), (0, 0)]
    out = ranked(slots, 8, ["a", "b", "c"], 4)
    assert out.shape == (1, 2, 8)
    px = out[0, 0]
    assert [_f32(px[0]), _f32(px[2]), _f32(px[4])] == [_f32(name_id(n)) for n in "bac"]
    np.testing.assert_allclose(px[1::2], [5 / 8, 2 / 8, 1 / 8, 0.0])
    assert _f32(out[0, 1, 0]) == _f32(name_id("b")) and out[0, 1, 1] == 1.0 and not out[0, 1, 2:].any()
    merged = ranked(slots, 8, ["x", "y", "x"], 2)  # ids 0 and 2 in one asset x: 3 samples
    assert _f32(merged[0, 0, 0]) == _f32(name_id("y")) and _f32(merged[0, 0, 2]) == _f32(name_id("x"))
    np.testing.assert_allclose(merged[0, 0, 1::2], [5 / 8, 3 / 8])


def test_a_still_ranks_what_its_pixels_show():
    sc = linking_scene(linked=False)
    r = Renderer(sc, Settings(method="ris", seed=1, cryptomatte_levels=4))
    f = r.render_still(0, samples=8)
    assert f.cryptomatte is not None and set(f.cryptomatte) == {"object", "material", "asset"}
    obj = f.cryptomatte["object"]
    g = r.read_gbuffer()
    hit = g["normal"][..., 3].view(np.int32) >= 0
    ids = np.where(hit, g["albedo"][..., 3].view(np.int32) & 0xFFFFF, -1)
    hashes = {k: _f32(name_id(m.name)) for k, m in enumerate(sc.meshes)}
    inner = obj[..., 1] == 1.0  # one object in every sample
    assert inner[hit].mean() > 0.8
    got = obj[..., 0].view(np.uint32)
    for k, h in hashes.items():
        assert np.all(got[inner & (ids == k)] == h)
    assert not obj[~hit & inner].any()  # misses: no id
    np.testing.assert_allclose(obj[..., 1::2].sum(-1)[hit & inner], 1.0)


def test_the_exr_holds_the_layers_the_groups_and_the_manifest(tmp_path):
    import OpenEXR
    from restircl.io.images import write_exr

    sc = linking_scene(linked=False)
    sc.light_groups = ["all"]
    for part in (*sc.lights, *sc.meshes):
        part.lightgroup = "all"
    f = Renderer(sc, Settings(method="ris", seed=1, cryptomatte_levels=3)).render_still(0, samples=4)
    write_exr(tmp_path / "f.exr", f)
    with OpenEXR.File(str(tmp_path / "f.exr"), separate_channels=True) as exr:
        names = set(exr.channels())
        header = {k: v for k, v in exr.header().items() if isinstance(v, str)}
    assert {"Combined_all.R", "Combined_all.G", "Combined_all.B"} <= names
    for layer in ("CryptoObject", "CryptoMaterial", "CryptoAsset"):  # 3 ranks: two layers, the second half empty
        assert {f"{layer}{k:02d}.{c}" for k in range(2) for c in "rgba"} <= names
        assert f"{layer}02.r" not in names
    key = next(k for k, v in header.items() if k.endswith("/name") and v == "CryptoObject")
    assert '"floor_a":' in header[key.replace("/name", "/manifest")]
