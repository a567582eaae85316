"""Frame policy (render/plan.py): plan_frame's decisions for representative situations, against the values each case
should give, written out here. No device: plan_frame is pure."""

from __future__ import annotations

from dataclasses import replace

import pytest
from restircl.render.plan import FramePlan, FrameSituation, plan_frame
from restircl.settings.table import BSDF_ANALYTIC_MAX, LIGHT_TILES_AUTO, Settings

#: an animation frame that follows the last one, whose history is valid, over four light objects
NEXT = FrameSituation(frame=3, last_frame=2, frame_count=10, history_valid=True, light_count=4)


def plan(situation: FrameSituation = NEXT, **settings) -> FramePlan:
    return plan_frame(Settings(**settings).validate(), situation)


def test_restir_animation_frame_runs_every_reuse_stage():
    p = plan(method="restir", boiling_filter=0.2)
    assert (p.frame, p.prev_frame, p.next_frame) == (3, 2, 4)
    assert p.method == "restir" and p.history and p.restir_history and not p.drop_history
    assert p.temporal and p.boiling and p.spatial and p.taa and not p.filter
    assert not (p.light_tree or p.tiles or p.pick_table)


def test_reuse_settings_switch_their_stages_off():
    assert not plan(method="restir", temporal=False).temporal
    assert not plan(method="restir", spatial=False).spatial
    assert not plan(method="restir", spatial_neighbours=0).spatial
    assert not plan(method="restir").boiling  # boiling_filter 0: off
    p = plan(method="restir", taa=False, realtime_filter=True)
    assert not p.taa and not p.filter  # the filter filters TAA's output
    assert plan(method="restir", realtime_filter=True).filter


@pytest.mark.parametrize("method", ["uniform", "light_array", "ris", "reference"])
def test_methods_without_reuse_run_no_restir_stage(method):
    p = plan(method=method, boiling_filter=0.5)
    assert p.method == method
    assert not (p.temporal or p.boiling or p.spatial)
    assert p.taa and p.history  # TAA still blends with last frame's colour


def test_still_frames_have_no_taa_and_no_boiling_filter():
    still = replace(NEXT, still=True)
    p = plan(still, method="restir", boiling_filter=0.2, realtime_filter=True)
    assert p.temporal and p.spatial  # ReSTIR's reuse runs in a still render's frames too
    assert not (p.boiling or p.taa or p.filter or p.taa_moving)
    a = plan(method="restir", boiling_filter=0.2, realtime_filter=True)
    assert a.boiling and a.taa and a.filter


@pytest.mark.parametrize("method", ["restir", "ris", "reference"])
def test_stills_read_textures_at_full_resolution_and_frames_at_their_mip_level(method):
    still = replace(NEXT, still=True)
    assert plan(still, method=method).texture_full  # auto
    assert not plan(method=method).texture_full
    assert plan(still, method=method, texture_filter="full").texture_full
    assert plan(method=method, texture_filter="full").texture_full
    assert not plan(still, method=method, texture_filter="mip").texture_full
    assert not plan(method=method, texture_filter="mip").texture_full


def test_one_light_runs_the_light_array_sampler_unless_sobol_or_environment():
    one = replace(NEXT, light_count=1)
    assert plan(one, method="ris").method == "light_array"
    assert plan(replace(one, sobol=True), method="ris").method == "ris"
    # the environment alone: one light whose candidates are directions
    assert plan(replace(one, environment=True), method="ris").method == "ris"
    assert plan(one, method="restir").method == "restir"  # only RIS is reduced
    assert plan(NEXT, method="ris").method == "ris"  # four lights


def test_many_lights_draw_from_tiles_under_auto():
    for count, used in ((4, False), (LIGHT_TILES_AUTO - 1, False), (LIGHT_TILES_AUTO, True), (10**6, True)):
        x = replace(NEXT, light_count=count)
        assert plan(x, method="ris").tiles == used, count
        assert plan(x, method="restir").tiles == used, count
        assert not plan(x, method="light_array").tiles
        assert not plan(x, method="restir", light_tiles="off").tiles
    assert plan(replace(NEXT, light_count=2), method="restir", light_tiles="on").tiles
    assert not plan(replace(NEXT, light_count=1), method="restir", light_tiles="on").tiles  # nothing to presample


def test_the_light_tree_takes_precedence_over_tiles():
    many = replace(NEXT, light_count=LIGHT_TILES_AUTO, light_tree=True)
    p = plan(many, method="restir", light_tiles="on")
    assert p.light_tree and not p.tiles and not p.pick_table
    one = replace(NEXT, light_count=1, light_tree=True)
    assert not plan(one, method="restir").light_tree  # a tree over one light picks it
    assert not plan(one, method="ris").light_tree  # (and RIS over one light runs light_array)


def test_pick_table_only_for_still_ris_frames_of_a_few_lights():
    still = replace(NEXT, still=True, pick_table=True)
    assert plan(still, method="ris").pick_table
    assert plan(still, method="ris", light_proposal="pixel").pick_table
    assert not plan(still, method="ris", light_proposal="array").pick_table
    assert plan(replace(still, light_count=64), method="ris").pick_table
    assert not plan(replace(still, light_count=65), method="ris").pick_table  # more than 64 lights
    assert not plan(replace(still, light_count=1), method="ris").pick_table
    assert not plan(still, method="restir").pick_table
    assert not plan(replace(still, pick_table=False), method="ris").pick_table  # not compiled in / not a still
    p = plan(still, method="ris", light_tiles="on")
    assert p.tiles and not p.pick_table
    assert not plan(replace(still, light_tree=True), method="ris").pick_table


def test_camera_cut_resets_history_but_not_when_the_cut_frame_is_rendered_again():
    cut = replace(NEXT, cut_at_frame=True)
    p = plan(cut, method="restir")
    assert not p.history and not p.restir_history and not p.temporal and p.prev_frame == 3
    again = replace(cut, last_frame=3)  # the cut frame once more (a still camera's accumulation)
    p = plan(again, method="restir")
    assert p.history and p.temporal and p.prev_frame == 3


def test_history_only_across_consecutive_frames():
    for last, frame, kept in ((2, 3, True), (3, 3, True), (1, 3, False), (4, 3, False), (None, 0, False)):
        p = plan(replace(NEXT, frame=frame, last_frame=last), method="restir")
        assert p.history == kept and p.temporal == kept, (last, frame)
        assert p.prev_frame == (last if kept else frame)
    assert not plan(replace(NEXT, history_valid=False), method="restir").history  # after reset()
    assert plan(replace(NEXT, frame=9, last_frame=8)).next_frame == 9  # the last frame of the animation


def test_lights_switched_keep_taa_history_but_not_reservoirs():
    p = plan(replace(NEXT, lights_switched=True), method="restir")
    assert p.history and p.taa and p.prev_frame == 2
    assert not p.restir_history and not p.temporal and not p.drop_history
    p = plan(replace(NEXT, lights_reindexed=True), method="restir")  # the light count changed
    assert p.drop_history and not p.history and not p.restir_history and p.prev_frame == 3


def test_bsdf_candidates_under_auto_only_with_glossy_materials():
    glossy = replace(NEXT, glossy=True)
    assert plan(NEXT, method="ris").bsdf_candidates == 0
    assert plan(glossy, method="ris", bsdf_candidates=2).bsdf_candidates == 2
    assert plan(glossy, method="restir").bsdf_candidates == 1
    assert plan(NEXT, method="ris", bsdf_sampling="on", bsdf_candidates=3).bsdf_candidates == 3
    assert plan(glossy, method="ris", bsdf_sampling="off").bsdf_candidates == 0
    assert plan(glossy, method="light_array").bsdf_candidates == 0
    assert plan(replace(glossy, light_count=0), method="ris").bsdf_candidates == 0
    assert plan(NEXT, method="ris", bsdf_sampling="auto").bsdf_glossy_only
    assert not plan(NEXT, method="ris", bsdf_sampling="on").bsdf_glossy_only


def test_bsdf_mis_sample_replaces_the_bsdf_candidates():
    p = plan(NEXT, method="ris", bsdf_sampling="on", bsdf_mis_sample=True)
    assert p.mis_sample and p.bsdf_candidates == 0
    p = plan(NEXT, method="restir", bsdf_sampling="on", bsdf_mis_sample=True)  # ReSTIR keeps its candidates
    assert not p.mis_sample and p.bsdf_candidates == 1
    # one light object, random numbers: light_array runs, which has no MIS sample
    assert not plan(replace(NEXT, light_count=1), method="ris", bsdf_mis_sample=True).mis_sample
    assert plan(replace(NEXT, light_count=1, sobol=True), method="ris", bsdf_mis_sample=True).mis_sample


def test_what_bsdf_rays_look_for():
    lights = replace(NEXT, analytic_lights=3, triangle_lights=True)
    p = plan(lights, method="ris", bsdf_sampling="on")
    assert p.bsdf_analytic == 3 and p.bsdf_triangles
    p = plan(lights, method="ris", bsdf_sampling="off", bsdf_mis_sample=True)  # the MIS sample's rays
    assert p.bsdf_analytic == 3 and p.bsdf_triangles
    p = plan(lights, method="ris", bsdf_sampling="off")  # no BSDF rays: nothing to look for
    assert p.bsdf_analytic == 0 and not p.bsdf_triangles
    too_many = replace(lights, analytic_lights=BSDF_ANALYTIC_MAX + 1)
    assert plan(too_many, method="ris", bsdf_sampling="on").bsdf_analytic == 0
    at_max = replace(lights, analytic_lights=BSDF_ANALYTIC_MAX)
    assert plan(at_max, method="ris", bsdf_sampling="on").bsdf_analytic == BSDF_ANALYTIC_MAX


def test_taa_clips_its_history_only_where_something_moved():
    assert not plan(NEXT).taa_moving  # a still camera's animation
    assert plan(replace(NEXT, camera_moved=True)).taa_moving
    assert plan(replace(NEXT, scene_moves=True)).taa_moving
    # without history (a cut) the camera's motion means nothing to TAA; moving objects still do
    assert not plan(replace(NEXT, camera_moved=True, cut_at_frame=True)).taa_moving
    assert plan(replace(NEXT, scene_moves=True, cut_at_frame=True)).taa_moving


def test_bounces_run_restir_gi_in_animation_frames_and_the_path_pass_in_stills():
    gi_next = replace(NEXT, gi_history_valid=True)
    none = plan(gi_next, max_bounces=0)
    assert not (none.paths or none.gi or none.gi_temporal or none.gi_spatial)
    p = plan(gi_next, max_bounces=2)
    assert p.gi and p.gi_temporal and p.gi_spatial and not p.paths
    still = plan(replace(gi_next, still=True), max_bounces=2)
    assert still.paths and not (still.gi or still.gi_temporal or still.gi_spatial)
    off = plan(gi_next, max_bounces=2, gi_reuse=False)
    assert off.paths and not (off.gi or off.gi_temporal or off.gi_spatial)
    # ReSTIR GI does not depend on the direct light's method
    for method in ("ris", "light_array", "restir"):
        q = plan(gi_next, max_bounces=2, method=method)
        assert q.gi and q.gi_temporal and not q.paths, method


def test_scenes_with_glass_run_the_path_pass_beside_restir_gi_in_animation_frames():
    """ReSTIR GI does not reuse paths refracted at the visible point: a scene that refracts runs the path pass too,
    for the pixels that transmit (render/test_restir_gi_glass.py), and ReSTIR GI for the rest."""
    glass = plan(replace(NEXT, gi_history_valid=True, transmission=True), max_bounces=2)
    assert glass.paths and glass.gi and glass.gi_temporal and glass.gi_spatial
    still = plan(replace(NEXT, still=True, transmission=True), max_bounces=2)
    assert still.paths and not still.gi


def test_restir_gi_reuses_its_history_where_restir_may():
    gi_next = replace(NEXT, gi_history_valid=True)
    assert plan(gi_next, max_bounces=1).gi_temporal
    for case in (replace(gi_next, cut_at_frame=True), replace(gi_next, lights_switched=True),
                 replace(gi_next, lights_reindexed=True), replace(gi_next, last_frame=1),
                 replace(gi_next, history_valid=False), replace(gi_next, gi_history_valid=False),
                 replace(gi_next, last_frame=None)):
        p = plan(case, max_bounces=1)
        assert p.gi and p.gi_spatial and not p.gi_temporal, case  # the frame starts over, with its neighbours
    assert not plan(gi_next, max_bounces=1, gi_temporal=False).gi_temporal
    assert not plan(gi_next, max_bounces=1, gi_spatial_neighbours=0).gi_spatial
    # ReSTIR GI's boiling filter: its own strength, biased, so never in a still (whose frames run the path pass)
    assert not plan(gi_next, max_bounces=1, boiling_filter=0.5).gi_boiling
    assert plan(gi_next, max_bounces=1, gi_boiling_filter=0.5).gi_boiling
    assert not plan(replace(gi_next, still=True), max_bounces=1, gi_boiling_filter=0.5).gi_boiling
    # the same frame again (a still camera's animation or an unchanged viewport) keeps it
    assert plan(replace(gi_next, frame=2), max_bounces=1).gi_temporal


def test_path_vertices_pick_from_the_tree_the_renderer_built_for_them():
    """NEE at path vertices takes the tree where the renderer built it for them (FrameSituation.path_light_tree) and
    there are two lights or more; the direct light's candidates keep their own source (the per-pixel table of a
    still RIS frame stays)."""
    still = replace(NEXT, still=True, pick_table=True)
    p = plan(replace(still, path_light_tree=True), method="ris", max_bounces=2)
    assert p.paths and p.path_light_tree
    assert not p.light_tree and p.pick_table
    assert not plan(replace(still, path_light_tree=False), method="ris", max_bounces=2).path_light_tree
    assert not plan(replace(still, path_light_tree=True, light_count=1), method="ris", max_bounces=2).path_light_tree
    # the candidates' tree alone does not make the path pick from it: the renderer says so by path_light_tree
    assert not plan(replace(still, light_tree=True), method="ris", max_bounces=2).path_light_tree
