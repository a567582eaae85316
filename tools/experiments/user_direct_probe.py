"""Where our converged direct light on the `user` kind differs from Cycles' (issue 37): both renderers' light
passes (Combined, Diffuse and Glossy Direct, Emission, Environment, Diffuse and Glossy Color) and the object index,
two independent renders a side, at equal samples, of the user scene or of a variant of it (a subset of its lights,
its world alone, ...: VARIANTS, applied to the bpy scene before the add-on exports it, so both sides see the same
scene). Writes one .npz per side and variant; `--report` prints per object and per pass the converged relMSE (the
renders' own noise taken out by their halves) and the mean ratio ours / Cycles. docs/measurements/error-vs-time.md,
"user's direct light against Cycles".

    nice python -m tools.experiments.user_direct_probe --variant all --spp 1024 --out out/udp
    nice python -m tools.experiments.user_direct_probe --variant all --report --out out/udp
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np
from restircl.eval.cycles.passes import render_passes
from restircl.eval.metrics import rel_mse
from restircl.render.pipeline import Renderer
from restircl.settings.table import Settings

PASSES = ("diffuse_direct", "glossy_direct", "emission", "environment", "albedo", "glossy_color", "object_index")
SIDE_PASSES = ("color", *PASSES)
SEEDS = (101, 102)


def _remove(bpy, keep) -> None:
    for ob in list(bpy.data.objects):
        if ob.type == "LIGHT" and not keep(ob):
            bpy.data.objects.remove(ob)


def _world_off(bpy, sc) -> None:
    sc.world.node_tree.nodes["Background"].inputs["Strength"].default_value = 0.0


def _variant(bpy, sc, name: str) -> None:
    """Change the bpy user scene into the variant `name` (before export): NAME[+MODIFIER...]."""
    name, *mods = name.split("+")
    for mod in mods:
        if mod == "closest":  # the world's Environment Texture read texel by texel (Blender's default: Linear)
            tex = next(n for n in sc.world.node_tree.nodes if n.bl_idname == "ShaderNodeTexEnvironment")
            tex.interpolation = "Closest"
        elif mod == "flat":  # every mesh flat-shaded: no smooth normal to correct at the silhouettes
            for ob in bpy.data.objects:
                if ob.type == "MESH":
                    for f in ob.data.polygons:
                        f.use_smooth = False
        elif mod == "noterm":  # Cycles' shadow terminator geometry offset off (Blender's default is 0.1)
            for ob in bpy.data.objects:
                if ob.type == "MESH":
                    ob.shadow_terminator_geometry_offset = 0.0
        else:
            raise ValueError(mod)
    if name == "all":
        return
    if name == "world":
        _remove(bpy, lambda ob: False)
        return
    _world_off(bpy, sc)
    types = {"sun": "SUN", "area": "AREA", "spot": "SPOT", "point": "POINT"}
    if name in types:
        _remove(bpy, lambda ob: ob.data.type == types[name])
        return
    if name == "lights":
        return
    if name.startswith("light:"):  # one light by name
        _remove(bpy, lambda ob: ob.name == name.split(":", 1)[1])
        return
    raise ValueError(name)


def build(width: int, height: int, variant: str):
    """(restircl Scene, bpy scene) of the user kind's `variant`, objects numbered by pass index (1, 2, ...)."""
    import bpy
    from restircl.eval.scenes import user_scene as us
    from restircl.io.blend import addon_module

    _, sc = us.user_scene(width, height)
    for i, ob in enumerate(sorted((o for o in bpy.data.objects if o.type == "MESH"), key=lambda o: o.name)):
        ob.pass_index = i + 1
    _variant(bpy, sc, variant)
    bpy.context.view_layer.update()
    exp = addon_module().export.export_scene(bpy.context.evaluated_depsgraph_get())
    scene = exp.scene
    scene.name = f"user_{variant}"
    return scene.validate(), sc


def object_names() -> list[str]:
    import bpy

    return sorted(o.name for o in bpy.data.objects if o.type == "MESH")


def render_cycles(sc, spp: int) -> dict[str, np.ndarray]:
    out = {}
    for k, seed in enumerate(SEEDS):
        r = render_passes(sc, PASSES[:-1], spp, seed)
        for name, img in r.items():
            out[f"{name}{k}"] = img
    return out


def render_ours(scene, frames: int, settings: dict) -> dict[str, np.ndarray]:
    out = {}
    for k, seed in enumerate(SEEDS):
        s = Settings(**{"method": "ris", "candidates": 32, "light_passes": True, "seed": seed, **settings})
        f = Renderer(scene, s.validate()).render_still(0, frames)
        for name in SIDE_PASSES:
            img = getattr(f, name)
            if img is None:
                continue
            img = np.asarray(img, np.float32)
            out[f"{name}{k}"] = np.repeat(img[..., None], 3, -1) if img.ndim == 2 else img[..., :3]
    return out


def converged(o: list[np.ndarray], c: list[np.ndarray]) -> tuple[float, float]:
    """(relMSE of the two sides' means with the noise of both taken out, the noise's share) as rel_mse weighs it."""
    o64 = [x.astype(np.float64) for x in o]
    c64 = [x.astype(np.float64) for x in c]
    mo, mc = (o64[0] + o64[1]) / 2, (c64[0] + c64[1]) / 2
    w = 1.0 / (mc * mc + 0.01)
    raw = np.mean((mo - mc) ** 2 * w)
    noise = np.mean(((o64[0] - o64[1]) ** 2 / 4 + (c64[0] - c64[1]) ** 2 / 4) * w)
    return float(raw - noise), float(noise)


def report(ours: dict, cyc: dict, names: list[str]) -> None:
    idx = np.rint(ours["object_index0"][..., 0]).astype(int)  # Cycles' is one channel: not read
    mc_all = (cyc["color0"].astype(np.float64) + cyc["color1"]) / 2
    mo_all = (ours["color0"].astype(np.float64) + ours["color1"]) / 2
    n = mc_all.size
    print(f"relMSE of the means {rel_mse(mo_all, mc_all):.3e}; sums ours/Cycles {mo_all.sum() / mc_all.sum():.4f}")
    rel, noise = converged([ours["color0"], ours["color1"]], [cyc["color0"], cyc["color1"]])
    print(f"combined: converged relMSE {rel:.3e} (noise {noise:.3e})")
    w = 1.0 / (mc_all * mc_all + 0.01)
    d2 = (mo_all - mc_all) ** 2 * w
    nz = (
        (ours["color0"] - ours["color1"].astype(np.float64)) ** 2 / 4
        + (cyc["color0"] - cyc["color1"].astype(np.float64)) ** 2 / 4
    ) * w
    print("per object: pixels, share of the excess (sum over image / N), mean ratio ours/Cycles")
    for i in range(idx.max() + 1):
        m = idx == i
        if not m.any():
            continue
        ex = float((d2[m] - nz[m]).sum() / n)
        ratio = float(mo_all[m].sum() / max(mc_all[m].sum(), 1e-30))
        name = "background" if i == 0 else names[i - 1]
        print(f"  {name:<12} {int(m.sum()):6d} px  excess {ex:.3e}  ratio {ratio:.4f}")
    for p in ("diffuse_direct", "glossy_direct", "emission", "environment", "albedo", "glossy_color"):
        if f"{p}0" not in ours or f"{p}0" not in cyc:
            continue
        o = (ours[f"{p}0"].astype(np.float64) + ours[f"{p}1"]) / 2
        c = (cyc[f"{p}0"].astype(np.float64) + cyc[f"{p}1"]) / 2
        line = [f"{p:<15} sum ratio {o.sum() / max(c.sum(), 1e-30):.4f}"]
        for i in range(idx.max() + 1):
            m = idx == i
            if m.any() and c[m].sum() > 0:
                line.append(f"{('bg' if i == 0 else names[i - 1])[:8]} {o[m].sum() / c[m].sum():.3f}")
        print("  ".join(line))


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--variant", default="all")
    p.add_argument("--width", type=int, default=192)
    p.add_argument("--height", type=int, default=108)
    p.add_argument("--spp", type=int, default=1024, help="Cycles' samples and our frames, each of two renders")
    p.add_argument("--side", default="both", choices=("both", "cycles", "ours"))
    p.add_argument("--tag", default="", help="a name for our variant of settings (--set)")
    p.add_argument("--set", action="append", default=[], help="Settings override NAME=VALUE of ours")
    p.add_argument("--report", action="store_true")
    p.add_argument("--out", default="out/udp")
    a = p.parse_args()
    out = Path(a.out)
    out.mkdir(parents=True, exist_ok=True)
    stem = f"{a.variant.replace(':', '_').replace('+', '_')}_{a.width}x{a.height}_{a.spp}"
    cpath, opath = out / f"cycles_{stem}.npz", out / f"ours{a.tag}_{stem}.npz"
    scene, sc = build(a.width, a.height, a.variant)
    if a.report:
        report(dict(np.load(opath)), dict(np.load(cpath)), object_names())
        return
    if a.side in ("both", "cycles"):
        np.savez_compressed(cpath, **render_cycles(sc, a.spp))
        print(f"wrote {cpath}")
    if a.side in ("both", "ours"):
        overrides = {}
        for kv in a.set:
            k, v = kv.split("=", 1)
            overrides[k] = (
                type(getattr(Settings(), k))(v)
                if not isinstance(getattr(Settings(), k), bool)
                else v.lower() in ("1", "true", "on")
            )
        np.savez_compressed(opath, **render_ours(scene, a.spp, overrides))
        print(f"wrote {opath}")


if __name__ == "__main__":
    main()
