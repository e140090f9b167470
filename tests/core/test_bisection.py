"""The batched bracket solver (agents.bisection): crease brackets narrow fast, and
brackets that cannot succeed are given up early rather than held for all 60
iterations (every batch waits for its slowest bracket)."""
import math

import numpy as np

from blobtree_ink import model as M
from blobtree_ink.agents import Session, Settings
from blobtree_ink.agents.bisection import bisect
from blobtree_ink.agents.surface import CREASE, SIL, Surface
from blobtree_ink.blackboard.view import View

from test_massris import BODY, K, POCKET, model_of, run, two_sphere_crease


class Counting(Surface):
    """The real surface, counting its projection calls (one per bisection iteration)."""

    def __init__(self, *a, **kw):
        super().__init__(*a, **kw)
        self.calls = 0

    def project(self, P, *args, **kwargs):
        self.calls += 1
        return super().project(P, *args, **kwargs)


def crease_seed_brackets(root, eye, resolution=20):
    """A session's crease seeds (polygon edges) as on-surface bracket ends, with a
    counting surface on its evaluator."""
    s = Session(model_of(root), View(eye=eye), Settings(resolution=resolution))
    s.request("OUTLINES")
    ids = s._open_seeds()
    ids = ids[s.bb.feat["kind"][ids] == CREASE]
    surf = Counting(s.ev, s.view)
    a, _, ga = surf.project(s.bb.feat["a"][ids])
    b, _, gb = surf.project(s.bb.feat["b"][ids])
    surf.calls = 0
    return s, surf, a, ga, b, gb


def test_brackets_that_cannot_converge_are_given_up():
    r = math.sqrt(1 - 0.5 ** (1 / 3))

    class Sheets(Surface):
        """Every trial point lands back on one of two fixed points (two sheets): the
        bracket can never narrow."""
        calls = 0

        def project(self, P, steps=6, max_step=None, anchor=None):
            Sheets.calls += 1
            P = np.asarray(P, float)
            Q = np.where((P[:, :1] < 0), [[-1.0, 0.0, 0.0]], [[1.0, 0.0, 0.0]])
            g = np.where((P[:, :1] < 0), [[0.0, -1.0, 0.0]], [[0.0, 1.0, 0.0]])
            return Q, np.full(len(P), self.iso), g

    ev = M.Evaluator(model_of({"type": "point", "center": [0, 0, 0], "radius": 1.0}))
    surf = Sheets(ev, View(eye=(0.0, -6.0, 0.0)))
    A, B = np.array([[-1.0, 0.0, 0.0]]), np.array([[1.0, 0.0, 0.0]])
    res = bisect(surf, np.array([SIL]), A, B, np.zeros((1, 3)), 1e-8 * ev.scale)
    assert not res[-1][0]
    assert Sheets.calls < 12                     # given up after a few iterations, not 60
    # a smooth bend taken for a crease: the ends' normals meet as it narrows
    one = M.Evaluator(model_of({"type": "point", "center": [0, 0, 0], "radius": 1.0}))
    surf = Surface(one, View(eye=(0.0, -6.0, 0.0)))
    A, B = np.array([[r, 0.0, 0.0]]), np.array([[0.0, r, 0.0]])
    ref = np.array([[1.0, -1.0, 0.0]])
    res = bisect(surf, np.array([CREASE]), A, B, ref, 1e-8 * one.scale, crease_angle=math.radians(35))
    assert not res[-1][0]
    # a real crease (the CSG circle) is still found
    diff = M.Evaluator(model_of({"type": "difference", "children": [
        {"type": "point", "center": [0, 0, 0], "radius": 1.5},
        {"type": "point", "center": [0.6, 0, 0], "radius": 1.2}]}))
    s = run(diff, View(eye=(4, -6, 3)), resolution=20)
    assert [o for o in s.outlines() if o.kind == "crease"]


def test_crease_brackets_converge_in_a_few_iterations():
    """Across the sharp wedge of a CSG difference a plain bisection shrank a bracket by
    only about 0.86 per iteration (about 40 iterations to 1e-8 of the model size); the
    tangent-plane estimate with a trial point on each side gets there in under 15."""
    c0, c1 = np.array([0.0, 0, 0]), np.array([0.6, 0.1, -0.1])
    root = {"type": "difference", "children": [{"type": "point", "center": list(c0), "radius": 1.5},
                                               {"type": "point", "center": list(c1), "radius": 1.2}]}
    s, surf, a, ga, b, gb = crease_seed_brackets(root, (4, -6, 3))
    assert len(a) > 20
    tol = 1e-8 * s.ev.scale
    X, _, A, B, _, _, valid = bisect(surf, np.full(len(a), CREASE), a, b, surf.normals(ga) - surf.normals(gb),
                                          tol, crease_angle=s.settings.crease_angle)
    assert valid.mean() > 0.9
    assert surf.calls <= 2 + 15                      # it took 62 calls
    assert np.linalg.norm(A[valid] - B[valid], axis=1).max() <= tol
    centre, axis, rad = two_sphere_crease(c0, K * 1.5, c1, K * 1.2)
    rel = X[valid] - centre
    along = rel @ axis
    assert np.abs(along).max() < 1e-6
    assert np.abs(np.linalg.norm(rel - along[:, None] * axis, axis=1) - rad).max() < 1e-6


def test_a_narrow_crease_bracket_finishes_where_its_tangent_planes_meet():
    """With ``finish`` = sqrt(tol * L), a crease bracket stops at that width and its
    crossing is where its ends' tangent planes meet, projected onto the surface: off the
    crease by the sheets' curvature times the width squared, so as close as the full
    bisection to tol, in fewer iterations."""
    c0, c1 = np.array([0.0, 0, 0]), np.array([0.6, 0.1, -0.1])
    root = {"type": "difference", "children": [{"type": "point", "center": list(c0), "radius": 1.5},
                                               {"type": "point", "center": list(c1), "radius": 1.2}]}
    s, surf, a, ga, b, gb = crease_seed_brackets(root, (4, -6, 3))
    tol = 1e-8 * s.ev.scale
    kinds, ref = np.full(len(a), CREASE), surf.normals(ga) - surf.normals(gb)
    full = bisect(surf, kinds, a, b, ref, tol, crease_angle=s.settings.crease_angle)
    calls_full, surf.calls = surf.calls, 0
    finish = np.sqrt(tol * np.linalg.norm(a - b, axis=1))
    X, gX, A, B, _, _, valid = bisect(surf, kinds, a, b, ref, tol, crease_angle=s.settings.crease_angle,
                                           finish=finish)
    assert np.array_equal(valid, full[-1]) and valid.mean() > 0.9
    assert surf.calls < calls_full
    w = np.linalg.norm(A[valid] - B[valid], axis=1)
    assert np.all(w <= finish[valid]) and np.median(w) > 10 * tol       # it stopped early
    np.testing.assert_allclose(s.ev.field(X[valid]), s.ev.iso, atol=1e-12)
    centre, axis, rad = two_sphere_crease(c0, K * 1.5, c1, K * 1.2)
    rel = X[valid] - centre
    along = rel @ axis
    assert np.abs(along).max() < tol
    assert np.abs(np.linalg.norm(rel - along[:, None] * axis, axis=1) - rad).max() < tol


def test_a_silhouette_bracket_across_a_crease_is_given_up_early():
    """n.v can change sign by jumping across a crease rather than passing through zero
    (here the rim of a pocket whose far wall faces away): such a bracket is no
    silhouette (the callers reject it) and need not run all 60 iterations: once it is
    down to a hundredth with its ends' normals still apart, it stops, invalid."""
    s, surf, a, ga, b, gb = crease_seed_brackets({"type": "difference", "children": [BODY, POCKET]},
                                                 (-3.0, -6.0, 0.3))
    kinds = np.full(len(a), SIL)
    across = (surf.signs(kinds, a, ga, None) > 0) != (surf.signs(kinds, b, gb, None) > 0)
    assert across.sum() >= 3
    tol = 1e-8 * s.ev.scale
    ca = s.settings.crease_angle
    A0, B0, k0 = a[across], b[across], kinds[across]
    X, gX, A, B, nA, nB, valid = bisect(surf, k0, A0, B0, np.zeros((len(k0), 3)), tol, crease_angle=ca)
    assert surf.calls <= 2 + 25                      # it took 56 calls
    # what it gives up early is what the callers would reject at the end: without the
    # early outs, those brackets end with their normals apart (on the rim)
    full = bisect(surf, k0, A0, B0, np.zeros((len(k0), 3)), tol)
    apart = np.einsum("ij,ij->i", full[4], full[5]) < np.cos(0.5 * ca)
    assert np.array_equal(valid, full[-1] & ~apart)
    assert (~valid).sum() >= 3
    # and what it keeps is a true silhouette point
    v = s.view.towards_eye(X[valid])
    assert np.abs(np.einsum("ij,ij->i", surf.normals(gX[valid]), v)).max() < 1e-6


def test_a_crease_bracket_that_never_narrows_stops():
    """Trial points that land back near the ends, the bracket's width see-sawing (so it
    never stalls three times running): a crease bracket not down to a quarter within
    12 iterations stops, invalid, instead of holding its batch for all 60."""
    class SeeSaw(Surface):
        calls = 0

        def project(self, P, steps=6, max_step=None, anchor=None):
            SeeSaw.calls += 1
            P = np.asarray(P, float)
            left = P[:, :1] < 0.5
            x = -1.0 if SeeSaw.calls % 2 else -0.8
            Q = np.where(left, [[x, 0.0, 0.0]], [[1.0, 0.0, 0.0]])
            g = np.where(left, [[0.0, -1.0, 0.0]], [[0.0, 1.0, 0.0]])
            return Q, np.full(len(P), self.iso), g

    ev = M.Evaluator(model_of({"type": "point", "center": [0, 0, 0], "radius": 1.0}))
    surf = SeeSaw(ev, View(eye=(0.0, -6.0, 0.0)))
    A, B = np.array([[-1.0, 0.0, 0.0]]), np.array([[1.0, 0.0, 0.0]])
    res = bisect(surf, np.array([CREASE]), A, B, np.array([[0.0, 2.0, 0.0]]), 1e-8 * ev.scale,
                      crease_angle=math.radians(35))
    assert not res[-1][0]
    assert SeeSaw.calls <= 2 + 13


def test_a_crease_estimate_off_by_more_than_its_nudge_is_nudged_by_a_quarter(monkeypatch):
    """Where the sheets curve at the bracket's scale (a coarse grid's long brackets
    across two balls' crease), the tangent planes' estimate is off by more than its
    small nudge: both trial points land on one side and one end moves by the nudge
    alone, and the bracket is given up before it converges. After such an estimate the
    next trial points are a quarter of the bracket off it: twice as many brackets
    converge, onto the analytic circle."""
    import blobtree_ink.agents.bisection as bisection_module
    c0, c1 = np.array([0.0, 0, 0]), np.array([0.9, 0.1, -0.1])
    root = {"type": "union", "children": [{"type": "point", "center": list(c0), "radius": 1.5},
                                          {"type": "point", "center": list(c1), "radius": 1.0}]}
    s, surf, a, ga, b, gb = crease_seed_brackets(root, (4, -6, 3), resolution=8)
    tol = 1e-8 * s.ev.scale
    kinds, ref = np.full(len(a), CREASE), surf.normals(ga) - surf.normals(gb)
    finish = np.sqrt(tol * np.linalg.norm(a - b, axis=1))
    runs = {}
    for nudge in (bisection_module.WIDE_NUDGE, bisection_module.CREASE_NUDGE):
        monkeypatch.setattr(bisection_module, "WIDE_NUDGE", nudge)
        surf.calls = 0
        res = bisect(surf, kinds, a, b, ref, tol, crease_angle=s.settings.crease_angle, finish=finish)
        runs[nudge] = (surf.calls, res)
    (calls, (X, _, _, _, _, _, valid)), (_, small) = runs.values()
    assert valid.sum() >= 2 * small[-1].sum() and valid.sum() > 20
    assert calls <= 10
    centre, axis, rad = two_sphere_crease(c0, K * 1.5, c1, K * 1.0)
    rel = X[valid] - centre
    along = rel @ axis
    assert np.abs(along).max() < 1e-6
    assert np.abs(np.linalg.norm(rel - along[:, None] * axis, axis=1) - rad).max() < 1e-6
