"""Negative controls of the unbiasedness tests: the kernels built with a test hook that makes an estimator biased
on purpose (`#ifdef` blocks in opencl/, compiled out of every ordinary build, so the images stay bit-identical).
A statistical test that passes the biased build has no power to see that bias; each harness pairs its checks with
a test that asserts it rejects one of these builds.

- TEST_PICK_PDF_SCALE=s: every light sample's source pdf times s (direct/ris.h, direct/direct.cl): a wrong pdf;
  the direct light comes out 1/s times too bright (with BSDF candidates or a BSDF MIS sample, a little less).
- TEST_WITHOUT_MIXTURE_PDF: light candidates keep their own pdf beside BSDF candidates instead of the mixture
  density (direct/ris.h): a dropped MIS weight, where both strategies reach a light it is counted twice.
- TEST_WITHOUT_MIS_WEIGHT: the light sample's MIS weight against the BSDF MIS sample is 1 (direct/bsdf_mis.h).
- TEST_REFERENCE_PDF_SCALE=s: the exhaustive `reference` method's light pdf times s (direct/direct.cl), for the
  check of the renderer against the independent numpy path tracer (render/test_path_reference.py).
- PATH_ROULETTE_WITHOUT_DIVIDE, GI_WITHOUT_JACOBIAN: the path pass and ReSTIR GI (render/test_paths.py,
  render/test_restir_gi.py).
- DIELECTRIC_WITHOUT_FRESNEL_IN_REFRACTION: glass refracts all that reaches it besides what it reflects
  (bsdf/microfacet_dielectric.h): energy made at every crossing (render/test_glass.py, the white furnace).
- LIGHT_TREE_ONE_SIDED: the light tree ranks lights at a transmitting surface by the incidence bound of its normal
  alone (lights/tree.h): no bias (the power floor keeps every light), the noise of lights behind rough glass
  (lights/test_tree_glass.py).
- TEST_DESCENT_WITHOUT_REMAP: the light tree's stratified descent compares the same uniform at every level
  instead of remapping it (lights/tree.h): the leaves are reached with other probabilities than the pdf says
  (render/test_path_descent.py, the path pass's NEE from the tree with the Sobol sampler).
- TEST_DIELECTRIC_REFLECT_PDF_SCALE=s: the dielectric lobe's reflection pdf times s, its sampling unchanged
  (bsdf/microfacet_dielectric.h; materials/test_dielectric_branch.py).
- TEST_PATH_LINKED_NEE_ONLY (the reference: the path's BSDF rays leave lights with linked shadows to NEE) and
  TEST_PATH_LINKED_NEE_WEIGHT_ONE (NEE weight 1 beside the BSDF rays' weights: counted twice), path/mis.h, path/nee.h
  (render/test_path_linked_lights.py).
- GLASS_KEEPS_HISTORY: TAA keeps a glass pixel's history (surface/view_dependence.h leaves dielectric lobes out), the
  rule before 2026-12-05 (render/test_taa_glass.py).
- TEST_OPAQUE_SHADOWS: shadow rays stop at transparent and alpha-masked surfaces as at opaque ones
  (bvh/transparent.h; render/test_transparency.py, blender/test_alpha_cycles.py).
- TEST_THIN_WALL_COUNTED_TWICE: a path going on through a smooth thin wall counts the emitters its ray meets, which
  the vertex before it counted through the wall already (path/walk.h; render/test_thin_wall_furnace.py).
- TEST_THIN_TRANSMISSION_PDF_SCALE=s: the thin dielectric lobe's transmission pdf times s, its sampling unchanged
  (bsdf/thin_dielectric.h): a rough thin wall passes too much light (render/test_thin_wall_furnace.py).
- TEST_SHADOW_ALLOWANCE_WHOLE: every shadow ray may pass Transparent Max Bounces surfaces, whatever the camera ray
  passed (direct/visibility.h shadow_allowance; blender/test_shadow_allowance_cycles.py).
- TEST_DISTANT_PICK_FIXED_PDF: light_pick_pdf gives the distant lights and the tree their fixed shares of the light
  array while the pick takes them by importance at the point (lights/tree.h, lights/distant_pick.h): the MIS weights'
  pdf is not the pick's (lights/test_distant_pick.py).
- TEST_TREE_EXACT_BRANCH_PDF: light_pick_pdf follows the light tree's branches all the way down to the leaf while the
  pick takes a light below a node of few lights by its own importance (lights/tree.h, lights/tree_exact.h): the MIS
  weights' pdf is not the pick's (lights/test_tree_exact.py). Not a bias but a test hook beside it:
  TEST_LIGHT_TREE_EXACT=k builds the tree's exact pick for nodes of at most k lights instead of LIGHT_TREE_EXACT (1:
  every pick branches down to its leaf), so that a small scene still has branches (render/test_path_descent.py).
- TEST_LAYER_WEIGHT_WHOLE: a still's weighted layers shade a partly transparent surface whole instead of by its
  coverage (camera/layers.h; render/test_camera_layers.py).
- TEST_LONELY_FRESH_M_KEPT: a lonely fresh pixel's extra candidates (restir/lonely_fresh.h) are merged but its M
  stays its own candidates' count: the merged W too large by (M_c + M_e) / M_c (render/test_restir.py).
- TEST_BIASED_PLAIN_M: ReSTIR DI's biased merge normalised by the M of every input, those whose target cannot hold the
  chosen sample included (restir/reuse.h): darker where the targets' supports differ (render/test_restir_biased.py)."""

from __future__ import annotations

import pytest
from restircl.eval.probe_defines import add_probe_defines

# A pdf 2 % too small: the direct light 2.04 % too bright, the size of the biased ReSTIR mode's darkening
# (render/test_restir.py) that the quick sizes must be able to see.
PDF_SCALE = 0.98


def built_with(monkeypatch: pytest.MonkeyPatch, *defines: str) -> None:
    """Every program built after this call, in this test, has `defines` (NAME or NAME=VALUE) added."""
    add_probe_defines(defines, monkeypatch.setattr)


def wrong_pdf(monkeypatch: pytest.MonkeyPatch, scale: float = PDF_SCALE) -> None:
    built_with(monkeypatch, f"TEST_PICK_PDF_SCALE={scale!r}f")
