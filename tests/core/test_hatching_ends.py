"""Hatching lines that run into one corner end one after another, not in a blot
(strokes.hatching.spread_ends): no more than END_MOST ends within END_REACH line widths
of any end, over the parts of a layer; the lines ranked first keep their length."""
import os

import numpy as np

from blobtree_ink.strokes import hatching as HT
from blobtree_ink.strokes.data import Stroke
from blobtree_ink.strokes.paper import Paper, Placed

WIDEST = 0.01
PAPER = Paper(eye=(0.0, -10.0, 0.0), centre=(0.0, 0.0, 0.0))     # the paper is the plane y = 0, seen square


def fan(n=12, length=1.0, points=40):
    """``n`` straight lines on the paper, fanned over 60 degrees, all ending at the origin."""
    out = []
    for a in np.radians(np.linspace(120.0, 180.0, n)):
        t = np.linspace(length, 0.0, points)[:, None]
        P = np.hstack([t * np.cos(a), np.zeros_like(t), t * np.sin(a)])
        out.append(Stroke(P, np.full(points, 0.4 * WIDEST), np.ones(points), mark=len(out)))
    return out


def most_ends_near(strokes):
    E = np.array([PAPER.place(s.points[[i]])[0][0, :2] for s in strokes for i in (0, -1)])
    d = np.linalg.norm(E[:, None] - E[None], axis=2)
    reach = HT.END_REACH * WIDEST * PAPER.place(np.zeros((1, 3)))[1][0]
    return int((d < reach).sum(1).max())


def test_a_fan_of_lines_into_one_corner_ends_in_turn():
    lines = fan()
    assert most_ends_near(lines) == 12
    out = HT.spread_ends(PAPER, lines, np.arange(len(lines)), WIDEST, Placed())
    assert most_ends_near(out) <= HT.END_MOST
    kept = {s.mark: s for s in out}
    for k in range(HT.END_MOST):                 # the first ranked lines keep their whole length
        assert len(kept[k].points) == 40
    shortened = [k for k in kept if len(kept[k].points) < 40]
    assert shortened, "later lines are shortened at the corner"
    for k in shortened:                          # from the corner's end only, the rest of the line as it was
        assert np.array_equal(kept[k].points, lines[k].points[:len(kept[k].points)])
    assert len(out) >= 10                        # shortened, not dropped: each line is long enough to keep


def test_the_ends_of_parts_drawn_before_count():
    lines = fan()
    drawn = Placed()
    first = HT.spread_ends(PAPER, lines[:6], np.arange(6), WIDEST, drawn)
    second = HT.spread_ends(PAPER, lines[6:], np.arange(6), WIDEST, drawn)
    assert len(drawn.places) == 2 * (len(first) + len(second))
    assert most_ends_near(first + second) <= HT.END_MOST


def test_lines_whose_ends_stand_apart_are_left_as_they_are():
    lines = [Stroke(np.c_[np.linspace(0, 1, 20), np.zeros(20), np.full(20, 0.1 * k)], np.full(20, 0.004),
                    np.ones(20), mark=k) for k in range(20)]          # parallel, 10 widths apart
    out = HT.spread_ends(PAPER, lines, np.arange(20), WIDEST, Placed())
    assert len(out) == 20 and all(a is b for a, b in zip(out, lines))


def test_a_look_drawn_in_parts_of_a_few_lines_is_the_one_drawn_at_once(monkeypatch):
    """Where ends crowd, lines give way in the map's order whichever part they are drawn
    in: the jug's hatching drawn five map lines a part is the one drawn whole."""
    from blobtree_ink import model as M
    from blobtree_ink import pipeline as PL
    from blobtree_ink.blackboard.view import View
    from blobtree_ink.pipeline import layers as LY
    from blobtree_ink.strokes import style as ST

    def hatching():
        ev = M.Evaluator(M.load(os.path.join(os.path.dirname(__file__), "..", "..", "examples", "jug.json")))
        centre, radius = PL.bounds(ev)
        eye = PL.three_quarter_eye(centre, radius)
        light = tuple(PL.default_light(centre, eye))
        outlines = PL.Illustration(PL.Job(ev, view=View(eye=eye), light=light)).run().strokes
        lines = [s for name in ("Silhouette", "Crease") for s in outlines.layers.get(name, ())]
        job = PL.Job(ev, view=View(eye=eye), light=light, style=ST.style("hatched"),
                     requests=(PL.Request(PL.PLACE_STROKES),), lines=tuple(lines))
        return PL.Illustration(job).run().strokes.layers["Hatching"]
    whole = hatching()
    monkeypatch.setattr(LY, "CHUNK_LINES", 5)
    parts = hatching()
    assert len(whole) > 50 and len(parts) == len(whole)
    assert all(np.array_equal(a.points, b.points) and np.array_equal(a.radius, b.radius)
               for a, b in zip(whole, parts))
