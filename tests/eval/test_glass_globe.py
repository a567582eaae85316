"""The light-inside-a-globe kinds of restircl compare (eval/scenes/glass_globe.py)."""

import numpy as np
from restircl.eval.scenes import kinds as K
from restircl.eval.scenes.glass_globe import GLOBE_AT, GLOBE_R


def test_the_bulb_sits_inside_its_globe_and_only_the_unshadowed_kind_links_it():
    for kind in ("globe_frosted", "globe_clear", "globe_frosted_unshadowed"):
        scene = K.scene_of_kind(kind, 32, 24)
        assert scene.name == f"glass_{kind}"
        (bulb,) = scene.lights
        at = np.asarray(bulb.transforms).reshape(-1, 4, 4)[0, :3, 3]
        assert np.linalg.norm(at - np.array(GLOBE_AT)) + bulb.radius < GLOBE_R
        globe = next(m for m in scene.meshes if m.name == "globe")
        glass = scene.materials[int(np.ravel(globe.material_ids)[0])]
        assert glass.kind == "glass" and (glass.roughness == 0.0) == (kind == "globe_clear")
        assert bulb.linking.blockers == ({"globe": "EXCLUDE"} if kind == "globe_frosted_unshadowed" else {})
