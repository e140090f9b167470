"""Bisections that pause (agents.bisection.bisect_some) and seeds that go back on the
blackboard with their narrowed brackets (agents.traces.Traces._requeue): a seed's refinement
is one agent action per system iteration, not a batch held up by its slowest row."""
import math

import numpy as np

from blobtree_ink.agents import Session, Settings
from blobtree_ink.agents import traces as TS
from blobtree_ink.agents.bisection import bisect, bisect_some
from blobtree_ink.agents.surface import SIL
from blobtree_ink.blackboard.view import View

from test_massris import K, coverage, polyline_samples
from test_silhouette_newton import silhouette_circle, sphere_surface


def brackets_across_the_silhouette(eye, n=24):
    """Brackets across a unit-ball sphere's silhouette circle, their ends on the
    sphere on either side of it, at uneven distances (regula falsi needs several
    iterations); with the circle's centre, radius and axis."""
    surf = sphere_surface(View(eye=tuple(eye)))
    centre, rad, axis, u, w = silhouette_circle(eye)
    a = np.linspace(0, 2 * math.pi, n, endpoint=False)
    radial = np.cos(a)[:, None] * u + np.sin(a)[:, None] * w
    on = centre + rad * radial
    t = np.linspace(0.05, 0.3, n)[:, None]
    A, _, _ = surf.project(on - t * axis)          # turned away from the eye
    B, _, _ = surf.project(on + 0.4 * t * axis)    # towards it
    return surf, A, B, (centre, rad, axis)


def test_a_paused_bisection_goes_on_from_its_narrowed_brackets_to_the_same_crossings():
    eye = np.array([0.0, -5.0, 1.0])
    surf, A, B, (centre, rad, axis) = brackets_across_the_silhouette(eye)
    kinds, ref, tol = np.full(len(A), SIL), np.zeros((len(A), 3)), 1e-10
    full = bisect(surf, kinds, A, B, ref, tol)
    assert full[-1].all()
    (X, _, A2, B2, _, _, valid), opened = bisect_some(surf, kinds, A, B, ref, tol, 7, pause=True)
    assert opened.sum() >= 5 and valid.sum() >= 10 and not valid[opened].any()
    # the open brackets are narrower, their ends on the sphere and on either side of the silhouette
    w0, w2 = np.linalg.norm(B - A, axis=1), np.linalg.norm(B2 - A2, axis=1)
    assert np.all(w2[opened] < 0.6 * w0[opened])
    np.testing.assert_allclose(np.linalg.norm(A2[opened], axis=1), K, atol=1e-6)
    s = lambda P: np.einsum("ij,ij->i", surf.normals(surf.ev.field_grad(P)[1]), surf.view.towards_eye(P))
    assert np.all(s(A2[opened]) * s(B2[opened]) < 0)
    # going on from there lands where the bisection run to the end did, on the circle
    rest = bisect(surf, kinds[opened], A2[opened], B2[opened], ref[opened], tol)
    assert rest[-1].all()
    np.testing.assert_allclose(rest[0], full[0][opened], atol=1e-8)
    np.testing.assert_allclose(np.linalg.norm(rest[0], axis=1), K, atol=1e-12)
    np.testing.assert_allclose(np.linalg.norm(rest[0] - centre, axis=1), rad, atol=1e-8)
    # the ones that settled within the seven iterations are the same crossings, on
    # the surface to rounding (their last trial points projected the rest of the way)
    np.testing.assert_allclose(X[valid], full[0][valid], atol=1e-8)
    assert np.abs(surf.ev.field(X[valid]) - surf.iso).max() < 1e-13


def heart_outlines(load_example, monkeypatch, pause, rounds=TS.SEED_ROUNDS):
    monkeypatch.setattr(TS, "SEED_PAUSE", pause)
    monkeypatch.setattr(TS, "SEED_ROUNDS", rounds)
    s = Session(load_example("heart"), View(eye=(4.0, -6.0, 3.0)), Settings(resolution=16))
    s.request("OUTLINES")
    s.run()
    assert s.done
    return s


def test_seeds_left_open_go_back_on_the_blackboard_and_the_outlines_are_the_same(load_example, monkeypatch):
    whole = heart_outlines(load_example, monkeypatch, 60)
    paused = heart_outlines(load_example, monkeypatch, 1)
    f = paused.bb.feat
    again = f["rounds"][:f.n] > 0
    assert again.sum() >= 5 and not (whole.bb.feat["rounds"][:whole.bb.feat.n] > 0).any()
    # requeued seeds are the same feature points: a voxel counts each once (equation 3's mu)
    first = np.bincount(f["voxel"][:f.n][~again], minlength=paused.bb.vox.n)
    np.testing.assert_array_equal(paused.bb.vox["features"][:paused.bb.vox.n], first)
    # the same outlines: as long, each within a trace step of the other
    pts = [np.concatenate([polyline_samples(o) for o in s.outlines() if o.kind == "silhouette"])
           for s in (whole, paused)]
    near = whole.step_len
    assert coverage(pts[0], pts[1], near)[1] > 0.98 and coverage(pts[1], pts[0], near)[1] > 0.98
    # and as long to within the overlaps where traces started in different iterations
    # meet, and the heart's tight turns (a silhouette curling within a step), where the
    # order the traces reach them in decides how far each crawls (the detail phase's
    # explorers start later in one than in the other): 0.4-2.1 % on this heart
    lengths = [sum(o.length for o in s.outlines()) for s in (whole, paused)]
    assert abs(lengths[1] - lengths[0]) < 0.03 * lengths[0]


def test_a_seed_open_after_its_last_round_is_dropped(load_example, monkeypatch):
    s = heart_outlines(load_example, monkeypatch, 1, rounds=1)
    f = s.bb.feat
    assert not (f["rounds"][:f.n] > 0).any()
    assert s.outlines()                      # the seeds Newton settles still start traces


def test_a_seed_whose_bracket_did_not_narrow_is_dropped():
    """_requeue puts a paused seed back with its narrowed bracket, one round more, but
    not one whose bracket kept NARROWED of its width or more in the round (a stuck
    bisection), nor one at its last round."""
    from test_massris import model_of
    s = Session(model_of({"type": "point", "center": [0, 0, 0], "radius": 1.0}), View(eye=(0.0, -5.0, 1.0)),
                Settings(resolution=8))
    f = s.bb.feat
    a = np.array([[K, 0.0, 0.0], [0.0, 0.0, K], [-K, 0.0, 0.0], [0.0, 0.0, -K]])
    b = a + [0.0, -0.2, 0.0]
    ids = s.bb.add_features(0.5 * (a + b), a, b, "silhouette")
    f["rounds"][ids[3]] = TS.SEED_ROUNDS - 1
    n0 = f.n
    # the first bracket narrowed to a half, the second to just under NARROWED, the
    # third not quite (it is stuck), the fourth narrowed but is at its last round
    frac = np.array([0.5, TS.NARROWED - 0.01, TS.NARROWED + 0.01, 0.5])
    A, B = a, a + frac[:, None] * (b - a)
    s.traces._requeue(ids, A, B)
    assert f.n == n0 + 2
    np.testing.assert_array_equal(f["a"][n0:f.n], A[:2])
    np.testing.assert_array_equal(f["b"][n0:f.n], B[:2])
    np.testing.assert_array_equal(f["rounds"][n0:f.n], [1, 1])
