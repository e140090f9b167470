"""The hatching map's measured spread (strokes.hatch_map.spread): how far apart its lines
really stand about each point, per set of levels, which the hatching's widths answer so
that crowded lines thin and lonely ones widen."""
import numpy as np

from blobtree_ink.strokes import hatch_map as HM


def flat_map(offsets, levels, spacing=1.0, step=0.1, length=4.0):
    """Straight lines along x on the plane z = 0 (normals +z), at y = ``offsets``, of the
    given ``levels``."""
    x = np.arange(0.0, length + 1e-9, step)
    P = np.concatenate([np.c_[x, np.full(len(x), y), np.zeros(len(x))] for y in offsets])
    n = len(offsets)
    return HM.HatchMap(P, np.tile([0.0, 0.0, 1.0], (len(P), 1)), np.repeat(np.arange(n), len(x)),
                       np.asarray(levels, np.int64), np.arange(n, dtype=np.uint64), np.arange(n) * len(x), spacing,
                       max(levels) + 1)


def test_spread_is_the_mean_gap_to_the_nearest_line_on_either_side_over_the_spacing():
    hmap = flat_map([0.0, 1.0, 1.5], [0, 0, 0])
    mid = np.arange(len(hmap.points)) % 41 == 20
    got = hmap.spread[mid, 0]
    reach = HM.SPREAD_REACH                   # a side with no line counts as that many spacings
    assert np.allclose(got, [(reach + 1.0) / 2, (1.0 + 0.5) / 2, (0.5 + reach) / 2])


def test_each_set_of_levels_counts_its_own_lines():
    """Level 1's line halves the gaps of the set 0..1, not of level 0's set; a level 1
    point has no spread in level 0's set (it is not drawn there: 1)."""
    hmap = flat_map([0.0, 0.5, 1.0], [0, 1, 0])
    mid = np.arange(len(hmap.points)) % 41 == 20
    assert np.allclose(hmap.spread[mid, 0], [(HM.SPREAD_REACH + 1.0) / 2, 1.0, (1.0 + HM.SPREAD_REACH) / 2])
    # set 0..1 spacing 0.5: the middle line stands 0.5 from either neighbour
    assert np.allclose(hmap.spread[mid, 1], [(HM.SPREAD_REACH + 1.0) / 2, 1.0, (1.0 + HM.SPREAD_REACH) / 2])


def test_lines_on_another_sheet_do_not_count():
    """A line under another (its normal opposite: the far wall of a thin part) is no
    neighbour."""
    hmap = flat_map([0.0, 1.0], [0, 0])
    hmap.normals[len(hmap.points) // 2:] *= -1.0
    hmap = HM.HatchMap(hmap.points, hmap.normals, hmap.line, hmap.level, hmap.key, hmap.start, 1.0, 1)
    assert np.allclose(hmap.spread[:, 0], HM.SPREAD_REACH)
