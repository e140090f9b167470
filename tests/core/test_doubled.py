"""Outlines drawn twice (strokes.doubled): of two strokes running side by side on the
paper within about a line width, one leaves its stretch along the other out."""
import numpy as np

from blobtree_ink.strokes import doubled as DB
from blobtree_ink.strokes.data import Stroke

EYE = np.array([0.0, -10.0, 0.0])        # looking along +y: the paper is x (right), z (up) at depth 10
R = 0.01                                 # line radius: a line width is 0.02 on the paper at depth 10


def line(x0, x1, z=0.0, n=41, cyclic=False, radius=R):
    x = np.linspace(x0, x1, n)
    P = np.stack([x, np.zeros(n), np.full(n, z)], axis=1)
    return Stroke(P, np.full(n, radius), np.ones(n), cyclic=cyclic)


def test_the_shorter_of_two_lines_a_width_apart_leaves_out_its_stretch_along_the_longer():
    long_, short = line(-1.0, 1.0), line(-0.5, 1.5, z=0.02, n=41)           # a line width apart
    kept_long, kept_short = DB.undoubled([long_, short], EYE)
    assert len(kept_long) == 1 and kept_long[0] is long_
    (rest,) = kept_short                                     # what runs past the long line's end is kept
    assert rest.points[:, 0].min() <= 1.0 + 0.05 + 1e-9 and rest.points[:, 0].max() == 1.5
    assert rest.points[:, 0].min() > 0.85                    # ... reaching a point into the doubled stretch
    assert len(rest.points) == len(rest.radius) == len(rest.opacity)


def test_lines_further_apart_crossing_or_meeting_at_a_t_stay_whole():
    a = line(-1.0, 1.0)
    apart = line(-1.0, 1.0, z=0.08)                          # four line widths apart
    n = 41
    z = np.linspace(-1.0, 1.0, n)
    crossing = Stroke(np.stack([np.zeros(n), np.zeros(n), z], axis=1), np.full(n, R), np.ones(n))
    t = Stroke(np.stack([np.full(n, 0.3), np.zeros(n), np.linspace(0.0, 1.0, n)], axis=1), np.full(n, R), np.ones(n))
    for other in (apart, crossing, t):
        kept = DB.undoubled([a, other], EYE)
        assert [len(k) for k in kept] == [1, 1] and kept[1][0] is other


def test_a_closed_loop_stays_whole_and_a_line_along_it_meets_it():
    n = 200
    th = np.linspace(0, 2 * np.pi, n, endpoint=False)
    loop = Stroke(np.stack([0.5 * np.cos(th), np.zeros(n), 0.3 * np.sin(th)], axis=1), np.full(n, R), np.ones(n),
                  cyclic=True)
    arc_th = np.linspace(0.3, np.pi - 0.3, 300)
    shoulder = Stroke(np.stack([0.52 * np.cos(arc_th) * 1.6, np.zeros(300), 0.3 * np.sin(arc_th) + 0.01], axis=1),
                      np.full(300, R), np.ones(300))                # longer, running along the loop's top
    kept_loop, kept_shoulder = DB.undoubled([loop, shoulder], EYE)
    assert len(kept_loop) == 1 and kept_loop[0] is loop
    assert len(kept_shoulder) == 2                                  # its two ends, off the loop
    for piece in kept_shoulder:
        assert not piece.cyclic and len(piece.points) >= 2


def test_a_stub_between_two_doubled_stretches_goes_with_them():
    long_ = line(-1.0, 1.0, n=81)
    wobbly = line(-0.8, 0.8, n=65)
    P = wobbly.points.copy()
    P[31:33, 2] += 0.05                                             # two points leave the long line for a moment
    wobbly = Stroke(P, wobbly.radius, wobbly.opacity)
    hit = DB.doubled_points([long_, wobbly], EYE)[1]
    assert not hit[31:33].any() and hit[:29].all() and hit[35:].all()     # (the bump's ends turn away too)
    assert DB.undoubled([long_, wobbly], EYE)[1] == []              # no stub left on the line


def test_a_scrap_wholly_along_a_line_goes_and_a_short_touch_stays():
    """A stroke of two points or more lying wholly along a longer one is that line drawn
    again, whatever its length; a stroke touching a line for fewer than MIN_RUN points
    keeps them."""
    long_ = line(-1.0, 1.0)
    for n in (2, 3, 4):
        assert DB.undoubled([long_, line(-0.2, 0.2, z=0.01, n=n)], EYE)[1] == []
    z = np.linspace(0.3, 0.0, 31)
    x = np.where(z > 0.02, 0.0, 0.1 * np.arange(31) - 2.9)            # comes down to the line, then along it
    touch = Stroke(np.stack([x, np.zeros(31), z], axis=1), np.full(31, R), np.ones(31))
    hit = DB.doubled_points([long_, touch], EYE)[1]
    assert 0 < hit.sum() < DB.MIN_RUN
    assert DB.undoubled([long_, touch], EYE)[1] == [touch]


def test_a_loops_closing_segment_counts_and_an_empty_stroke_is_no_trouble():
    n = 8
    th = np.linspace(0, 2 * np.pi, n, endpoint=False)
    loop = Stroke(np.stack([np.cos(th), np.zeros(n), np.sin(th)], axis=1), np.full(n, R), np.ones(n), cyclic=True)
    a, b = loop.points[-1], loop.points[0]                     # the segment from the last point to the first
    t = np.linspace(0.2, 0.8, 7)[:, None]
    along = Stroke(a + t * (b - a) + [0.0, 0.0, 0.005], np.full(7, R), np.ones(7))
    assert DB.doubled_points([loop, along], EYE)[1].all()
    empty = Stroke(np.zeros((0, 3)), np.zeros(0), np.zeros(0))
    hits = DB.doubled_points([loop, empty, along], EYE)
    assert len(hits[1]) == 0 and hits[2].all()
    assert DB.undoubled([loop, empty, along], EYE) == [[loop], [], []]
