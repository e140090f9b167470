"""model.vectors: the cross product the agents, strokes and outputs share."""
import numpy as np

from blobtree_ink.model.vectors import cross


def test_cross_is_numpys_to_the_bit_broadcast_alike():
    rng = np.random.default_rng(5)
    shapes = [((5, 3), (5, 3)), ((3,), (3,)), ((7, 3), (3,)), ((3,), (7, 3)), ((4, 2, 3), (2, 3)), ((0, 3), (0, 3))]
    for sa, sb in shapes:
        a, b = rng.normal(size=sa) * 10.0 ** rng.integers(-8, 8, size=sa), rng.normal(size=sb)
        got, want = cross(a, b), np.cross(a, b)
        assert got.shape == want.shape and got.dtype == np.float64
        assert np.array_equal(got, want)
    assert np.array_equal(cross([1, 0, 0], [0, 1, 0]), [0.0, 0.0, 1.0])      # lists and ints: float64
