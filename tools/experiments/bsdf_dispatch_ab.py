"""Issue 35: the cost of the BSDF's lobe dispatch (opencl/bsdf/lobes.h). Device sources of several trees side by
side, interleaved run by run in one process, this tree's host code feeding all of them:
  kernel  a BSDF-bound kernel: per work-item one resolved glossy surface (1-2 packed closures, each with a lobe),
          then 64 x (bsdf_eval, bsdf_pdf) and 8 bsdf_sample; its outputs must be bit-identical across the trees;
  frames  frames of the glossy material_balls (ris 8 candidates, restir), frame by frame.

    git archive <commit> opencl | tar -x -C /tmp/old
    python tools/experiments/bsdf_dispatch_ab.py base=/tmp/old/opencl new=opencl [--runs 100] [--frames 160]

Prints per tree the median ms and the median (and quartiles) of the ratio to the first tree, run by run.
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np
import pyopencl as cl
from restircl.core import program
from restircl.core.device import get_device
from restircl.materials.material import Material
from restircl.render.features import general_flags
from restircl.render.pipeline import Renderer
from restircl.scenes.builtin import material_balls
from restircl.settings.table import Settings
from restircl.upload.ggx_tables import ggx_tables
from restircl.upload.materials import pack_materials

HEADERS = """
#include "types.h"
#include "numerics.h"
#include "sampling/rng.h"
#include "lights/lights.h"
#include "surface/surface.h"
#include "textures/point.h"
#include "textures/image.h"
#include "textures/nodes.h"
#include "textures/closure_inputs.h"
#include "bsdf/bsdf.h"
"""
KERNEL = """
/* per work-item c: material c of mats (its closures in cl) at a surface of normal and view g[2 c], g[2 c + 1] */
__kernel void bench(const __global Material* mats, const __global Closure* cl, const __global float4* g,
                    const __global float4* dirs, const __global float* tab, __global float4* out)
{
    int c = get_global_id(0);
    int4 info = mats[c].info;
    ClosureInputs in[MAX_LAYERS];
    for (int k = 0; k < info.y; ++k) in[k] = closure_constants(&cl[info.x + k]);
    Surface s;
    s.x = (float3)(0.0f);
    surface_set_normal(&s, g[2 * c].xyz);
    float3 wo = g[2 * c + 1].xyz;
    s.wo = wo;
    s.depth = 1.0f;
    s.valid = 1;
    s.prim = 0;
    GlossySample gx;
    s.mat.albedo = surface_resolve(in, info.y, s.n, wo, tab, &gx);
    s.mat.lobes = as_int(gx.wo.w);
    s.mat.lobe[0] = gx.lobe0;
    s.mat.lobe[1] = gx.lobe1;
    float4 acc = (float4)(0.0f);
    for (int i = 0; i < 64; ++i) {
        float3 wi = dirs[(c * 7 + i) & 255].xyz;
        acc += (float4)(bsdf_eval(&s, wo, wi), bsdf_pdf(&s, wo, wi));
    }
    for (int i = 0; i < 8; ++i) {
        float3 wi;
        float pdf;
        float4 u = dirs[(c * 3 + i) & 255];
        acc += (float4)(bsdf_sample(&s, wo, 0.5f * u.x + 0.5f, 0.5f * u.y + 0.5f, &wi, &pdf), pdf);
    }
    out[c] = acc;
}
"""


def use(d: Path) -> None:
    program.opencl_dir = lambda: d  # build_program's -I and main file, for every build that follows


def source(d: Path) -> str:
    """The resolve's header of tree d: bsdf/resolve.h, or bsdf/principled.h before the lobe split."""
    split = (d / "bsdf" / "resolve.h").exists()
    resolve = '#include "bsdf/resolve.h"\n' if split else '#include "bsdf/tables.h"\n#include "bsdf/principled.h"\n'
    return HEADERS + resolve + KERNEL


def report(label: str, ts: dict[str, list[float]]) -> None:
    names = list(ts)
    ms = {n: round(1e3 * float(np.median(v)), 1) for n, v in ts.items()}
    line = f"{label}: median ms {ms}"
    for n in names[1:]:
        r = np.array(ts[n]) / np.array(ts[names[0]])
        line += (f"; {n}/{names[0]} {np.median(r):.3f} (quartiles {np.percentile(r, 25):.3f} "
                 f"{np.percentile(r, 75):.3f})")
    print(line)


def bench_kernel(trees: dict[str, Path], runs: int) -> None:
    dev = get_device()
    progs = {}
    for name, d in trees.items():
        use(d)
        progs[name] = cl.Kernel(program.build_program(dev, general_flags(), source=source(d)), "bench")
    rng = np.random.default_rng(7)
    n = 1 << 15

    def closure(k: int) -> Material:
        return Material(f"c{k}", albedo=tuple(rng.uniform(0, 1, 3)), kind=str(rng.choice(["principled", "glossy"])),
                        metallic=float(rng.choice([0.0, 1.0])), roughness=float(rng.uniform(0.05, 1)), specular=0.5)

    mats = [closure(c) if rng.random() < 0.5 else Material.mixed(closure(c), closure(c)) for c in range(n)]
    packed = pack_materials(mats)
    g = np.zeros((n, 2, 4), np.float32)
    g[:, 0, 2] = 1.0
    wo = rng.normal(size=(n, 3))
    wo[:, 2] = np.abs(wo[:, 2])
    g[:, 1, :3] = wo / np.linalg.norm(wo, axis=1, keepdims=True)
    d = rng.normal(size=(256, 4))
    d[:, 2] = np.abs(d[:, 2])
    d[:, :3] /= np.linalg.norm(d[:, :3], axis=1, keepdims=True)
    mf = cl.mem_flags
    args = [cl.Buffer(dev.context, mf.READ_ONLY | mf.COPY_HOST_PTR, hostbuf=np.ascontiguousarray(a))
            for a in (packed.materials, packed.closures, g, d.astype(np.float32), ggx_tables())]
    ob = cl.Buffer(dev.context, mf.WRITE_ONLY, n * 16)
    ts: dict[str, list[float]] = {name: [] for name in trees}
    outs = {}
    for r in range(runs + 1):
        for name in (list(trees) if r % 2 == 0 else list(trees)[::-1]):
            t = time.perf_counter()
            progs[name](dev.queue, (n,), None, *args, ob)
            dev.queue.finish()
            if r > 0:  # the first run of each is a warm-up
                ts[name].append(time.perf_counter() - t)
            out = np.empty((n, 4), np.float32)
            cl.enqueue_copy(dev.queue, out, ob)
            outs[name] = out.view(np.uint32)
    report("kernel", ts)
    first = outs[next(iter(trees))]
    print("  outputs bit-identical:", all(np.array_equal(first, o) for o in outs.values()))


def bench_frames(trees: dict[str, Path], frames: int, width: int, height: int) -> None:
    for method, kw in (("ris", {"method": "ris", "candidates": 8}), ("restir", {"method": "restir"})):
        rs = {}
        for name, d in trees.items():
            use(d)
            rs[name] = Renderer(material_balls(width, height, frames=8), Settings(**kw))
            for i in range(3):
                rs[name].render_frame(i, aovs=False)
        ts: dict[str, list[float]] = {name: [] for name in trees}
        for r in range(frames):
            for name in (list(trees) if r % 2 == 0 else list(trees)[::-1]):
                use(trees[name])
                t = time.perf_counter()
                rs[name].render_frame(3 + r % 5, aovs=False)
                ts[name].append(time.perf_counter() - t)
        report(f"frames {method} {width}x{height}", ts)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("trees", nargs="+", help="name=opencl-directory; the first is the base")
    ap.add_argument("--runs", type=int, default=100)
    ap.add_argument("--frames", type=int, default=160)
    ap.add_argument("--width", type=int, default=320)
    ap.add_argument("--height", type=int, default=180)
    a = ap.parse_args()
    trees = {t.split("=", 1)[0]: Path(t.split("=", 1)[1]).resolve() for t in a.trees}
    bench_kernel(trees, a.runs)
    bench_frames(trees, a.frames, a.width, a.height)


if __name__ == "__main__":
    main()
