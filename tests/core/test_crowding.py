"""Hatching that does not crowd on the paper (strokes.crowding): a fan of strokes meeting
at one point thins out towards it; crossings (of however many strokes heading one way)
and parallel strokes stay whole; the thinning changes continuously with the view."""
import numpy as np
import pytest

from blobtree_ink.model import keyed
from blobtree_ink.strokes import crowding as CR
from blobtree_ink.strokes.data import Stroke

EYE = np.array([0.0, 0.0, 10.0])          # looking down -z at the plane z = 0 (the paper at distance 10)
CENTRE = np.zeros(3)
GAP = 0.05                                 # model units on that plane


def line(a, b, n, mark):
    P = np.linspace(a, b, n)
    return Stroke(P, np.full(n, 0.01), np.ones(n), mark=mark)


def fan(n=10, r=1.0, points=81):
    """Strokes from a circle of radius ``r`` to its centre (on z = 0), each its own mark."""
    out = []
    for k in range(n):
        a = 2 * np.pi * k / n
        out.append(line([r * np.cos(a), r * np.sin(a), 0.0], [0.0, 0.0, 0.0], points, mark=1000 + k))
    return out


def drawn(s):
    """What of each point of a stroke is drawn (its radius against the untouched one's,
    to a millionth)."""
    return np.round(s.radius / 0.01, 6)


def order(strokes):
    """The strokes' places in the order (0 first): by the number their marks draw, highest first."""
    u = keyed.uniform(np.array([s.mark for s in strokes], np.uint64), CR.ORDER)
    return np.argsort(np.argsort(-u))


def test_a_fan_thins_out_towards_where_it_meets():
    strokes = fan()
    out = CR.Crowding(EYE, CENTRE, GAP).thinned(strokes)
    assert len(out) == len(strokes)
    by_mark = {s.mark: s for s in out}
    place = order(strokes)
    for s, p in zip(strokes, place):
        t = by_mark[s.mark]
        f = drawn(t)
        assert np.array_equal(t.points, s.points[:len(t.points)])   # shortened at most, not moved
        assert np.allclose(t.opacity, f, atol=1e-6)
        assert np.all(np.diff(f) <= 1e-12)                           # once thinned, never thicker again
        assert f[0] == 1.0                                           # whole far from the centre
        if p < 2:                                                    # nothing before it, or one stroke: whole
            assert np.all(f == 1.0)
    # the others thin out towards the centre (all but one end before it: the first two
    # strokes in the order may be one line, the stroke after them then meets one way only)
    later = [by_mark[s.mark] for s, p in zip(strokes, place) if p >= 2]
    ended = [t for t in later if len(t.points) < 81]
    assert len(ended) >= len(later) - 2
    for t in ended:
        r = np.linalg.norm(t.points[:, :2], axis=1)
        assert np.all(drawn(t)[r > 4 * GAP] == 1.0) and np.all(drawn(t) > 0)
        assert 0 < r.min() < GAP and drawn(t)[-1] < 0.5


def test_crossings_and_parallel_strokes_stay_whole():
    # a grid: parallel strokes far closer than the gap (0.2 of it), crossed at right angles
    # by others as tight: a stroke meets many strokes, all heading one way
    along = [line([-1, y, 0], [1, y, 0], 81, mark=k) for k, y in enumerate(np.arange(-10, 11) * 0.2 * GAP)]
    across = [line([x, -1, 0], [x, 1, 0], 81, mark=100 + k) for k, x in enumerate(np.arange(-5, 6) * 0.4 * GAP)]
    strokes = along + across
    out = CR.Crowding(EYE, CENTRE, GAP).thinned(strokes)
    assert [s.mark for s in out] == [s.mark for s in strokes]
    assert all(np.all(drawn(s) == 1.0) for s in out)
    # a third way through the grid's crossings: the strokes after others there thin out
    diagonal = [line([-1 + d, -1 - d, 0], [1 + d, 1 - d, 0], 81, mark=200 + k)
                for k, d in enumerate(np.arange(-3, 4) * 0.3 * GAP)]
    out = CR.Crowding(EYE, CENTRE, GAP).thinned(strokes + diagonal)
    assert sum(drawn(s).min() < 0.5 for s in out) >= 3


def test_the_runs_of_one_mark_never_thin_each_other():
    # one path's visible runs share its mark: a knot of its own runs is no meeting
    runs = [line([0, 0, 0], [np.cos(a), np.sin(a), 0], 21, mark=7) for a in np.linspace(0, np.pi, 6)]
    out = CR.Crowding(EYE, CENTRE, GAP).thinned(runs)
    assert all(np.all(drawn(s) == 1.0) for s in out) and len(out) == len(runs)
    # strokes are told apart by their marks: one without is an error, not a guess
    with pytest.raises(ValueError, match="has none"):
        CR.Crowding(EYE, CENTRE, GAP).thinned(runs + [line([0, 0, 0], [0, 1, 0], 21, mark=None)])


def test_parts_after_the_first_give_way_to_its_strokes():
    """A layer drawn in parts: the earlier parts' strokes come first, whatever the
    marks' order says. Three lines through one point, 45 degrees apart: drawn together,
    the last in the order thins out before the point; drawn in two parts, the diagonal
    of the second does, though it comes first in the order."""
    marks = np.arange(1, 200, dtype=np.uint64)
    u = keyed.uniform(marks, CR.ORDER)
    first, second, third = (int(m) for m in marks[np.argsort(-u)][:3])

    def through(angle, mark):
        d = np.array([np.cos(np.radians(angle)), np.sin(np.radians(angle)), 0.0])
        return line(-d, d, 81, mark)
    diagonal, h, v = through(45, first), through(0, second), through(90, third)
    together = CR.Crowding(EYE, CENTRE, GAP).thinned([h, v, diagonal])
    assert [s.mark for s in together] == [second, third, first]
    assert np.all(drawn(together[0]) == 1.0) and np.all(drawn(together[2]) == 1.0)
    assert drawn(together[1]).min() < 0.5
    crowd = CR.Crowding(EYE, CENTRE, GAP)
    assert all(np.all(drawn(s) == 1.0) for s in crowd.thinned([h, v]))
    later = crowd.thinned([diagonal])
    assert len(later) == 1 and later[0].mark == first and drawn(later[0]).min() < 0.5


def test_the_paper_is_what_the_eye_sees():
    """The distance is the one on the paper: a fan twice as far from the eye and twice
    as large, with the gap given at its distance, thins alike."""
    far = [Stroke(EYE + 2.0 * (s.points - EYE), s.radius, s.opacity, mark=s.mark) for s in fan()]
    a = CR.Crowding(EYE, CENTRE, GAP).thinned(fan())
    b = CR.Crowding(EYE, EYE + 2.0 * (CENTRE - EYE), 2.0 * GAP).thinned(far)
    assert [s.mark for s in a] == [s.mark for s in b]
    assert all(np.allclose(drawn(s), drawn(t)) for s, t in zip(a, b))


def test_a_turning_view_thins_continuously():
    """The eye turning a little about the fan changes how much of each point is drawn a
    little: strokes fade in and out of a knot, they do not jump."""
    strokes = fan()
    a = CR.Crowding(EYE, CENTRE, GAP).thinned(strokes)
    turn = np.radians(0.5)
    eye = np.array([0.0, 10.0 * np.sin(turn), 10.0 * np.cos(turn)])
    b = CR.Crowding(eye, CENTRE, GAP).thinned(strokes)
    assert [s.mark for s in a] == [s.mark for s in b]

    def along(s, n):
        return np.concatenate([drawn(s), np.zeros(n - len(s.points))])       # ended: nothing drawn
    change = [np.abs(along(s, 81) - along(t, 81)) for s, t in zip(a, b)]
    assert max(c.max() for c in change) < 0.25
    assert sum(c.sum() for c in change) > 0                                   # the view does count


def test_a_knot_weighs_alike_wherever_the_strokes_points_fall():
    """Strokes sampled as sparsely as hatching is (points farther apart than half the
    gap): a stroke met is the polyline through its points, so how much of a stroke a
    knot leaves does not depend on where the others' points happen to lie."""
    def knot(shift):
        spacing = 0.6 * GAP
        def through(angle, mark, offset):
            d = np.array([np.cos(np.radians(angle)), np.sin(np.radians(angle)), 0.0])
            t = np.arange(-20, 21) * spacing + offset
            return Stroke(t[:, None] * d, np.full(len(t), 0.01), np.ones(len(t)), mark=mark)
        marks = np.arange(1, 200, dtype=np.uint64)
        first, second, third = (int(m) for m in marks[np.argsort(-keyed.uniform(marks, CR.ORDER))][:3])
        out = CR.Crowding(EYE, CENTRE, GAP).thinned([through(0, first, shift), through(90, second, shift),
                                                     through(45, third, 0.0)])
        return [s for s in out if s.mark == third]
    ends = [knot(shift) for shift in np.linspace(0.0, 0.6 * GAP, 7)]
    # the diagonal ends before the crossing of the two strokes before it, at about the same place every time
    lengths = [len(e[0].points) if e else 0 for e in ends]
    assert all(0 < n < 41 for n in lengths) and max(lengths) - min(lengths) <= 1, lengths


def test_a_stroke_with_no_direction_is_no_knot():
    """A stroke whose points stand still (no direction on the paper) heads no way: it
    thins nothing, and a line through it is drawn whole."""
    still = Stroke(np.zeros((3, 3)), np.full(3, 0.01), np.ones(3), mark=1)
    marks = np.arange(2, 200, dtype=np.uint64)
    after = int(marks[np.argsort(keyed.uniform(marks, CR.ORDER))][0])     # after the still one in the order
    out = CR.Crowding(EYE, CENTRE, GAP).thinned([still, line([-1, 0, 0], [1, 0, 0], 81, mark=after)])
    assert [len(s.points) for s in out if s.mark == after] == [81]
    assert all(np.all(drawn(s) == 1.0) for s in out if s.mark == after)
