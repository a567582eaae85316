"""Test kernels for the BSDF's parts one at a time: a surface at the origin, normal +z, whose material is a packed
Closure table (upload/materials.py, as the renderer uploads it) resolved for a view direction as the primary pass
does (bsdf/resolve.h); then its Lambert part, each of its lobes through the dispatch of bsdf/lobes.h, and the
mixture (bsdf/bsdf.h), side by side. Also what the registrations on the device say: the lobe kinds listed in
bsdf/lobes.h."""

from __future__ import annotations

import re

import numpy as np
import pyopencl as cl
import pyopencl.cltypes as clt
from restircl.core.program import build_program, opencl_dir
from restircl.materials.material import Material
from restircl.render.features import general_flags
from restircl.upload.glass_tables import device_tables
from restircl.upload.materials import pack_materials

from .bsdf_kernels import HEADERS

SRC = HEADERS + """
/* the surface whose material is the packed closures cl[0 .. count) */
inline Surface resolved(const __global Closure* cl, int count, const __global float* tab, float3 wo)
{
    ClosureInputs in[MAX_LAYERS];
    for (int k = 0; k < count; ++k) in[k] = closure_constants(&cl[k]);
    return resolved_surface(in, count, tab, wo);
}

/* the code of every registered lobe kind, in BSDF_LOBE_KINDS order */
#define WRITE_LOBE_CODE(code, name) out[k++] = code;
__kernel void lobe_codes(__global int* out)
{
    int k = 0;
    BSDF_LOBE_KINDS(WRITE_LOBE_CODE)
}

/* the resolved surface: (Lambert's sampling weight, lobe count, 0, 0), then per lobe slot in use (sampling weight,
 * kind, alpha, 0) and its albedo (rgb, 0) */
__kernel void surface_parts(const __global Closure* cl, int count, const __global float* tab, float4 wo4,
                            __global float4* out)
{
    Surface s = resolved(cl, count, tab, wo4.xyz);
    out[0] = (float4)(lambert_weight(s.mat.albedo), (float)s.mat.lobes, 0.0f, 0.0f);
    for (int k = 0; k < s.mat.lobes; ++k) {
        const Lobe* l = &s.mat.lobe[k];
        out[1 + 2 * k] = (float4)(lobe_weight(l), (float)lobe_kind(l), lobe_alpha(l), 0.0f);
        out[2 + 2 * k] = (float4)(lobe_albedo(l), 0.0f);
    }
}

/* per direction: (f, pdf) of the mixture, of the Lambert part, then of each lobe slot (0 past the lobes in use) */
__kernel void direction_parts(const __global Closure* cl, int count, const __global float* tab, float4 wo4,
                              const __global float4* dirs, __global float4* out)
{
    int i = get_global_id(0);
    Surface s = resolved(cl, count, tab, wo4.xyz);
    float3 wo = wo4.xyz, wi = dirs[i].xyz;
    __global float4* o = out + i * (2 + MAX_LAYERS);
    o[0] = (float4)(bsdf_eval(&s, wo, wi), bsdf_pdf(&s, wo, wi));
    o[1] = (float4)(bsdf_eval_diffuse(&s, wi), lambert_pdf(s.n, wi));  /* 0 below the surface, as the mixture has it */
    for (int k = 0; k < MAX_LAYERS; ++k) {
        const Lobe* l = &s.mat.lobe[k];
        o[2 + k] = k < s.mat.lobes ? (float4)(lobe_eval(l, s.nl, wo, wi), lobe_pdf(l, s.nl, wo, wi)) : (float4)(0.0f);
    }
}

/* lobe slot k's own samples of the host's uniform numbers u[i]: (wi, 1), or 0 where it drew none */
__kernel void lobe_samples(const __global Closure* cl, int count, const __global float* tab, float4 wo4, int k,
                           const __global float2* u, __global float4* out)
{
    int i = get_global_id(0);
    Surface s = resolved(cl, count, tab, wo4.xyz);
    float3 wi;
    bool ok = lobe_sample(&s.mat.lobe[k], s.nl, wo4.xyz, u[i].x, u[i].y, &wi);
    out[i] = ok ? (float4)(wi, 1.0f) : (float4)(0.0f);
}
"""


def device_lobe_kinds() -> dict[str, str]:
    """The lobe kinds registered in opencl/bsdf/lobes.h, name -> code macro, in their order there."""
    text = (opencl_dir() / "bsdf" / "lobes.h").read_text()
    body = re.search(r"#define BSDF_LOBE_KINDS\(X\)((?:[^\n]*\\\n)*[^\n]*)", text)
    assert body is not None, "opencl/bsdf/lobes.h defines no BSDF_LOBE_KINDS(X)"
    return {name: code for code, name in re.findall(r"X\((\w+),\s*(\w+)\)", body.group(1))}


def mid_material(kind: str, name: str = "mid") -> Material:
    """A closure of `kind` with every input at a middle value (a Principled one has a metallic and a specular part)."""
    return Material(name, albedo=(0.6, 0.5, 0.4), kind=kind, metallic=0.5, roughness=0.4, specular=0.5,
                    specular_tint=(1.0, 0.9, 0.8))


class LobeKernels:
    def __init__(self, device, source: str = SRC) -> None:
        self.device = device
        self.prog = build_program(device, general_flags(), source=source)
        self.tab = self._buf(device_tables())

    def _buf(self, a: np.ndarray) -> cl.Buffer:
        mf = cl.mem_flags
        return cl.Buffer(self.device.context, mf.READ_ONLY | mf.COPY_HOST_PTR, hostbuf=np.ascontiguousarray(a))

    def _run(self, name: str, m: Material, wo: np.ndarray, size: int, out: np.ndarray, *args) -> np.ndarray:
        closures = pack_materials([m]).closures
        count = len(m.layers) if m.layers else 1
        ob = cl.Buffer(self.device.context, cl.mem_flags.WRITE_ONLY, out.nbytes)
        cl.Kernel(self.prog, name)(self.device.queue, (size,), None, self._buf(closures), np.int32(count), self.tab,
                                   clt.make_float4(*wo, 0.0), *args, ob)
        cl.enqueue_copy(self.device.queue, out, ob)
        return out

    def lobe_codes(self) -> list[int]:
        out = np.full(64, -1, np.int32)
        ob = cl.Buffer(self.device.context, cl.mem_flags.WRITE_ONLY | cl.mem_flags.COPY_HOST_PTR, hostbuf=out)
        cl.Kernel(self.prog, "lobe_codes")(self.device.queue, (1,), None, ob)
        cl.enqueue_copy(self.device.queue, out, ob)
        return out[out >= 0].tolist()

    def surface(self, m: Material, wo: np.ndarray) -> tuple[float, list[dict]]:
        """Lambert's sampling weight and per lobe {weight, kind, alpha, albedo}."""
        out = self._run("surface_parts", m, wo, 1, np.zeros((1 + 4, 4), np.float32)).astype(np.float64)
        lobes = [{"weight": out[1 + 2 * k, 0], "kind": int(out[1 + 2 * k, 1]), "alpha": out[1 + 2 * k, 2],
                  "albedo": out[2 + 2 * k, :3]} for k in range(int(out[0, 1]))]
        return float(out[0, 0]), lobes

    def directions(self, m: Material, wo: np.ndarray, dirs: np.ndarray) -> np.ndarray:
        """(len(dirs), 2 + MAX_LAYERS, 4): (f rgb, pdf) of the mixture, Lambert, each lobe slot; float64."""
        d4 = np.zeros((len(dirs), 4), np.float32)
        d4[:, :3] = dirs
        out = np.zeros((len(dirs), 4, 4), np.float32)
        return self._run("direction_parts", m, wo, len(dirs), out, self._buf(d4)).astype(np.float64)

    def lobe_samples(self, m: Material, wo: np.ndarray, slot: int, count: int, seed: int = 5) -> np.ndarray:
        """(count, 4): (wi, 1) per sample of lobe slot `slot`, 0 where it drew none; float64."""
        u = np.minimum(np.random.default_rng(seed).random((count, 2)), 0.99999994).astype(np.float32)
        out = np.zeros((count, 4), np.float32)
        return self._run("lobe_samples", m, wo, count, out, np.int32(slot), self._buf(u)).astype(np.float64)
