"""Stitching traced fragments into whole outlines: ends that point at each other across
a gap wider than the chaining's link are joined, and a free end reaches the middle of
another outline it points at; ends that do not point at each other, or lie on other
sheets, stay apart."""
import numpy as np

from blobtree_ink.agents.outline import Outline
from blobtree_ink.agents.stitch import AHEAD, REACH, stitch

STEP = 0.1
LINK = 2.5 * STEP
UP = np.array([0.0, 0.0, 1.0])


def piece(points, normal=UP):
    P = np.asarray(points, float)
    return Outline("silhouette", P, np.tile(normal, (len(P), 1)), False, STEP)


def line(x0, x1, y=0.0):
    """Points every STEP along x from x0 to x1 (either way) at height y."""
    n = int(round(abs(x1 - x0) / STEP)) + 1
    return np.stack([np.linspace(x0, x1, n), np.full(n, y), np.zeros(n)], axis=1)


def stitched(*pieces):
    return stitch(list(pieces), LINK, lambda kind, P, N, closed: Outline(kind, P, N, closed, STEP))


def test_ends_pointing_at_each_other_across_a_wide_gap_are_joined():
    gap = 3.5 * STEP                                     # wider than a link, within REACH links
    assert LINK < gap < REACH * LINK
    out = stitched(piece(line(0.0, 1.0)), piece(line(1.0 + gap + 1.0, 1.0 + gap)))     # the second runs back
    assert len(out) == 1 and not out[0].closed
    x = out[0].points[:, 0]
    assert len(x) == 22 and (np.all(np.diff(x) > 0) or np.all(np.diff(x) < 0))


def test_pieces_joined_round_are_closed():
    """A circle in four arcs, each stopped short of the next by more than a link: one
    closed outline."""
    R, gap = 2.0, 3.5 * STEP
    arcs = []
    for k in range(4):
        t0, t1 = k * np.pi / 2, (k + 1) * np.pi / 2 - gap / R
        t = np.linspace(t0, t1, int(round((t1 - t0) * R / STEP)) + 1)
        arcs.append(np.stack([R * np.cos(t), R * np.sin(t), 0 * t], axis=1))
    out = stitched(*[piece(p) for p in arcs])
    assert len(out) == 1 and out[0].closed and len(out[0].points) == sum(len(p) for p in arcs)


def test_ends_that_do_not_point_at_each_other_stay_apart():
    """Parallel lines side by side, a line ending beside another's end at a right
    angle, and a gap beyond REACH links are not joined."""
    side = stitched(piece(line(0.0, 1.0)), piece(line(1.3, 2.3, y=0.3)))
    assert len(side) == 2
    far = stitched(piece(line(0.0, 1.0)), piece(line(1.0 + 1.2 * REACH * LINK, 3.0)))
    assert len(far) == 2
    across = np.stack([np.full(11, 1.3), np.linspace(0.35, 1.35, 11), np.zeros(11)], axis=1)
    bent = stitched(piece(line(0.0, 1.0)), piece(across))
    assert len(bent) == 2 and {len(o.points) for o in bent} == {11}


def test_ends_on_two_sheets_stay_apart():
    tilted = np.array([0.0, np.sin(0.5), np.cos(0.5)])          # normals 29 degrees apart: a crease's sides
    out = stitched(piece(line(0.0, 1.0)), piece(line(1.35, 2.35), tilted))
    assert len(out) == 2


def test_a_free_end_reaches_the_middle_of_an_outline_it_points_at():
    """A trace stopped short of another outline's middle (a junction, a cusp) ends on it;
    one that passes beside it at an angle further than AHEAD does not."""
    main = piece(line(0.0, 2.0))
    towards = np.stack([np.full(8, 1.0), np.linspace(1.0, 0.3, 8), np.zeros(8)], axis=1)      # stops 0.3 short
    out = stitched(main, piece(towards))
    branch = [o for o in out if len(o.points) != 21]
    assert len(out) == 2 and len(branch) == 1 and len(branch[0].points) == 9
    assert np.allclose(branch[0].points[-1], [1.0, 0.0, 0.0])
    beyond = towards + np.array([1.25, 0.0, 0.0])           # points down past the line's end
    off = np.array([2.0, 0.0, 0.0]) - beyond[-1]
    assert np.linalg.norm(off) < REACH * LINK and np.array([0.0, -1.0, 0.0]) @ off / np.linalg.norm(off) < AHEAD
    assert sorted(len(o.points) for o in stitched(main, piece(beyond))) == [8, 21]


def test_a_loop_whose_own_ends_stop_short_closes():
    R, gap = 2.0, 3.5 * STEP
    t = np.linspace(0.0, 2 * np.pi - gap / R, int(round((2 * np.pi * R - gap) / STEP)) + 1)
    out = stitched(piece(np.stack([R * np.cos(t), R * np.sin(t), 0 * t], axis=1)))
    assert len(out) == 1 and out[0].closed and len(out[0].points) == len(t)


def rim(R, t0, t1, step):
    """An arc of a circle of radius R from angle t0 to t1, points about ``step`` apart,
    with normals tilted 20 degrees off the circle's plane (the rim's sheet)."""
    t = np.linspace(t0, t1, int(round(abs(t1 - t0) * R / step)) + 1)
    P = np.stack([R * np.cos(t), R * np.sin(t), 0 * t], axis=1)
    tilt = np.radians(20.0)
    N = np.stack([np.sin(tilt) * np.cos(t), np.sin(tilt) * np.sin(t), np.full_like(t, np.cos(tilt))], axis=1)
    return P, N


def test_a_rim_traced_at_two_scales_is_one_closed_outline():
    """A crease loop traced round at a fine scale but for one arc, which a trace of the
    coarse step found, each stopped short of the other by most of a coarse step: its
    scales' stitching leaves two pieces, and their ends, facing each other, join into
    one closed outline of the finer step, whatever the normals at the joints (a
    crease's normal is one of its sheets'); silhouettes on other sheets stay apart."""
    from blobtree_ink.agents.outline import stitch_scales
    fine, R, gap = STEP / 6, 0.5, 0.7 * STEP
    P, N = rim(R, gap / R, 1.5 * np.pi, fine)
    a = Outline("crease", P, N, False, fine)
    Q, _ = rim(R, 1.5 * np.pi + gap / R, 2 * np.pi, STEP)
    b = Outline("crease", Q, np.tile([1.0, 0.0, 0.0], (len(Q), 1)), False, STEP)   # the other sheet's normal
    assert not np.allclose(a.points[0], b.points[-1])
    out = stitch_scales([a, b])
    assert len(out) == 1 and out[0].closed and out[0].step == fine
    assert len(out[0].points) == len(P) + len(Q)
    d = np.linalg.norm(np.diff(np.vstack([out[0].points, out[0].points[:1]]), axis=0), axis=1)
    assert d.max() < 1.1 * STEP                          # no chord across the loop
    # silhouettes whose normals at the joint disagree are two sheets' lines: apart
    sil = stitch_scales([Outline("silhouette", a.points, a.normals, False, fine),
                         Outline("silhouette", b.points, b.normals, False, STEP)])
    assert len(sil) == 2 and not any(o.closed for o in sil)


def test_across_scales_only_ends_that_face_each_other_join():
    """Two creases of different scales meeting at a right angle (a box's corner), one
    whose end lies beyond the coarse reach, and pieces of one scale, stay as they were."""
    from blobtree_ink.agents.outline import stitch_scales
    fine = STEP / 6
    along = np.stack([np.linspace(0.0, 1.0, 61), np.zeros(61), np.zeros(61)], axis=1)
    up = np.stack([np.full(11, 1.0 + 0.5 * STEP), np.linspace(0.5 * STEP, 1.0, 11), np.zeros(11)], axis=1)
    n = np.tile(UP, (61, 1))
    corner = stitch_scales([Outline("crease", along, n, False, fine), Outline("crease", up, n[:11], False, STEP)])
    assert len(corner) == 2 and sorted(len(o.points) for o in corner) == [11, 61]
    far = np.stack([np.linspace(1.0 + 1.1 * REACH * LINK, 3.0, 11), np.zeros(11), np.zeros(11)], axis=1)
    apart = stitch_scales([Outline("crease", along, n, False, fine), Outline("crease", far, n[:11], False, STEP)])
    assert len(apart) == 2
    near = np.stack([np.linspace(1.0 + 0.5 * STEP, 3.0, 21), np.zeros(21), np.zeros(21)], axis=1)
    joined = stitch_scales([Outline("crease", along, n, False, fine), Outline("crease", near, n[:21], False, STEP)])
    assert len(joined) == 1 and len(joined[0].points) == 82 and not joined[0].closed
