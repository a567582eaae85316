"""The light array: slots proportional to importance, at least one per emitting light, pdf = slots / M, and the
O(1) device pick follows slots / M (chi-square). Edge cases: one light, 1e6 lights, zero power, all equal."""

import numpy as np
import pyopencl as cl
from restircl.core.program import build_program
from restircl.lights.array import build_light_array
from restircl.render.features import general_flags

from ..stats import pooled_chi2

SRC = """
#include "types.h"
#include "sampling/rng.h"
#include "lights/lights.h"
#include "lights/array.h"
__kernel void picks(const __global int* slots, int slot_count, const __global float* pdf, int per_item,
                    volatile __global int* counts, __global float* pdf_err)
{
    int i = get_global_id(0);
    uint rng = rng_seed((uint)i, 0u, 17u, 0u);
    float worst = 0.0f;
    for (int k = 0; k < per_item; ++k) {
        float p;
        int light = light_array_pick(slots, slot_count, pdf, &rng, &p);
        atomic_inc(&counts[light]);
        worst = fmax(worst, fabs(p - pdf[light]));
    }
    pdf_err[i] = worst;
}
"""


def device_picks(device, la, n_lights: int, items: int = 4096, per_item: int = 256) -> np.ndarray:
    prog = build_program(device, general_flags(), source=SRC)
    mf = cl.mem_flags
    ctx, q = device.context, device.queue
    slots = cl.Buffer(ctx, mf.READ_ONLY | mf.COPY_HOST_PTR, hostbuf=la.slots)
    pdf = cl.Buffer(ctx, mf.READ_ONLY | mf.COPY_HOST_PTR, hostbuf=la.pdf)
    counts = np.zeros(n_lights, np.int32)
    cb = cl.Buffer(ctx, mf.READ_WRITE | mf.COPY_HOST_PTR, hostbuf=counts)
    err = cl.Buffer(ctx, mf.WRITE_ONLY, 4 * items)
    cl.Kernel(prog, "picks")(q, (items,), None, slots, np.int32(la.slot_count), pdf, np.int32(per_item), cb, err)
    cl.enqueue_copy(q, counts, cb)
    return counts


def test_slots_follow_importance_and_cover_every_emitter():
    rng = np.random.default_rng(0)
    imp = np.exp(rng.uniform(np.log(1e-6), np.log(1e6), 5000))
    imp[::7] = 0.0
    la = build_light_array(imp, 4.0)
    emits = imp > 0
    assert np.all(la.counts[emits] >= 1) and np.all(la.counts[~emits] == 0)
    m = la.slot_count
    np.testing.assert_array_equal(la.pdf, (la.counts / m).astype(np.float32))
    assert abs(m - 4 * len(imp)) < 0.5 * 4 * len(imp)
    # consecutive slots per light, in light order
    np.testing.assert_array_equal(la.slots, np.repeat(np.arange(len(imp)), la.counts))
    # lights large enough to own many slots get a share close to their importance share
    share = imp / imp.sum() * 4 * len(imp)  # the share of the target size M = k N
    big = share > 20
    assert np.all(np.abs(la.counts[big] - share[big]) <= 0.5 + 1e-9)


def test_device_picks_follow_slots_over_m(device):
    rng = np.random.default_rng(1)
    imp = np.exp(rng.normal(0, 2, 1000))
    imp[:50] = 0.0
    la = build_light_array(imp, 4.0)
    counts = device_picks(device, la, len(imp))
    assert counts[:50].sum() == 0
    stat, p, dof = pooled_chi2(counts, la.counts / la.slot_count)
    assert dof > 100 and p > 1e-4, (stat, p, dof)


def test_edge_cases(device):
    one = build_light_array(np.array([3.0]))
    assert one.slot_count == 4 and one.pdf[0] == 1.0
    equal = build_light_array(np.full(100, 2.5), 4.0)
    assert np.all(equal.counts == 4) and np.allclose(equal.pdf, 0.01)
    none = build_light_array(np.zeros(10))
    assert none.slot_count == 0 and np.all(none.pdf == 0)
    empty = build_light_array(np.zeros(0))
    assert empty.slot_count == 0
    nan = build_light_array(np.array([1.0, np.nan, np.inf, -1.0, 2.0]))
    assert list(nan.counts[1:4]) == [0, 0, 0] and nan.counts[0] >= 1 and nan.counts[4] >= 1


def test_million_lights(device):
    rng = np.random.default_rng(2)
    imp = np.exp(rng.uniform(np.log(1e-6), np.log(1e6), 1_000_000))
    la = build_light_array(imp, 4.0)
    assert np.all(la.counts >= 1)
    assert la.slot_count < 2**31
    assert abs(la.pdf.astype(np.float64).sum() - 1.0) < 1e-3
    # the device pick over 4M slots stays uniform per slot: the most important lights' frequencies match
    counts = device_picks(device, la, len(imp), items=8192, per_item=256)
    top = np.argsort(la.counts)[-200:]
    n = counts.sum()
    exp = la.counts[top] / la.slot_count * n
    z = (counts[top] - exp) / np.sqrt(exp)
    assert np.abs(z).max() < 5.0
    stat, p, dof = pooled_chi2(counts, la.counts / la.slot_count, min_expected=20)
    assert p > 1e-4, (stat, p, dof)
