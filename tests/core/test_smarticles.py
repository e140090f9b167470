"""Smarticles: steering on the surface, flocking, termination, hatching and stipples."""
import math

import numpy as np
import pytest

from blobtree_ink import model as M
from blobtree_ink.model import keyed
from blobtree_ink.model.marks import surface_marks
from blobtree_ink.strokes import layers, smarticles as sm
from blobtree_ink.strokes import paper as PA
from blobtree_ink.strokes import stipples as SP
from blobtree_ink.strokes import tone as TN
from blobtree_ink.strokes.data import Stroke
from blobtree_ink.strokes.paper import Paper

K = math.sqrt(1 - 0.5 ** (1 / 3))


def ev_of(root):
    return M.Evaluator(M.from_dict({"format": "blobtree-1", "root": root}))


def cylinder():
    return ev_of({"type": "segment", "a": [-4, 0, 0], "b": [4, 0, 0], "radius": 1.0})


def keys(n, salt=0):
    """The smarticles' own keys (model.keyed)."""
    return keyed.combine(np.arange(n, dtype=np.uint64), salt)


def ring_starts(r, n, x=0.0):
    t = np.linspace(0, 2 * np.pi, n, endpoint=False)
    return np.stack([np.full(n, x), r * np.cos(t), r * np.sin(t)], axis=1)


def test_paths_stay_on_the_surface_and_follow_the_principal_direction():
    ev = cylinder()
    r = K
    rules = sm.StrokeRules(max_steps=15, stop_on_curvature_sign=False)
    # dir2 (zero curvature) is the axis; dir1 goes around
    res = sm.run(ev, ring_starts(r, 12), layers.direction_field("dir2"), 0.05, sm.PRESETS["hatching"], rules,
                 keys(12))
    for p in res.paths:
        assert len(p) == 16
        f = ev.field(p)
        assert np.abs(f - 0.5).max() < 1e-9
        seg = np.diff(p, axis=0)
        cosang = np.abs(seg[:, 0]) / np.linalg.norm(seg, axis=1)
        assert cosang.min() > math.cos(math.radians(5))
    res = sm.run(ev, ring_starts(r, 6, x=1.0), layers.direction_field("dir1"), 0.05, sm.PRESETS["hatching"],
                 rules, keys(6))
    for p in res.paths:
        assert np.abs(p[:, 0] - 1.0).max() < 1e-6          # around the cylinder, not along it


def test_termination_rules_and_the_terminating_point_is_excluded():
    ev = ev_of({"type": "point", "center": [0, 0, 0], "radius": 1.0})
    r = K
    rules = sm.StrokeRules(max_steps=200, max_normal_angle=math.radians(30), stop_on_curvature_sign=False)
    res = sm.run(ev, np.array([[0, 0, r]]), layers.direction_field("axis", (1, 0, 0)), 0.02,
                 sm.PRESETS["hatching"], rules, keys(1))
    p, n = res.paths[0], res.normals[0]
    assert res.reasons[0] == "normal angle"
    angles = np.degrees(np.arccos(np.clip(n @ n[0], -1, 1)))
    assert angles.max() <= 30 and angles.max() > 27     # stopped just before the limit, not after
    rules = sm.StrokeRules(max_steps=200, max_length=0.1, max_normal_angle=math.pi, stop_on_curvature_sign=False)
    res = sm.run(ev, np.array([[0, 0, r]]), layers.direction_field("axis", (1, 0, 0)), 0.02,
                 sm.PRESETS["hatching"], rules, keys(1))
    L = np.linalg.norm(np.diff(res.paths[0], axis=0), axis=1).sum()
    assert res.reasons[0] == "length" and 0.08 <= L <= 0.1


def test_curvature_sign_change_ends_a_stroke():
    # a ball with a smooth dent on top (a negative-strength point): convex around, concave inside
    ev = ev_of({"type": "blend", "children": [{"type": "point", "center": [0, 0, 0], "radius": 2.0},
                                              {"type": "point", "center": [0, 0, 1.15], "radius": 0.8,
                                               "strength": -0.6}]})
    from blobtree_ink.agents.surface import Surface
    from blobtree_ink.model.curvature import curvature
    start = Surface(ev, None).project(np.array([[-0.75, 0.0, 0.5]]))[0]
    assert curvature(ev, start)["mean"][0] > 0
    assert curvature(ev, Surface(ev, None).project(np.array([[0.0, 0, 0.8]]))[0])["mean"][0] < 0
    rules = sm.StrokeRules(max_steps=400, max_normal_angle=math.pi, stop_on_curvature_sign=True)
    res = sm.run(ev, start, layers.direction_field("axis", (1, 0, 0)), 0.01, sm.PRESETS["hatching"], rules,
                 keys(1))
    assert res.reasons[0] == "curvature sign"
    last = res.paths[0][-1]
    assert curvature(ev, last[None])["mean"][0] > 0      # the convex side: the crossing point is excluded
    assert -0.75 < last[0] < 0.0                         # stopped at the dent's rim


def test_flocking_cohesion_converges_and_separation_keeps_apart():
    ev = cylinder()
    starts = np.array([[0, K * math.cos(a), K * math.sin(a)] for a in np.linspace(-0.6, 0.6, 6)])
    rules = sm.StrokeRules(max_steps=40, stop_on_curvature_sign=False, max_normal_angle=math.pi)
    field = layers.direction_field("dir2")
    spread = lambda res: np.ptp(np.array([p[-1] for p in res.paths])[:, 1:], axis=0).max()   # noqa: E731
    together = sm.run(ev, starts, field, 0.03, {"flow": 1.0, "cohesion": 3.0}, rules, keys(6), flock=np.zeros(6, int))
    apart = sm.run(ev, starts, field, 0.03, {"flow": 1.0, "separation": 3.0}, rules, keys(6), flock=np.zeros(6, int),
                   separation_radius=0.6)
    start_spread = np.ptp(starts[:, 1:], axis=0).max()
    assert spread(together) < 0.5 * start_spread
    assert spread(apart) > start_spread
    for res in (together, apart):
        for p in res.paths:
            assert np.abs(ev.field(p) - 0.5).max() < 1e-9


def _shadows(ev, light):
    """The light's shadows on a model, at marks of its own (strokes.tone.Shadows)."""
    nodes = surface_marks(ev, 0.05, 3)
    return TN.Shadows(ev, nodes.points, nodes.normals, light, 4 * ev.scale, 0.05)


def test_stipples_are_dots_on_the_surface_facing_the_eye_where_the_tone_wants_ink():
    ev = ev_of({"type": "point", "center": [0, 0, 0], "radius": 1.0})
    marks = surface_marks(ev, 0.03)
    assert len(marks) > 300
    eye = np.array([0.0, -6.0, 0.0])
    light = np.array([0.0, -1.0, 1.0]) / np.sqrt(2.0)
    dots = SP.stipples(ev, marks, Paper(eye, (0, 0, 0)), _shadows(ev, light), 0.02, 0.1, 0.7, radius=0.01)
    assert len(dots) > 100 and all(s.dots and len(s.points) == 1 for s in dots)
    assert len({s.mark for s in dots}) == len(dots)            # every dot its own mark
    P = np.concatenate([s.points for s in dots])
    assert np.abs(ev.field(P) - 0.5).max() < 1e-9
    N = P / np.linalg.norm(P, axis=1, keepdims=True)
    assert (P[:, 1] < 0.05).all()                              # only the side facing the eye
    t = TN.tone(TN.lambert(N, light), 0.1, 0.7)
    assert (t > 0).all()                                       # none in the highlight
    # darker, bigger and no sparser: a dark dot covers more of the room its nearest dot leaves
    R = np.array([s.radius[0] for s in dots])
    d = np.linalg.norm(P[:, None] - P[None], axis=2) + np.eye(len(P))
    fill = (R / d.min(axis=1)) ** 2
    dark, light_ = t > 0.8 * TN.DARKEST, t < 0.3 * TN.DARKEST
    assert dark.sum() > 20 and light_.sum() > 5
    assert np.median(R[dark]) > 1.5 * np.median(R[light_]) and np.median(fill[dark]) > 2 * np.median(fill[light_])


def test_stipples_never_touch_on_the_paper():
    """Drawn stipples never touch as the eye sees them, also where the surface turns
    away and dots apart on the surface crowd on the paper."""
    ev = ev_of({"type": "point", "center": [0, 0, 0], "radius": 1.0})
    marks = surface_marks(ev, 0.03)
    eye = np.array([0.0, -6.0, 0.0])
    light = np.array([0.0, -1.0, 1.0]) / np.sqrt(2.0)
    dots = SP.stipples(ev, marks, Paper(eye, (0, 0, 0)), _shadows(ev, light), 0.02, 0.1, 0.7, radius=0.01)
    P = np.concatenate([s.points for s in dots])
    R = np.array([s.radius[0] for s in dots])
    U, a = SP.on_paper(P, R, eye)
    d = np.linalg.norm(U[:, None] - U[None], axis=2) + np.eye(len(P)) * 1e9
    assert (d >= (a[:, None] + a[None]) * (1 - 1e-9)).all()


def test_spaced_keeps_the_points_taking_them_one_by_one_in_their_keys_order():
    """The rounds over all the points keep what taking them one at a time, highest key
    first, keeps (each keeping its own reach from points as dense as it or denser); a far
    point changes nothing; a point near one kept before is left out; ``first`` orders
    them instead of the keys."""
    rng = np.random.default_rng(3)
    P = np.column_stack([rng.random((400, 2)), np.zeros(400)])
    reach = rng.uniform(0.01, 0.03, 400)
    k = np.arange(400, dtype=np.uint64)
    keep = SP.spaced(P, reach, k)

    def one_by_one(order):
        kept = []
        for n in order:
            if all(np.linalg.norm(P[n] - P[m]) >= 2 * min(reach[n], reach[m]) for m in kept):
                kept.append(n)
        return sorted(kept)
    assert one_by_one(np.argsort(-keyed.uniform(k, SP.SPACING))) == np.flatnonzero(keep).tolist()
    assert 30 < keep.sum() < 390
    order = rng.permutation(400)
    by_first = SP.spaced(P, reach, k, first=np.argsort(order))
    assert one_by_one(order) == np.flatnonzero(by_first).tolist()
    far = SP.spaced(np.vstack([P, [[50.0, 0, 0]]]), np.append(reach, 0.05), np.arange(401, dtype=np.uint64))
    assert (far[:400] == keep).all() and far[400]
    first = int(np.flatnonzero(keep)[0])
    assert not SP.spaced(P, reach, k, P[first:first + 1] + [1e-3, 0, 0], reach[first:first + 1])[first]
    assert SP.spaced(np.zeros((0, 3)), np.zeros(0), np.zeros(0, np.uint64)).shape == (0,)


def test_a_stipple_layers_parts_keep_apart_on_the_paper():
    """A stipple layer drawn in parts keeps each part's dots apart on the paper from the
    dots the parts before chose (strokes.paper.Placed): a second part at the same marks
    adds no dot."""
    ev = ev_of({"type": "point", "center": [0, 0, 0], "radius": 1.0})
    marks = surface_marks(ev, 0.03)
    eye = np.array([0.0, -6.0, 0.0])
    paper, shadows = Paper(eye, (0, 0, 0)), _shadows(ev, (0.0, 0.0, -1.0))
    dots = PA.Placed()
    first = SP.stipples(ev, marks, paper, shadows, 0.02, 0.1, 0.7, radius=0.01, dots=dots)
    assert first and len(dots.places) >= len(first)
    n = len(dots.places)
    again = SP.stipples(ev, marks, paper, shadows, 0.02, 0.1, 0.7, radius=0.01, dots=dots)
    assert again == [] and len(dots.places) == n


def test_fitted_dots_shrink_smoothly_where_they_crowd_on_the_paper():
    """Two dots apart in space but nearly in line with the eye are drawn smaller, just
    not touching on the paper; a lone dot keeps its size; a small turn of the view
    changes the sizes a little, it does not make dots come or go."""
    eye = np.array([0.0, -10.0, 0.0])
    P = np.array([[0.0, 0.0, 0.0], [0.03, 1.0, 0.0], [3.0, 0.0, 0.0]])
    r = np.full(3, 0.05)
    f = SP.fitted(P, r, eye)
    U, a = SP.on_paper(P, f, eye)
    gap = np.linalg.norm(U[0] - U[1])
    assert f[2] == r[2] and f[0] < r[0] and f[1] < r[1]
    assert np.isclose(a[0] + a[1], gap / SP.STIPPLE_GAP)
    turned = SP.fitted(P, r, eye + [0.05, 0.0, 0.0])
    assert np.all(np.abs(turned - f) < 0.2 * f) and np.any(turned != f)
    # against a dot drawn before (which keeps its size), the new dot alone gives way
    drawn = [Stroke(np.array([[0.1, 1.0, 0.0]]), r[1:2], np.ones(1), dots=True)]
    g = SP.fitted(P[:1], r[:1], eye, drawn)
    Ud, ad = SP.on_paper(drawn[0].points, r[1:2], eye)
    assert 0 < g[0] < r[0]
    assert np.isclose(SP.on_paper(P[:1], g, eye)[1][0] + ad[0], np.linalg.norm(U[0] - Ud[0]) / SP.STIPPLE_GAP)


def test_fitted_dots_keep_clear_of_the_lines_drawn():
    """A dot beside a line is drawn finer, just not touching it on the paper (the line's
    nearest point may lie between two of its points); one on the line is not drawn;
    one far from it keeps its size; a line of one point (a dot) is no line."""
    eye = np.array([0.0, -10.0, 0.0])
    line = Stroke(np.array([[-1.0, 0.0, 0.0], [1.0, 0.0, 0.0]]), np.full(2, 0.02), np.ones(2))
    P = np.array([[0.3, 0.0, 0.06], [0.5, 0.0, 0.0], [0.0, 0.0, 2.0]])
    r = np.full(3, 0.05)
    f = SP.fitted(P, r, eye, lines=[line])
    assert 0 < f[0] < r[0] and f[1] == 0 and f[2] == r[2]
    U, a = SP.on_paper(P[:1], f[:1], eye)
    foot, b = SP.on_paper(np.array([[0.3, 0.0, 0.0]]), [0.02], eye)
    # (the line's radius on the paper is its ends', a little further off than the foot)
    assert np.isclose(a[0] + b[0], np.linalg.norm(U[0] - foot[0]) / SP.STIPPLE_GAP, rtol=1e-2)
    dot = Stroke(np.array([[0.3, 0.0, 0.0]]), np.full(1, 0.02), np.ones(1), dots=True)
    np.testing.assert_array_equal(SP.fitted(P, r, eye, lines=[dot]), SP.fitted(P, r, eye))


def sphere_ev():
    return ev_of({"type": "point", "center": [0, 0, 0], "radius": 1.0})


def test_seek_reaches_its_target_on_the_surface():
    ev = sphere_ev()
    target = np.array([0.0, K, 0.0])
    rules = sm.StrokeRules(max_steps=60, max_normal_angle=math.pi, stop_on_curvature_sign=False)
    res = sm.run(ev, np.array([[K, 0.0, 0.0]]), layers.direction_field("dir1"), 0.02, {"seek": 1.0}, rules,
                 keys(1), target=target)
    d = np.linalg.norm(res.paths[0] - target, axis=1)
    assert d[-1] < 0.03 and d[0] > 0.6
    assert np.abs(ev.field(res.paths[0]) - 0.5).max() < 1e-6
    with pytest.raises(ValueError, match="seek behaviour needs a target"):
        sm.run(ev, np.array([[K, 0.0, 0.0]]), layers.direction_field("dir1"), 0.02, {"seek": 1.0}, rules,
               keys(1))


def test_path_following_keeps_a_wandering_smarticle_on_its_path():
    ev = sphere_ev()
    t = np.linspace(0, np.pi, 200)
    path = np.stack([K * np.cos(t), K * np.sin(t), 0 * t], 1)          # half the equator
    rules = sm.StrokeRules(max_steps=60, max_normal_angle=math.pi, stop_on_curvature_sign=False)
    start = np.array([[K, 0.0, 0.0]])
    head = np.array([[0.0, 1.0, 0.0]])

    def worst(weights):
        res = sm.run(ev, start, layers.direction_field("straight"), 0.01, weights, rules,
                     keys(1, 3), headings=head, path=path)
        return sm.nearest_distance(res.paths[0], path).max()
    follow = worst({"wander": 0.6, "path": 2.0})
    drift = worst({"wander": 0.6})
    assert follow < 0.02 and drift > 3 * follow


def test_containment_steers_back_before_leaving_the_region():
    from blobtree_ink.agents import Region
    ev = sphere_ev()
    top = np.array([0.0, 0.0, K])
    region = Region(sphere=(top, 0.15))
    rules = sm.StrokeRules(max_steps=150, max_normal_angle=math.pi, stop_on_curvature_sign=False, region=region)
    kept = sm.run(ev, top[None], layers.direction_field("dir1"), 0.01, {"wander": 0.5, "containment": 3.0}, rules,
                  keys(1))
    free = sm.run(ev, top[None], layers.direction_field("dir1"), 0.01, {"wander": 0.5}, rules, keys(1))
    assert kept.reasons[0] == "steps" and len(kept.paths[0]) == 151
    assert region.contains(kept.paths[0]).all()
    assert free.reasons[0] == "left region" and len(free.paths[0]) < 100


def test_a_start_that_does_not_reach_the_surface_draws_nothing():
    """A start too far off the surface for its Newton steps (here deep in empty space
    beside a sphere) gets an empty path; the others are traced."""
    ev = M.Evaluator(M.from_dict({"format": "blobtree-1", "root": {"type": "point", "center": [0, 0, 0],
                                                                   "radius": 1.0}}))
    starts = np.array([[0.0, -0.6, 0.0], [0.0, -50.0, 0.0]])
    res = sm.run(ev, starts, layers.direction_field("dir1"), 0.05, sm.PRESETS["hatching"],
                 sm.StrokeRules(max_steps=5), keys(2))
    assert len(res.paths[0]) > 3 and res.paths[1].shape == (0, 3) and res.reasons[1] == "lost surface"
    assert np.abs(ev.field(res.paths[0]) - 0.5).max() < 1e-6


def test_a_kept_heading_steers_as_strongly_as_a_principal_direction():
    """Where the principal directions mean nothing (or swap), and in the "straight"
    field, the flow is the unit heading, whatever the smarticle's speed: it weighs as
    much as a principal direction against a flock's wander and alignment."""
    P = np.array([[0.0, 1.0, 0.0], [0.0, 0.0, 1.0]])
    N = P.copy()
    V = 0.01 * np.array([[0.0, 0.0, 1.0], [0.0, 1.0, 0.0]])         # across the axis (dir1 runs along it)
    c = {"velocity": V, "k1": np.array([1.0, 0.5]), "k2": np.array([0.0, 0.5]),
         "dir1": np.array([[1.0, 0.0, 0.0], [1.0, 0.0, 0.0]]), "dir2": np.array([[0.0, 0.0, 1.0], [0.0, 1.0, 0.0]])}
    d = layers.direction_field("dir1")(P, N, c)
    np.testing.assert_allclose(d, [[0, 0, 1.0], [0, 1.0, 0]])      # across: the heading kept; isotropic: too
    np.testing.assert_allclose(layers.direction_field("straight")(P, N, c), [[0, 0, 1.0], [0, 1.0, 0]])
    assert not np.any(layers.direction_field("straight")(P, N, dict(c, velocity=np.zeros((2, 3)))))


def test_flocked_hatching_turns_smoothly(load_example):
    """The flocked style's strokes on the jug turn less than 60 degrees from one step to
    the next: no zigzag where its principal directions mean nothing."""
    from blobtree_ink import pipeline as PL
    from helpers import job_for
    result = PL.Illustration(job_for(load_example, "jug", "flocked", res=14)).run()
    turns = []
    for s in result.strokes.layers["Hatching"]:
        d = np.diff(s.points, axis=0)
        d /= np.linalg.norm(d, axis=1, keepdims=True)
        turns.append(np.degrees(np.arccos(np.clip(np.einsum("ij,ij->i", d[1:], d[:-1]), -1, 1))))
    turns = np.concatenate(turns)
    assert len(turns) > 1000 and turns.max() < 60, np.sort(turns)[-10:]
