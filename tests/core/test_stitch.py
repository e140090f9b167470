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


def test_a_free_end_beside_a_line_it_runs_along_does_not_hook_onto_it():
    """An end running alongside another line, half a link off it, reaches nothing (it
    does not head across that line, nor lie on its run, though the line's points ahead
    lie within AHEAD); turned towards the line, it reaches it."""
    main = piece(line(0.0, 2.0))
    beside = line(0.2, 1.0, y=0.5 * LINK)
    gap = main.points[13] - beside[-1]                          # a point of the line ahead, within reach
    assert np.linalg.norm(gap) < REACH * LINK and gap[0] / np.linalg.norm(gap) >= AHEAD
    assert sorted(len(o.points) for o in stitched(main, piece(beside))) == [9, 21]
    turned = np.vstack([beside, beside[-1] + [0.1, -0.06, 0.0]])   # its last step heads down
    assert sorted(len(o.points) for o in stitched(main, piece(turned))) == [11, 21]


def chained(*polylines, **kw):
    """join_ends on the polylines as chains (no pooling): (points, closed) per result."""
    from blobtree_ink.agents.stitch import join_ends
    P = np.concatenate(polylines)
    first = np.cumsum([0] + [len(q) for q in polylines])
    chains = [list(range(a, b)) for a, b in zip(first[:-1].tolist(), first[1:].tolist())]
    return [(P[idx], closed) for idx, closed in join_ends(P, np.tile(UP, (len(P), 1)), chains, LINK, **kw)]


def test_two_ends_that_reach_each_other_join_once():
    """Two lines meeting at a corner whose ends each reach the other's end (within 60
    degrees of their directions, not facing each other within AHEAD): one runs on to
    the other's end, not both (no doubled corner)."""
    a = line(0.0, 1.0)
    b = np.stack([np.full(8, 1.3), np.linspace(0.95, 0.25, 8), np.zeros(8)], axis=1)    # heads down
    out = chained(a, b, reach=0.45, ahead=0.5)
    assert sorted(len(q) for q, _ in out) in ([8, 12], [9, 11])
    assert sorted(len(q) for q, _ in chained(a, b)) == [8, 11]          # not within AHEAD: apart


def test_an_end_run_on_to_another_line_does_not_close_its_outline():
    """A U whose two ends, farther apart than a link, turn in and both run on to a line
    below, on points closer than a link: one open outline ending on that line at both
    ends, not a closed loop."""
    main = line(-1.0, 1.0)
    up = np.linspace(0.25, 1.0, 9)
    u = np.concatenate([[[0.15, 0.2, 0.0]], np.stack([np.full(9, 0.2), up, 0 * up], axis=1),
                        np.stack([np.full(9, -0.2), up[::-1], 0 * up], axis=1), [[-0.15, 0.2, 0.0]]])
    assert np.linalg.norm(u[0] - u[-1]) > LINK
    out = chained(main, u)
    ran = [(q, closed) for q, closed in out if len(q) == len(u) + 2]
    assert len(ran) == 1 and not ran[0][1] and np.allclose(ran[0][0][[0, -1], 1], 0.0)
    assert np.linalg.norm(ran[0][0][0] - ran[0][0][-1]) < LINK


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


def test_across_scales_an_end_runs_on_to_a_line_it_stopped_short_of():
    """Two creases of different scales meeting at a right angle (a box's corner) stay
    two outlines, the fine one running on to the coarse one's nearest point ahead (its
    trace stopped short of it: within MEET of the coarse step); one whose end lies
    beyond the coarse reach, and pieces of one scale, stay as they were."""
    from blobtree_ink.agents.outline import MEET, stitch_scales
    fine = STEP / 6
    along = np.stack([np.linspace(0.0, 1.0, 61), np.zeros(61), np.zeros(61)], axis=1)
    up = np.stack([np.full(11, 1.0 + 0.5 * STEP), np.linspace(0.5 * STEP, 1.0, 11), np.zeros(11)], axis=1)
    n = np.tile(UP, (61, 1))
    corner = stitch_scales([Outline("crease", along, n, False, fine), Outline("crease", up, n[:11], False, STEP)])
    assert len(corner) == 2 and sorted(len(o.points) for o in corner) == [11, 62]
    ran = next(o for o in corner if len(o.points) == 62)
    assert np.allclose(ran.points[:61], along) and np.allclose(ran.points[-1], up[0])
    assert np.linalg.norm(up[0] - along[-1]) < MEET * STEP
    beyond = up + [0.0, (MEET + 0.1) * STEP, 0.0]       # out of reach: as it was
    out = stitch_scales([Outline("crease", along, n, False, fine), Outline("crease", beyond, n[:11], False, STEP)])
    assert sorted(len(o.points) for o in out) == [11, 61]
    # a coarse piece running alongside the fine one half a step off: as they were
    beside = np.stack([np.linspace(0.2, 0.8, 7), np.full(7, 0.5 * STEP), np.zeros(7)], axis=1)
    out = stitch_scales([Outline("crease", along, n, False, fine), Outline("crease", beside, n[:7], False, STEP)])
    assert sorted(len(o.points) for o in out) == [7, 61]
    # ... and one that ends on the fine piece's middle (a T-junction) runs on to it
    tee = np.stack([np.full(7, 0.5), np.linspace(0.7, 0.5 * STEP, 7), np.zeros(7)], axis=1)
    out = stitch_scales([Outline("crease", along, n, False, fine), Outline("crease", tee, n[:7], False, STEP)])
    assert sorted(len(o.points) for o in out) == [8, 61]
    assert any(np.allclose(o.points[-1], [0.5, 0.0, 0.0]) for o in out if len(o.points) == 8)
    far = np.stack([np.linspace(1.0 + 1.1 * REACH * LINK, 3.0, 11), np.zeros(11), np.zeros(11)], axis=1)
    apart = stitch_scales([Outline("crease", along, n, False, fine), Outline("crease", far, n[:11], False, STEP)])
    assert len(apart) == 2
    near = np.stack([np.linspace(1.0 + 0.5 * STEP, 3.0, 21), np.zeros(21), np.zeros(21)], axis=1)
    joined = stitch_scales([Outline("crease", along, n, False, fine), Outline("crease", near, n[:21], False, STEP)])
    assert len(joined) == 1 and len(joined[0].points) == 82 and not joined[0].closed


def test_across_scales_a_closed_ring_is_reached_never_joined():
    """A fine crease stopped short of a coarse closed rim (a window's rim) runs on to the
    rim's nearest point ahead; a fine piece across the rim's seam, which is wider than a
    link (its pieces were joined round), does not take the rim's end: the rim is drawn
    once, closed, as it was."""
    from blobtree_ink.agents.outline import stitch_scales
    fine = STEP / 6
    t = np.linspace(0.0, 2 * np.pi - 1.3 * LINK, 60)            # a seam of 1.3 links
    ring = np.stack([np.cos(t), np.sin(t), 0 * t], axis=1)
    assert np.linalg.norm(ring[0] - ring[-1]) > LINK
    rim = Outline("crease", ring, np.tile(UP, (60, 1)), True, STEP)
    spoke = np.stack([np.full(31, 0.3), np.linspace(-0.3, -0.9, 31), np.zeros(31)], axis=1)   # heads down to the rim
    across = np.stack([np.linspace(1.2, 0.8, 25), np.full(25, -0.24), np.zeros(25)], axis=1)  # just ahead of the seam
    out = stitch_scales([rim, Outline("crease", spoke, np.tile(UP, (31, 1)), False, fine),
                         Outline("crease", across, np.tile(UP, (25, 1)), False, fine)])
    rings = [o for o in out if len(o.points) >= 60]
    assert len(rings) == 1 and rings[0].closed and np.allclose(rings[0].points, ring)
    ran = [o for o in out if len(o.points) == 32]
    assert len(ran) == 1 and not ran[0].closed and np.isclose(np.linalg.norm(ran[0].points[-1][:2]), 1.0)


def test_across_scales_coarse_pieces_stitch_alike_beside_a_fine_piece_far_away():
    """A coarse crease ending beside another's end, 50 degrees off pointing at it (within
    MEET_AHEAD, not AHEAD): a fine piece elsewhere in the model does not make it run on
    to the other (coarse pieces were stitched with their own rules)."""
    from blobtree_ink.agents.outline import MEET, stitch_scales
    a = line(0.0, 1.0)
    d = np.array([np.cos(np.radians(-40.0)), np.sin(np.radians(-40.0)), 0.0])
    b = np.array([1.0, 0.06, 0.0]) - np.arange(7, -1, -1)[:, None] * STEP * d        # ends heading down to a
    assert np.linalg.norm(b[-1] - a[-1]) < MEET * STEP
    pieces = [Outline("crease", a, np.tile(UP, (11, 1)), False, STEP), Outline("crease", b, np.tile(UP, (8, 1)), False, STEP)]
    alone = stitch_scales(pieces)
    assert sorted(len(o.points) for o in alone) == [8, 11]
    x = np.linspace(10.0, 11.0, 61)
    far = Outline("crease", np.stack([x, np.full(61, 5.0), 0 * x], axis=1), np.tile(UP, (61, 1)), False, STEP / 6)
    beside = stitch_scales(pieces + [far])
    assert sorted(len(o.points) for o in beside) == [8, 11, 61]
