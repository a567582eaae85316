"""The motion rows of a deforming mesh (upload/deform_motion.py): the affine map that carries its world-space
vertices at one time to another's, exact for an affine deformation (written out by hand below), the least-squares
fit for one that is not, identity where nothing moves."""

import numpy as np
import pytest
from restircl import Mesh, translation
from restircl.upload.deform_motion import deform_motion

QUAD = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]])
TRIS = [[0, 1, 2], [0, 2, 3]]


def apply(rows: np.ndarray, p: np.ndarray) -> np.ndarray:
    return p @ rows[:, :3].T + rows[:, 3]


def sliding(moved: np.ndarray, transforms=None) -> Mesh:
    """The quad as QUAD at time 0 and `moved` at time 1 (linear between)."""
    return Mesh("q", QUAD, TRIS, 0, deform=np.stack([QUAD, moved]), deform_times=[0.0, 1.0],
                **({} if transforms is None else {"transforms": transforms}))


def test_a_slide_and_stretch_is_carried_exactly():
    """x doubled about 0 and the quad slid 0.5 in y and 2 in z over one frame: at time 0.5, x is 1.5 x0 and the
    offset (0, 0.25, 1); at 1, 2 x0 and (0, 0.5, 2). A point inside the quad at 0.5 (0.75, 0.5 + 0.25, 1) goes to
    (1.0, 1.0, 2) at time 1 and back to (0.5, 0.5, 0) at time 0."""
    moved = QUAD * [2.0, 1.0, 1.0] + [0.0, 0.5, 2.0]
    mesh = sliding(moved)
    p = np.array([[0.75, 0.75, 1.0]])
    np.testing.assert_allclose(apply(deform_motion(mesh, 0.5, 1.0), p), [[1.0, 1.0, 2.0]], atol=1e-12)
    np.testing.assert_allclose(apply(deform_motion(mesh, 0.5, 0.0), p), [[0.5, 0.5, 0.0]], atol=1e-12)


def test_the_transform_moves_the_deformed_vertices():
    """The quad slid 1 in x by its deformation over a frame, its transform 3 in z: world motion (1, 0, 3)."""
    mesh = sliding(QUAD + [1.0, 0.0, 0.0], transforms=np.stack([np.eye(4), translation(0.0, 0.0, 3.0)]))
    p = np.array([[0.2, 0.4, 0.0]])
    np.testing.assert_allclose(apply(deform_motion(mesh, 0.0, 1.0), p), [[1.2, 0.4, 3.0]], atol=1e-12)


def test_a_non_affine_deformation_gets_its_least_squares_fit():
    """One corner (1, 1) raised by 1 in z: the best affine fit of the four corners raises z by (x + y) / 2 - 1/4
    (the plane nearest to heights 0, 0, 1, 0 at the corners), so the corners move by -1/4, 1/4, 3/4, 1/4."""
    moved = QUAD.copy()
    moved[2, 2] = 1.0
    rows = deform_motion(sliding(moved), 0.0, 1.0)
    np.testing.assert_allclose(apply(rows, QUAD)[:, 2], [-0.25, 0.25, 0.75, 0.25], atol=1e-12)
    np.testing.assert_allclose(apply(rows, QUAD)[:, :2], QUAD[:, :2], atol=1e-12)


@pytest.mark.parametrize(("a", "b"), [(0.5, 0.5), (2.0, 3.0)])
def test_no_motion_is_the_identity(a, b):
    """The same time, or two times after the last step (held there)."""
    np.testing.assert_array_equal(deform_motion(sliding(QUAD + 1.0), a, b), np.eye(4)[:3])
