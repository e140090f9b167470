"""The blackboard's voxels (blackboard.board): neighbour rows kept as voxels come, and
theta_i, the largest angle between a surface voxel's corner gradients."""
import math

import numpy as np
import pytest

from blobtree_ink import model as M
from blobtree_ink.blackboard.board import Blackboard
from blobtree_ink.blackboard.polygonise import Grid

from test_massris import model_of


def test_voxel_neighbours_stay_those_of_the_hash_as_voxels_are_added():
    """The blackboard keeps each voxel's 27 neighbour rows as voxels come (agents add
    voxels the polygonisation missed): after batches in any order, including voxels
    beside earlier ones and duplicates, inside the grid's box and outside it, they are
    exactly what looking up the hash gives."""
    from blobtree_ink.blackboard.cells import _NEIGHBOURS, pack
    grid = Grid(lo=np.zeros(3), cell=np.ones(3), res=(6, 6, 6), field=np.zeros((7, 7, 7)))
    bb = Blackboard(grid, 0.5)
    rng = np.random.default_rng(5)
    for size in (200, 1, 150, 300, 3):
        bb.voxel_rows(rng.integers(-5, 11, (size, 3)))
        rows = np.arange(bb.vox.n)
        want = bb.index.lookup(pack(bb.vox["ijk"][rows][:, None, :] + _NEIGHBOURS[None]))
        np.testing.assert_array_equal(bb.neighbours(rows), want)
    assert (want >= 0).sum() > 2 * bb.vox.n             # voxels do have neighbours


def test_a_voxels_theta_is_the_largest_angle_between_its_corner_gradients():
    """theta_i of the manager: the largest angle between the gradients at a surface
    voxel's eight corners, a corner without a gradient (a box's flat core) counting
    as no angle; against every pair computed one by one."""
    from blobtree_ink.blackboard.board import from_mesh
    from blobtree_ink.blackboard.polygonise import polygonise
    from blobtree_ink.model.curvature import curvature
    box = {"type": "box", "center": [0, 0, 0], "half_size": [0.6, 0.4, 0.5], "radius": 0.3}
    bite = {"type": "point", "center": [0.6, 0.4, 0.5], "radius": 0.6, "strength": 2.0}
    ev = M.Evaluator(model_of({"type": "difference", "children": [box, bite]}))
    bb, _ = from_mesh(polygonise(ev, 8), ev, lambda P, g: curvature(ev, P, g))
    C = bb.corner_pos
    _, g = ev.field_grad(C.reshape(-1, 3))
    g = g.reshape(-1, 8, 3)
    want = np.zeros(len(C))
    for v in range(len(C)):
        for i in range(8):
            for j in range(i + 1, 8):
                ni, nj = np.linalg.norm(g[v, i]), np.linalg.norm(g[v, j])
                if ni > 0 and nj > 0:
                    c = np.clip(g[v, i] @ g[v, j] / (ni * nj), -1, 1)
                    want[v] = max(want[v], math.acos(c))
    got = bb.vox["theta"][bb.surface_rows]
    np.testing.assert_allclose(got, want, rtol=0, atol=1e-12)
    flat = ~(np.linalg.norm(g, axis=2) > 0)
    assert flat.any(axis=1).sum() > 10 and (flat.any(axis=1) & (got > 0.3)).any()
    assert (got > math.radians(35)).sum() > 10 and (got < 0.1).sum() > 10


def test_unique_rows_is_numpys_row_unique():
    """unique_rows (one int64 key per row) gives np.unique(axis=0)'s rows, first
    indices and inverse exactly: negative and wide values, one to four columns,
    unsigned ints, no rows; rows too wide for one key fall back to numpy's row sort."""
    from blobtree_ink.blackboard.keys import unique_rows
    rng = np.random.default_rng(3)
    cases = [rng.integers(-7, 9, (500, 3)), rng.integers(-10**6, 10**6, (300, 2)),
             rng.integers(0, 4, (50, 1)), rng.integers(0, 3, (200, 4)).astype(np.uint8),
             np.zeros((0, 3), np.int64), np.array([[-2**62, 2**62 - 1], [0, 1], [-2**62, 2**62 - 1]])]
    for a in cases:
        u, first, inv = unique_rows(a, return_index=True, return_inverse=True)
        nu, nfirst, ninv = np.unique(a, axis=0, return_index=True, return_inverse=True)
        assert u.dtype == a.dtype and np.array_equal(u, nu)
        assert np.array_equal(first, nfirst) and np.array_equal(inv, ninv.ravel())
        assert np.array_equal(u[inv], a) and np.array_equal(a[first], u)
        assert np.array_equal(unique_rows(a), nu)
    with pytest.raises(ValueError, match="integer array"):
        unique_rows(np.zeros((3, 2)))
