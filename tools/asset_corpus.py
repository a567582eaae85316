"""The corpus of real assets (tests/blender/asset_corpus.py CORPUS, found in $RESTIRCL_ASSETS by
restircl.eval.assets; tools/fetch_assets.py gets them): the node coverage table of docs/blender.md, and each asset's
scene rendered by F12 against Cycles, direct light and with Light Paths Max Bounces 4.

    python tools/asset_corpus.py table                   # the markdown table, from the imported materials
    python tools/asset_corpus.py render [--size 48 36] [--cycles 2048] [--ours 1024] [--bounces 0 4]
"""

from __future__ import annotations

import argparse
import sys
import tempfile
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))


def _label(kind: str) -> str:
    return kind.removeprefix("ShaderNode").removeprefix("Node")


def _kinds(kinds: list[str]) -> str:
    """'TexImage ×4, UVMap' of a list with one entry per node."""
    counts = {k: kinds.count(k) for k in sorted(set(kinds))}
    return ", ".join(f"{_label(k)} ×{n}" if n > 1 else _label(k) for k, n in counts.items()) or "—"


def table() -> list[str]:
    import bpy
    from restircl.eval import assets
    from restircl.eval import blender_scenes as scenes

    from tests.blender.asset_corpus import CORPUS, corpus_scene, coverage
    from tests.blender.test_blender_support import ensure_registered

    ensure_registered()
    from restircl_blender import export as ex

    rows = ["| asset | material | node types (count) | native | baked | ignored | export's notes |",
            "|---|---|---|---|---|---|---|"]
    for name in CORPUS:
        path, why = assets.find(name)
        if path is None:
            rows.append(f"| {name} | (absent: {why}) | | | | | |")
            continue
        corpus_scene(path, 16, 12)
        exp = ex.export_scene(bpy.context.evaluated_depsgraph_get(), bake_resolution=16)
        mats = sorted({s.material for o in bpy.context.scene.objects if o.type == "MESH" and o.name != "Floor"
                       for s in o.material_slots if s.material is not None}, key=lambda m: m.name)
        for mat in mats:
            c = coverage(mat, exp.warnings)
            kinds = _kinds([k for k, n in c.counts.items() for _ in range(n)])
            rows.append(f"| {name} | {mat.name} | {kinds} | {_kinds(c.native)} | {_kinds(c.baked)} | "
                        f"{_kinds(c.ignored)} | {'; '.join(c.notes) or '—'} |")
        scenes.new_scene(16, 12)
    return rows


def render(size: tuple[int, int], cycles_spp: int, our_spp: int, bounces: list[int]) -> None:
    from restircl.eval import assets

    from tests.blender.asset_corpus import CORPUS, compare, corpus_scene

    for name in CORPUS:
        path, why = assets.find(name)
        if path is None:
            print(f"{name}: skipped: {why}")
            continue
        for b in bounces:
            out = Path(tempfile.mkdtemp(prefix=f"corpus_{Path(name).stem}_b{b}_"))
            r = compare(corpus_scene(path, *size), cycles_spp, our_spp, b, out)
            print(f"{name} bounces {b}: {size[0]}x{size[1]} Cycles {cycles_spp} / ours {our_spp}: relMSE "
                  f"{100 * r['relmse']:.3f} %  mean ours/cycles {r['mean_ratio']:.4f}  "
                  f"({r['t_cycles']:.0f} s / {r['t_ours']:.0f} s; {out})", flush=True)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = ap.add_subparsers(dest="cmd", required=True)
    sub.add_parser("table")
    r = sub.add_parser("render")
    r.add_argument("--size", type=int, nargs=2, default=(48, 36))
    r.add_argument("--cycles", type=int, default=2048)
    r.add_argument("--ours", type=int, default=1024)
    r.add_argument("--bounces", type=int, nargs="+", default=[0, 4])
    args = ap.parse_args(argv)
    if args.cmd == "table":
        print("\n".join(table()))
    else:
        render(tuple(args.size), args.cycles, args.ours, args.bounces)
    return 0


if __name__ == "__main__":
    sys.exit(main())
