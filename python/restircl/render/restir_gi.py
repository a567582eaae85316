"""ReSTIR GI (Ouyang et al. 2021), the bounced light of animation and viewport frames: its stages in order, run by
Renderer.run_frame in place of the path pass where the plan says `gi` (render/plan.py path_plan).

    initial   the path pass from the pixel's visible point, kept as a secondary sample (x_s, n_s, L_o): a reservoir
    temporal  merge last frame's reservoir of the same surface, found by reprojection, M capped    (plan.gi_temporal)
    boiling   empty (or forget) reservoirs far above their tile's (biased: animation path)        (plan.gi_boiling)
    spatial   merge the reservoirs of similar neighbours within a radius                          (plan.gi_spatial)
    shade     f cos L_o W added to the frame's sample (and to the indirect light)

Device side: opencl/restir_gi/ (one file per stage; the sample and its Jacobian in sample.h, the combine of the
reuse passes in reuse.h). The final reservoirs become the history (render/history.py, gi_reservoirs).
"""

from __future__ import annotations

import pyopencl as cl

from ..core import layouts as L
from ..core.buffers import alloc
from ..settings.table import BIAS_CORRECTIONS
from .stages import (
    BoilingFilter,
    FrameState,
    Paths,
    Stage,
    StageTimer,
    image_size,
    path_params,
    permutation_key,
    pixel_count,
)


class RestirGI(Stage):
    """The stages of ReSTIR GI, from the frame's G-buffer to its sample."""

    def __init__(self, *args, paths: Paths) -> None:
        super().__init__(*args)
        self.paths = paths  # the path pass: its arguments and the frame's indirect light
        self.bias_code = BIAS_CORRECTIONS.index(self.settings.gi_bias_correction)
        self._scratch: list[cl.Buffer] = []
        self.boiling = BoilingFilter(*args, kernels="gi_", strength="gi_boiling_filter")

    def run(self, state: FrameState, timer: StageTimer) -> None:
        plan, h = state.plan, self.history
        if not self._scratch:
            size = int(state.frame_params["pixels"]) * L.GI_RESERVOIR.itemsize
            self._scratch = [alloc(self.kernels.device.context, size) for _ in range(2)]
        res = self.initial(state, self._scratch[0])
        timer.mark("gi_initial")
        if plan.gi_temporal:
            res = self.temporal(state, res, self._scratch[1])
            timer.mark("gi_temporal")
        if plan.gi_boiling:
            self.boiling.run(state, res)
            timer.mark("gi_boiling")
        if plan.gi_spatial:
            res = self.spatial(state, res, h.gi_reservoirs(h.cur))
            timer.mark("gi_spatial")
        h.keep_gi(self.kernels.device.queue, res)
        self.shade(state)
        timer.mark("gi_shade")

    def initial(self, state: FrameState, out: cl.Buffer) -> cl.Buffer:
        h = self.history
        self.kernels.launch("gi_initial", pixel_count(state), gbuf=h.gbuf(h.cur), glossy=h.glossy(h.cur),
                            **self.paths.arguments(state), out=out,
                            params=path_params(self.scene, self.settings, state.plan))
        return out

    def temporal(self, state: FrameState, current: cl.Buffer, out: cl.Buffer) -> cl.Buffer:
        s, h = self.settings, self.history
        params = L.pack(L.GI_TEMPORAL_PARAMS, similar=self._similarity(), m_cap=s.gi_m_cap,
                        bias_correction=self.bias_code, permutation=permutation_key(s, state, gi=True))
        self.kernels.launch("gi_temporal", image_size(state), gbuf=h.gbuf(h.cur), prev_gbuf=h.gbuf(h.prev),
                            glossy=h.glossy(h.cur), prev_glossy=h.glossy(h.prev), **self.scene.geometry,
                            current=current, previous=h.gi_reservoirs(h.prev), out=out, guards=self.buffers.guards,
                            frame_params=state.frame_params, params=params)
        return out

    def spatial(self, state: FrameState, res: cl.Buffer, out: cl.Buffer) -> cl.Buffer:
        s, h = self.settings, self.history
        params = L.pack(L.GI_SPATIAL_PARAMS, similar=self._similarity(), neighbours=s.gi_spatial_neighbours,
                        radius=s.gi_radius, bias_correction=self.bias_code,
                        boost_neighbours=s.gi_disocclusion_boost)
        self.kernels.launch("gi_spatial", image_size(state), gbuf=h.gbuf(h.cur), glossy=h.glossy(h.cur),
                            **self.scene.geometry, input=res, out=out, frame_params=state.frame_params,
                            params=params)
        return out

    def shade(self, state: FrameState) -> None:
        h = self.history
        params = L.pack(L.GI_SHADE_PARAMS, visible_known=int(self.settings.gi_bias_correction != "none"),
                        split_glass=int(state.plan.paths))
        self.kernels.launch("gi_shade", pixel_count(state), gbuf=h.gbuf(h.cur), glossy=h.glossy(h.cur),
                            **self.scene.geometry, res=h.gi_reservoirs(h.cur), guards=self.buffers.guards,
                            sample=self.buffers.sample, indirect=self.paths.indirect_buffer(state),
                            light_passes=self.buffers.light_passes, frame_params=state.frame_params, params=params)
