"""Test kernels for the BSDF (opencl/bsdf/bsdf.h over the closure resolves of bsdf/resolve.h and the lobes of
bsdf/lobes.h): a surface at the origin, normal +z, whose material is resolved from closure inputs for a view
direction exactly as the primary pass does, then evaluated, sampled or read back."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pyopencl as cl
import pyopencl.cltypes as clt
from restircl.core.program import build_program
from restircl.render.features import general_flags
from restircl.upload.glass_tables import device_tables
from restircl.upload.materials import KIND_CODE

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
#include "bsdf/resolve.h"

/* the surface at the origin, normal +z, seen from wo, whose count closures' inputs are resolved as the primary pass
 * resolves them */
inline Surface resolved_surface(const ClosureInputs* in, int count, const __global float* tab, float3 wo)
{
    Surface s;
    s.x = (float3)(0.0f);
    surface_set_normal(&s, (float3)(0.0f, 0.0f, 1.0f));
    s.wo = wo;
    s.depth = 1.0f;
    s.valid = 1;
    s.prim = 0;
    GlossySample gx;
    s.mat.albedo = surface_resolve(in, count, s.n, wo, tab, &gx);
    s.mat.lobes = as_int(gx.wo.w);
    s.mat.lobe[0] = gx.lobe0;
    s.mat.lobe[1] = gx.lobe1;
    return s;
}
"""

SRC = HEADERS + """
/* closure k is p[12 k ..]: base rgb, metallic, roughness, ior, specular, tint rgb, weight, kind + 8 multiscatter */
inline Surface test_surface(const __global float* p, int count, const __global float* tab, float3 wo)
{
    ClosureInputs in[MAX_LAYERS];
    for (int k = 0; k < count; ++k) {
        const __global float* q = p + 12 * k;
        in[k].base = (float3)(q[0], q[1], q[2]);
        in[k].metallic = q[3];
        in[k].roughness = q[4];
        in[k].ior = q[5];
        in[k].specular = q[6];
        in[k].tint = (float3)(q[7], q[8], q[9]);
        in[k].weight = q[10];
        in[k].kind = (int)q[11] & 7;
        in[k].multiscatter = (int)q[11] >> 3;
        in[k].transmission = 0.0f;
        in[k].backfacing = 0;
        in[k].thin_wall = 0;
        in[k].film_thickness = 0.0f;
        in[k].film_ior = 1.33f;
    }
    return resolved_surface(in, count, tab, wo);
}

/* per direction: (f, pdf) */
__kernel void eval_dirs(const __global float* p, int count, const __global float* tab, float4 wo4,
                        const __global float4* dirs, __global float4* out)
{
    int i = get_global_id(0);
    Surface s = test_surface(p, count, tab, wo4.xyz);
    float3 wi = dirs[i].xyz;
    out[i] = (float4)(bsdf_eval(&s, wo4.xyz, wi), bsdf_pdf(&s, wo4.xyz, wi));
}

/* per sample of the host's uniform numbers u[i]: (wi, pdf), (f, bsdf_pdf at wi) */
__kernel void sample_dirs(const __global float* p, int count, const __global float* tab, float4 wo4,
                          const __global float2* u, __global float4* out)
{
    int i = get_global_id(0);
    Surface s = test_surface(p, count, tab, wo4.xyz);
    float3 wi;
    float pdf;
    float3 f = bsdf_sample(&s, wo4.xyz, u[i].x, u[i].y, &wi, &pdf);
    out[2 * i] = (float4)(wi, pdf);
    out[2 * i + 1] = (float4)(f, bsdf_pdf(&s, s.wo, wi));
}
"""

@dataclass
class Closure:
    kind: str = "principled"
    base: tuple = (0.8, 0.8, 0.8)
    metallic: float = 0.0
    roughness: float = 0.5
    ior: float = 1.5
    specular: float = 0.5
    tint: tuple = (1.0, 1.0, 1.0)
    weight: float = 1.0
    multiscatter: bool = True

    def row(self) -> list[float]:
        code = KIND_CODE[self.kind] + 8 * int(self.multiscatter)
        return [*self.base, self.metallic, self.roughness, self.ior, self.specular, *self.tint, self.weight, code]


def view(theta_deg: float) -> np.ndarray:
    t = np.radians(theta_deg)
    return np.array([np.sin(t), 0.0, np.cos(t)])


class BsdfKernels:
    def __init__(self, device, source: str = SRC) -> None:
        self.device = device
        self.prog = build_program(device, general_flags(), source=source)
        mf = cl.mem_flags
        self.tab = cl.Buffer(device.context, mf.READ_ONLY | mf.COPY_HOST_PTR, hostbuf=device_tables())

    def _params(self, closures: list[Closure]) -> cl.Buffer:
        p = np.array([c.row() for c in closures], np.float32).ravel()
        return cl.Buffer(self.device.context, cl.mem_flags.READ_ONLY | cl.mem_flags.COPY_HOST_PTR, hostbuf=p)

    def eval(self, closures: list[Closure], wo: np.ndarray, dirs: np.ndarray) -> np.ndarray:
        """(f rgb, pdf) per direction, float64."""
        d4 = np.zeros((len(dirs), 4), np.float32)
        d4[:, :3] = dirs
        mf = cl.mem_flags
        db = cl.Buffer(self.device.context, mf.READ_ONLY | mf.COPY_HOST_PTR, hostbuf=d4)
        out = np.empty((len(dirs), 4), np.float32)
        ob = cl.Buffer(self.device.context, mf.WRITE_ONLY, out.nbytes)
        cl.Kernel(self.prog, "eval_dirs")(self.device.queue, (len(dirs),), None, self._params(closures),
                                          np.int32(len(closures)), self.tab, clt.make_float4(*wo, 0.0), db, ob)
        cl.enqueue_copy(self.device.queue, out, ob)
        return out.astype(np.float64)

    def sample(self, closures: list[Closure], wo: np.ndarray, count: int, seed: int = 7) -> np.ndarray:
        """(count, 2, 4): (wi, pdf), (f, bsdf_pdf at wi), float64."""
        # uniform in [0, 1) as float32 (a float64 draw can round up to 1.0)
        u = np.minimum(np.random.default_rng(seed).random((count, 2)), 0.99999994).astype(np.float32)
        mf = cl.mem_flags
        ub = cl.Buffer(self.device.context, mf.READ_ONLY | mf.COPY_HOST_PTR, hostbuf=u)
        out = np.empty((count, 2, 4), np.float32)
        ob = cl.Buffer(self.device.context, mf.WRITE_ONLY, out.nbytes)
        cl.Kernel(self.prog, "sample_dirs")(self.device.queue, (count,), None, self._params(closures),
                                            np.int32(len(closures)), self.tab, clt.make_float4(*wo, 0.0), ub, ob)
        cl.enqueue_copy(self.device.queue, out, ob)
        return out.astype(np.float64)
