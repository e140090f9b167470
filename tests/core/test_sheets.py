"""Creases by Newton's method on the two sheets a crease team's branch records pin
(agents.sheets): exact crease points in a few evaluations, smooth bends rejected
without bisecting, traces that step by Newton alone, and junctions where a third part
ends a crease."""
import itertools
import math

import numpy as np
import pytest

from blobtree_ink.agents import tracer as TR
from blobtree_ink.agents.surface import CREASE
from blobtree_ink.blackboard.view import View

from test_bisection import crease_seed_brackets
from test_massris import K, check_on_surface, run, model_of, two_sphere_crease

C0, C1 = np.array([0.0, 0, 0]), np.array([0.6, 0.1, -0.1])


def spheres(op):
    return {"type": op, "children": [{"type": "point", "center": list(C0), "radius": 1.5},
                                     {"type": "point", "center": list(C1), "radius": 1.2}]}


def counting(ev):
    calls = [0]
    run_ = ev._run

    def counted(P, need_grad, ctx=None):
        calls[0] += 1
        return run_(P, need_grad, ctx)
    ev._run = counted
    return calls


def spy_brackets(monkeypatch):
    """A list that receives the number of crease rows of every bracketed trace step."""
    bracketed = []
    step = TR._bracket_step

    def spy(surface, kinds, *a, **kw):
        bracketed.append(int((kinds == CREASE).sum()))
        return step(surface, kinds, *a, **kw)
    monkeypatch.setattr(TR, "_bracket_step", spy)
    return bracketed


def off_circle(X, centre, axis, rad):
    rel = X - centre
    along = rel @ axis
    return max(np.abs(along).max(), np.abs(np.linalg.norm(rel - along[:, None] * axis, axis=1) - rad).max())


@pytest.mark.parametrize("op", ["difference", "union"])
def test_crease_seeds_land_exactly_on_the_circle_in_a_few_evaluations(op):
    s, surf, a, ga, b, gb = crease_seed_brackets(spheres(op), (4, -6, 3))
    assert len(a) > 50
    calls = counting(s.ev)
    X, n, T, ref, A, B, valid, pins, _ = TR.refine_seeds(surf, np.full(len(a), CREASE), a, b, 1e-8 * s.ev.scale,
                                                      s.settings.crease_angle)
    assert valid.all()
    # projection, records, Newton iterations, checks: no bisection (it took 17
    # projections of several evaluations each)
    assert calls[0] <= 10 and surf.calls == 1
    assert off_circle(X, *two_sphere_crease(C0, K * 1.5, C1, K * 1.2)) < 1e-13
    # the sides' records: the sheets differ, and the tangent runs along the circle
    assert (pins[:, 0] != pins[:, 1]).any(axis=1).all()
    centre, axis, rad = two_sphere_crease(C0, K * 1.5, C1, K * 1.2)
    radial = X - centre - ((X - centre) @ axis)[:, None] * axis
    # (from the sheets' normals at Newton's last iterate but one, within tol)
    assert np.abs(np.einsum("ij,ij->i", T, radial)).max() < 1e-7
    assert np.abs(T @ axis).max() < 1e-7


def test_a_smooth_bend_taken_for_a_crease_is_rejected_without_bisecting():
    # two blended spheres: no max or min anywhere, so no crease candidate can be one
    root = {"type": "blend", "children": spheres("union")["children"]}
    s, surf, a, ga, b, gb = crease_seed_brackets(root, (4, -6, 3), resolution=10)
    assert s.ev.sites.count == 0
    rng = np.random.default_rng(0)
    P, _, _ = surf.project(rng.normal(size=(40, 3)))         # brackets across the waist
    a, b = P[:20], P[20:]
    surf.calls = 0
    seeds = TR.refine_seeds(surf, np.full(20, CREASE), a, b, 1e-8 * s.ev.scale, s.settings.crease_angle)
    valid = seeds.valid
    assert not valid.any() and surf.calls == 1


def test_a_crease_is_traced_by_newton_steps_alone(monkeypatch):
    bracketed = spy_brackets(monkeypatch)
    s = run(model_of(spheres("difference")), View(eye=(4, -6, 3)), resolution=20)
    creases = [o for o in s.outlines() if o.kind == "crease"]
    assert creases and sum(len(o.points) for o in creases) > 40
    assert sum(bracketed) == 0
    pts = np.concatenate([o.points for o in creases])
    assert off_circle(pts, *two_sphere_crease(C0, K * 1.5, C1, K * 1.2)) < 1e-12
    for o in creases:
        check_on_surface(s, o)


def test_creases_end_where_a_third_part_covers_their_sheets_meeting():
    # three unioned spheres: each pair's circle is a crease only outside the third
    # sphere; beyond the triple points the pinned sheets still meet (a ghost circle
    # inside the third sphere), which must not be traced
    C = [np.array(c) for c in ((0.0, 0, 0), (1.0, 0, 0), (0.5, 0.8, 0))]
    R = 1.3
    root = {"type": "union", "children": [{"type": "point", "center": list(c), "radius": R} for c in C]}
    s = run(model_of(root), View(eye=(1, -2, 6)), resolution=24)
    creases = [o for o in s.outlines() if o.kind == "crease"]
    assert creases
    pts = np.concatenate([o.points for o in creases])
    for o in creases:
        check_on_surface(s, o)
    r = K * R
    near = []
    for i, j in itertools.combinations(range(3), 2):
        centre, axis, rad = two_sphere_crease(C[i], r, C[j], r)
        rel = pts - centre
        along = rel @ axis
        near.append(np.maximum(np.abs(along), np.abs(np.linalg.norm(rel - along[:, None] * axis, axis=1) - rad)))
    assert np.min(near, axis=0).max() < 1e-9                  # each point on a pair's circle
    third = [np.linalg.norm(pts - c, axis=1) for c in C]
    # and on no ghost: every point is outside (or on) all three spheres
    assert np.min(third, axis=0).min() > r - 1e-9
    # every pair's visible arcs are covered
    for i, j in itertools.combinations(range(3), 2):
        k = 3 - i - j
        centre, axis, rad = two_sphere_crease(C[i], r, C[j], r)
        u = np.cross(axis, [0, 0, 1.0])
        u = u / np.linalg.norm(u) if np.linalg.norm(u) > 1e-9 else np.array([1.0, 0, 0])
        w = np.cross(axis, u)
        t = np.linspace(0, 2 * math.pi, 720, endpoint=False)
        ring = centre + rad * (np.cos(t)[:, None] * u + np.sin(t)[:, None] * w)
        vis = ring[np.linalg.norm(ring - C[k], axis=1) > r + 0.02]
        d = np.linalg.norm(vis[:, None] - pts[None], axis=2).min(axis=1)
        assert np.mean(d < 0.05 * r) > 0.97, (i, j, np.mean(d < 0.05 * r))


def test_a_silhouette_bracket_across_a_crease_is_rejected_without_bisecting():
    # two unioned spheres seen along their axis: n.v jumps from + to - across the crease
    # circle (x = 0), while each sphere's own silhouette is its great circle x = -+0.6
    from blobtree_ink import model as M
    from blobtree_ink.agents.surface import SIL, Surface
    root = {"type": "union", "children": [{"type": "point", "center": [-0.6, 0, 0], "radius": 1.5},
                                          {"type": "point", "center": [0.6, 0, 0], "radius": 1.5}]}
    ev = M.Evaluator(model_of(root))
    surf = Surface(ev, View(direction=(-1, 0, 0)))
    calls = counting(ev)
    r = K * 1.5
    t = np.linspace(0.3, 2.8, 12)
    ring = np.stack([np.zeros_like(t), np.cos(t), np.sin(t)], axis=1)
    yz = math.sqrt(r * r - 0.36)                         # the crease circle's radius
    across = [(np.array([-0.05, 0, 0]) + yz * u, np.array([0.05, 0, 0]) + yz * u) for u in ring]
    own = [(np.array([-0.65, 0, 0]) + r * u, np.array([-0.55, 0, 0]) + r * u) for u in ring]
    a = np.array([p for p, _ in across + own])
    b = np.array([q for _, q in across + own])
    X, n, T, ref, A, B, valid, pins, _ = TR.refine_seeds(surf, np.full(len(a), SIL), a, b, 1e-8 * ev.scale,
                                                      math.radians(35))
    assert not valid[:12].any() and valid[12:].all()
    np.testing.assert_allclose(X[12:, 0], -0.6, atol=1e-9)   # on sphere A's great circle
    # projection, records, the pinned sheets, silhouette Newton, checks: no bisection
    assert calls[0] <= 16


def test_a_model_with_too_many_sites_for_records_still_has_its_creases_bisected(monkeypatch):
    from blobtree_ink.agents import sheets
    monkeypatch.setattr(sheets, "MAX_SITES", 0)
    bracketed = spy_brackets(monkeypatch)
    s = run(model_of(spheres("union")), View(eye=(4, -6, 3)), resolution=20)
    creases = [o for o in s.outlines() if o.kind == "crease"]
    assert creases and sum(bracketed) > 20
    assert off_circle(np.concatenate([o.points for o in creases]), *two_sphere_crease(C0, K * 1.5, C1, K * 1.2)) < 1e-6
