"""A scene's canonical form (restircl/scene/canonical.py) and the digest of its content that keys cached references
(eval/report/reference.py scene_digest): the same triangles listed in another order, started at other corners or
over renumbered vertices give the same form and digest; a moved vertex or a flipped winding gives another."""

from __future__ import annotations

import dataclasses

import numpy as np
from restircl import Camera, Light, Material, Mesh, Scene, translation
from restircl.eval.report.reference import scene_digest
from restircl.scene.canonical import canonical_mesh, canonical_scene, key_scene

# two triangles of a unit square at z = 0 and one standing on its edge; corner values of the UVs and normals are
# tied to the corner's position (u = x, v = y + z; the normal (0, 0, 1) on the floor, (0, -1, 0) standing) so that
# each corner's values can be written out below in the order the docstring of canonical.py gives
VERTS = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), (0, 0, 1)]
TRIS = [(0, 1, 2), (0, 2, 3), (1, 0, 4)]


def _corner_data(verts, tris):
    v = np.asarray(verts, np.float64)[np.asarray(tris)]
    uvs = np.stack([v[..., 0], v[..., 1] + v[..., 2]], axis=-1)
    standing = (v[:, :, 2].max(axis=1) > 0)[:, None]
    normals = np.where(standing[..., None], [0.0, -1.0, 0.0], [0.0, 0.0, 1.0])
    normals = np.broadcast_to(normals, v.shape).copy()
    colours = np.concatenate([v, np.ones(v.shape[:2] + (1,))], axis=-1)
    return uvs, normals, colours


def _mesh(verts, tris, mats=(0, 1, 0)) -> Mesh:
    uvs, normals, colours = _corner_data(verts, tris)
    return Mesh("m", verts, tris, np.asarray(mats), uvs=uvs, normals=normals, attributes={"Col": colours})


def _shuffled(rng) -> Mesh:
    """The mesh of VERTS/TRIS with its triangles reordered, each started at another corner (its winding kept),
    its vertices renumbered and one unused vertex added."""
    perm_v = rng.permutation(len(VERTS) + 1)
    verts = np.zeros((len(VERTS) + 1, 3))
    verts[perm_v[:-1]] = VERTS
    verts[perm_v[-1]] = (9, 9, 9)  # referenced by no triangle
    tris = perm_v[np.asarray(TRIS)]
    mats = np.array([0, 1, 0])
    order = rng.permutation(len(TRIS))
    tris, mats = tris[order], mats[order]
    tris = np.array([np.roll(t, -int(s)) for t, s in zip(tris, rng.integers(0, 3, len(tris)), strict=True)])
    return _mesh(verts, tris, mats)


def test_canonical_form_as_written_out():
    m = canonical_mesh(_mesh(VERTS, TRIS))
    # distinct corner positions, sorted by x, then y, then z
    assert m.vertices.tolist() == [[0, 0, 0], [0, 0, 1], [0, 1, 0], [1, 0, 0], [1, 1, 0]]
    # each triangle starts at its least corner (winding kept); rows sorted by their corner positions:
    # (000, 001, 100) the standing one, rotated from (100, 000, 001); (000, 100, 110); (000, 110, 010)
    assert m.triangles.tolist() == [[0, 1, 3], [0, 3, 4], [0, 4, 2]]
    assert m.material_ids.tolist() == [0, 0, 1]
    assert m.uvs.tolist() == [[[0, 0], [0, 1], [1, 0]], [[0, 0], [1, 0], [1, 1]], [[0, 0], [1, 1], [0, 1]]]
    assert m.normals[0].tolist() == [[0, -1, 0]] * 3 and m.normals[2].tolist() == [[0, 0, 1]] * 3
    assert m.attributes["Col"][1, 2].tolist() == [1, 1, 0, 1]


def test_any_order_of_the_same_triangles_gives_the_same_form():
    want = canonical_mesh(_mesh(VERTS, TRIS))
    rng = np.random.default_rng(5)
    for _ in range(6):
        got = canonical_mesh(_shuffled(rng))
        for what in ("vertices", "triangles", "material_ids", "uvs", "normals"):
            assert np.array_equal(getattr(got, what), getattr(want, what)), what
        assert np.array_equal(got.attributes["Col"], want.attributes["Col"])


def _scene(mesh: Mesh) -> Scene:
    return Scene([mesh], [Material("a", (0.5, 0.5, 0.5)), Material("b", (0.2, 0.6, 0.2))],
                 [Light("key", "point", (1, 1, 1), 50.0, translation(0.5, -1, 2))],
                 Camera(translation(0.5, 0.5, 4), 16, 12))


def test_digest_depends_on_content_only(tmp_path):
    base = scene_digest(_scene(_mesh(VERTS, TRIS)), tmp_path)
    rng = np.random.default_rng(11)
    assert all(scene_digest(_scene(_shuffled(rng)), tmp_path) == base for _ in range(4))
    # negative controls: the scene file itself differs between orders; a moved vertex, a flipped winding and
    # another material on one triangle are other content
    raw = [tmp_path / "a.npz", tmp_path / "b.npz"]
    _scene(_mesh(VERTS, TRIS)).save(raw[0])
    _scene(_shuffled(rng)).save(raw[1])
    assert raw[0].read_bytes() != raw[1].read_bytes()
    moved = [list(v) for v in VERTS]
    moved[4][2] = 1.0 + 1e-9
    flipped = [TRIS[0], TRIS[1], (0, 1, 4)]
    assert scene_digest(_scene(_mesh(moved, TRIS)), tmp_path) != base
    assert scene_digest(_scene(_mesh(VERTS, flipped)), tmp_path) != base
    assert scene_digest(_scene(_mesh(VERTS, TRIS, (0, 1, 1))), tmp_path) != base


def test_canonical_scene_renders_the_same_picture(device):
    from restircl import Renderer, Settings

    rng = np.random.default_rng(3)
    scene = _scene(_shuffled(rng))
    s = Settings(method="reference", seed=4).validate()
    a = Renderer(scene, s, device).render_still(0, 64).color[..., :3]
    b = Renderer(canonical_scene(scene), s, device).render_still(0, 64).color[..., :3]
    # the same triangles: equal up to float rounding of the hit points (the BVH is built over another order)
    assert np.abs(a - b).max() <= 1e-4 * max(float(a.max()), 1e-6) + 1e-6
    assert float(a.mean()) > 0


def test_mesh_without_triangles():
    m = canonical_mesh(Mesh("e", [(1, 2, 3)], np.zeros((0, 3), np.int64)))
    assert len(m.triangles) == 0 and m.vertices.tolist() == [[1, 2, 3]]


def test_key_form_rounds_the_normals_only():
    # normals that differ by float32 rounding (as Blender's between processes) have one key form; the canonical
    # form keeps them as they are
    m = _mesh(VERTS, TRIS)
    noisy = dataclasses.replace(m, normals=m.normals + np.array([1.2e-7, -6e-8, 0.0]), vertices=m.vertices.copy())
    a, b = key_scene(_scene(m)).meshes[0], key_scene(_scene(noisy)).meshes[0]
    assert np.array_equal(a.normals, b.normals) and np.array_equal(a.vertices, b.vertices)
    assert not np.signbit(b.normals[b.normals == 0]).any()  # -6e-8 rounds to -0, made +0 (another file else)
    assert not np.array_equal(canonical_scene(_scene(m)).meshes[0].normals,
                              canonical_scene(_scene(noisy)).meshes[0].normals)
    # a turn of the normals by 3 degrees is another key
    turned = dataclasses.replace(m, normals=m.normals + np.array([0.05, 0.0, 0.0]))
    assert not np.array_equal(key_scene(_scene(turned)).meshes[0].normals, a.normals)
