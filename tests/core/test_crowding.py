"""Hatching that does not crowd on the paper (strokes.crowding): a fan of strokes meeting
at one point thins out towards it; crossings (of however many strokes heading one way)
and parallel strokes stay whole."""
import numpy as np

from blobtree_ink.model import keyed
from blobtree_ink.strokes import crowding as CR
from blobtree_ink.strokes.data import Stroke

EYE = np.array([0.0, 0.0, 10.0])          # looking down -z at the plane z = 0 (the paper at distance 10)
GAP = 0.05                                 # model units on that plane


def line(a, b, n, mark):
    P = np.linspace(a, b, n)
    return Stroke(P, np.full(n, 0.01), np.ones(n), mark=mark)


def fan(n=10, r=1.0, points=41):
    """Strokes from a circle of radius ``r`` to its centre (on z = 0), each its own mark."""
    out = []
    for k in range(n):
        a = 2 * np.pi * k / n
        out.append(line([r * np.cos(a), r * np.sin(a), 0.0], [0.0, 0.0, 0.0], points, mark=1000 + k))
    return out


def nearest_to_centre(strokes):
    return np.array([np.linalg.norm(s.points[:, :2], axis=1).min() for s in strokes])


def order(strokes):
    """The strokes' places in the order (0 first): by the number their marks draw, highest first."""
    u = keyed.uniform(np.array([s.mark for s in strokes], np.uint64), CR.ORDER)
    return np.argsort(np.argsort(-u))


def test_a_fan_thins_out_towards_where_it_meets():
    strokes = fan()
    cut = CR.Crowding(EYE, GAP).cut(strokes)
    by_mark = {s.mark: s for s in cut}
    # every stroke still starts where it did: a stroke is only shortened at its end
    assert len(cut) == len(strokes)
    for s in strokes:
        assert np.allclose(by_mark[s.mark].points[0], s.points[0])
    # the first two strokes in the order reach the centre (before them: nothing, then one
    # stroke heading one way: a crossing), and a stroke meeting two of those heading ways
    # apart does not; so do the strokes that go on through them
    place = order(strokes)
    reach = nearest_to_centre([by_mark[s.mark] for s in strokes])
    assert np.all(reach[place < 2] < 1e-9)
    reached = reach < 1e-9
    assert 2 <= reached.sum() <= 4, reach
    # the others stop short of it, where they come within the gap of strokes before them
    spread = 2 * np.pi / len(strokes)                  # neighbours' angle: a gap apart at radius GAP / spread
    assert np.all(reach[~reached] > 0.5 * GAP) and np.all(reach[~reached] < 2 * GAP / np.sin(spread))


def test_crossings_and_parallel_strokes_stay_whole():
    # a grid: parallel strokes far closer than the gap (0.2 of it), crossed at right angles
    # by others as tight: a stroke meets many strokes, all heading one way
    along = [line([-1, y, 0], [1, y, 0], 81, mark=k) for k, y in enumerate(np.arange(-10, 11) * 0.2 * GAP)]
    across = [line([x, -1, 0], [x, 1, 0], 81, mark=100 + k) for k, x in enumerate(np.arange(-5, 6) * 0.4 * GAP)]
    strokes = along + across
    cut = CR.Crowding(EYE, GAP).cut(strokes)
    assert [len(s.points) for s in cut] == [81] * len(strokes)
    # a third way through the grid's crossings: the strokes after others there stop
    diagonal = [line([-1 + d, -1 - d, 0], [1 + d, 1 - d, 0], 81, mark=200 + k)
                for k, d in enumerate(np.arange(-3, 4) * 0.3 * GAP)]
    cut = CR.Crowding(EYE, GAP).cut(strokes + diagonal)
    assert sum(len(s.points) for s in cut) < 81 * len(strokes + diagonal)
    assert len(cut) >= len(strokes)                    # shortened, not all gone


def test_the_runs_of_one_mark_never_stop_each_other():
    # one path's visible runs share its mark: a knot of its own runs is no meeting
    runs = [line([0, 0, 0], [np.cos(a), np.sin(a), 0], 21, mark=7) for a in np.linspace(0, np.pi, 6)]
    cut = CR.Crowding(EYE, GAP).cut(runs)
    assert [len(s.points) for s in cut] == [21] * len(runs)


def test_parts_after_the_first_stop_at_its_strokes():
    """A layer drawn in parts: the earlier parts' strokes come first, whatever the
    marks' order says. Three lines through one point, 45 degrees apart: drawn together,
    the last in the order stops short of the point; drawn in two parts, the diagonal of
    the second does, though it comes first in the order."""
    marks = np.arange(1, 200, dtype=np.uint64)
    u = keyed.uniform(marks, CR.ORDER)
    first, second, third = (int(m) for m in marks[np.argsort(-u)][:3])

    def through(angle, mark):
        d = np.array([np.cos(np.radians(angle)), np.sin(np.radians(angle)), 0.0])
        return line(-d, d, 81, mark)
    diagonal, h, v = through(45, first), through(0, second), through(90, third)
    together = CR.Crowding(EYE, GAP).cut([h, v, diagonal])
    assert [s.mark for s in together] == [second, third, first]
    assert len(together[0].points) == len(together[2].points) == 81
    assert 0.5 * GAP < nearest_to_centre([together[1]])[0] < 2 * GAP
    crowd = CR.Crowding(EYE, GAP)
    assert [len(s.points) for s in crowd.cut([h, v])] == [81, 81]
    later = crowd.cut([diagonal])
    assert len(later) == 1 and later[0].mark == first
    assert 0.5 * GAP < nearest_to_centre(later)[0] < 2 * GAP


def test_the_paper_is_what_the_eye_sees():
    """The distance is the one on the paper: a fan twice as far from the eye and twice
    as large, with the gap given at its distance, is cut alike."""
    near = fan()
    far = []
    for s in fan():                                    # the same fan twice as far from the eye, twice as large
        P = EYE + 2.0 * (s.points - EYE)
        far.append(Stroke(P, s.radius, s.opacity, mark=s.mark))
    a = CR.Crowding(EYE, GAP).cut(near)
    b = CR.Crowding(EYE, 2.0 * GAP).cut(far)         # the gap at the far fan's distance
    assert [len(s.points) for s in a] == [len(s.points) for s in b]
