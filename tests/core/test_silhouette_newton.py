"""The silhouette corrector by Newton's method (Surface.silhouette_newton) and how a
trace step uses it: exact silhouette points in a few evaluations, and no step across
a crease (the bracketing ends a silhouette there)."""
import functools
import math

import numpy as np

from blobtree_ink.agents.surface import SIL, Surface
from blobtree_ink.agents.tracer import trace_step
from blobtree_ink.blackboard.view import View
from blobtree_ink.model.branches import apart

from test_massris import K, model_of
from blobtree_ink import model as M


def sphere_surface(view):
    ev = M.Evaluator(model_of({"type": "point", "center": [0, 0, 0], "radius": 1.0}))
    return Surface(ev, view)


def silhouette_circle(eye, r=K):
    """The silhouette circle of the sphere of radius r at the origin seen from eye:
    its centre, radius, the unit axis towards the eye and two unit vectors across it."""
    d = np.linalg.norm(eye)
    axis = eye / d
    u = np.cross(axis, [1.0, 0, 0])
    u /= np.linalg.norm(u)
    return r * r / d * axis, r * math.sqrt(1 - r * r / (d * d)), axis, u, np.cross(axis, u)


def two_balls():
    """Overlapping balls (radii 1.5 and 1.2, centres 0.9 apart on x) and their crease
    circle's plane x = xc and radius rc."""
    c1 = np.array([0.9, 0, 0])
    ev = M.Evaluator(model_of({"type": "union", "children": [
        {"type": "point", "center": [0, 0, 0], "radius": 1.5},
        {"type": "point", "center": list(c1), "radius": 1.2}]}))
    r0, r1 = K * 1.5, K * 1.2
    xc = (r0 ** 2 - r1 ** 2 + 0.81) / 1.8
    return ev, c1, r0, r1, xc, math.sqrt(r0 ** 2 - xc ** 2)


def test_newton_lands_on_the_exact_silhouette_circle_in_the_plane_across_the_tangent():
    r = K
    eye = np.array([0.0, -5.0, 1.0])
    surf = sphere_surface(View(eye=tuple(eye)))
    centre, rad, axis, u, w = silhouette_circle(eye, r)
    a = np.linspace(0, 2 * math.pi, 40, endpoint=False)
    on = centre + rad * (np.cos(a)[:, None] * u + np.sin(a)[:, None] * w)
    T = -np.sin(a)[:, None] * u + np.cos(a)[:, None] * w          # along the circle
    Q = on + 0.05 * T + 0.03 * axis                                 # a predictor off the circle
    X, _, G, Tn, ok, bend = surf.silhouette_newton(Q, T, 0.2, 1e-10)
    assert ok.all()
    # the tangent handed on is the circle's at X, turned along T
    t = np.cross(axis, X - centre)
    t /= np.linalg.norm(t, axis=1, keepdims=True)
    np.testing.assert_allclose(np.abs(np.einsum("ij,ij->i", Tn, t)), 1.0, atol=1e-6)
    assert np.all(np.einsum("ij,ij->i", Tn, T) > 0)
    np.testing.assert_allclose(np.linalg.norm(X, axis=1), r, atol=1e-12)
    n = surf.normals(surf.ev.field_grad(X)[1])
    v = surf.view.towards_eye(X)
    assert np.abs(np.einsum("ij,ij->i", n, v)).max() < 1e-10
    np.testing.assert_allclose(np.einsum("ij,ij->i", X - Q, T), 0.0, atol=1e-12)
    # out of reach: the same points with a reach shorter than the distance to the circle
    _, _, _, _, near, _ = surf.silhouette_newton(Q, T, 0.01, 1e-10)
    assert not near.any()


def test_newton_hands_back_the_hessian_times_the_step_from_a_point():
    """With ``back``, the corrector returns H (X - back) at each converged X (the trace
    step predicts the gradient at its start from it): on the unit-radius point
    primitive f = (1 - |x|^2)^3, H = -6 [u^2 I - 4 u x x^T] with u = 1 - |x|^2, to
    first order in the difference step; and the field and gradient at X itself (the
    trace step's new point needs no evaluation of its own)."""
    eye = np.array([0.0, -5.0, 1.0])
    surf = sphere_surface(View(eye=tuple(eye)))
    centre, rad, axis, u, w = silhouette_circle(eye)
    a = np.linspace(0, 2 * math.pi, 24, endpoint=False)
    on = centre + rad * (np.cos(a)[:, None] * u + np.sin(a)[:, None] * w)
    T = -np.sin(a)[:, None] * u + np.cos(a)[:, None] * w
    P = on - 0.05 * T                                               # where a step started
    X, F, G, Tn, ok, bend = surf.silhouette_newton(on + 0.05 * T + 0.03 * axis, T, 0.2, 1e-10, back=P)
    assert ok.all()
    f, g = surf.ev.field_grad(X)
    assert np.array_equal(F, f) and np.array_equal(G, g)
    uu = 1 - np.einsum("ij,ij->i", X, X)
    D = X - P
    exact = -6 * (uu[:, None] ** 2 * D - 4 * uu[:, None] * X * np.einsum("ij,ij->i", X, D)[:, None])
    err = np.abs(bend - exact).max()
    assert err < 1e-4 * np.abs(exact).max()
    assert err > 0                                                  # a difference, not the exact formula
    # without back there is none
    assert surf.silhouette_newton(on + 0.05 * T, T, 0.2, 1e-10)[5] is None


def test_an_orthographic_view_too():
    surf = sphere_surface(View(direction=(0.0, 1.0, 0.0)))
    a = np.linspace(0, 2 * math.pi, 12, endpoint=False)
    on = K * np.stack([np.cos(a), np.zeros_like(a), np.sin(a)], axis=1)
    T = np.stack([-np.sin(a), np.zeros_like(a), np.cos(a)], axis=1)
    X, _, _, _, ok, _ = surf.silhouette_newton(on + 0.04 * T + [0, 0.05, 0], T, 0.2, 1e-10)
    assert ok.all()
    assert np.abs(X[:, 1]).max() < 1e-10                           # the great circle facing y
    np.testing.assert_allclose(np.linalg.norm(X, axis=1), K, atol=1e-12)


def test_a_silhouette_step_is_not_taken_across_a_crease():
    """Two overlapping balls: a step from ball 1's silhouette towards and over the crease
    circle would land Newton on the other ball's sheet; the step is refused (the caller
    halves it, and past its shortest step the silhouette ends there), and no bracketing
    takes it instead (its brackets may lie wholly on the far sheet): the point stays put."""
    ev, c1, r0, r1, xc, zc = two_balls()
    surf = Surface(ev, View(direction=(0.0, 1.0, 0.0)))
    # ball 1's silhouette (orthographic along y): the circle y = 0 around c1, in x-z;
    # it meets the crease circle (x = x_c) at z = +-zc
    ang = math.atan2(zc, xc - 0.9) - 0.15                           # on ball 1, 0.15 rad short of the crease
    P = np.array([[0.9 + r1 * math.cos(ang), 0.0, r1 * math.sin(ang)]])
    T = np.array([[-math.sin(ang), 0.0, math.cos(ang)]])            # towards the crease
    nP = (P - c1) / r1
    h = np.array([0.4])
    kinds = np.array([SIL])
    st = trace_step(surf, kinds, P, T, np.zeros((1, 3)), h, 1e-10, math.radians(35), nP)
    assert not st.ok[0]
    np.testing.assert_array_equal(st.X, P)
    # a short step stays on ball 1's silhouette
    st = trace_step(surf, kinds, P, T, np.zeros((1, 3)), np.array([0.02]), 1e-10, math.radians(35), nP)
    assert st.ok[0]
    np.testing.assert_allclose(np.linalg.norm(st.X[0] - c1), r1, atol=1e-9)
    assert abs(st.X[0, 1]) < 1e-9


def test_silhouette_seeds_are_refined_by_newton_and_one_across_a_crease_is_not():
    """refine_seeds settles a silhouette bracket by Newton's method in the plane through
    the bracket across the outline: the seed is on the sphere and on its silhouette to
    rounding, between the bracket's ends, with the circle's tangent. A bracket across the
    crease of two overlapping balls (where n.v jumps through zero without a silhouette
    between the ends) yields no seed."""
    from blobtree_ink.agents.tracer import refine_seeds
    eye = np.array([0.0, -5.0, 1.0])
    surf = sphere_surface(View(eye=tuple(eye)))
    centre, rad, axis, u, w = silhouette_circle(eye)
    a = np.linspace(0, 2 * math.pi, 16, endpoint=False)
    radial = np.cos(a)[:, None] * u + np.sin(a)[:, None] * w
    on = centre + rad * radial
    # polygon-edge-like brackets: ends off the circle on either side, off the surface
    A = on + 0.08 * radial + 0.05 * axis
    B = on - 0.1 * radial - 0.04 * axis + 0.02 * np.cross(axis, radial)
    kinds = np.full(len(A), SIL)
    X, n, T, ref, A2, B2, valid, _, _ = refine_seeds(surf, kinds, A, B, 1e-10, math.radians(35))
    assert valid.all()
    np.testing.assert_allclose(np.linalg.norm(X, axis=1), K, atol=1e-12)
    v = surf.view.towards_eye(X)
    assert np.abs(np.einsum("ij,ij->i", n, v)).max() < 1e-10
    t = np.cross(axis, X - centre)
    t /= np.linalg.norm(t, axis=1, keepdims=True)
    np.testing.assert_allclose(np.abs(np.einsum("ij,ij->i", T, t)), 1.0, atol=1e-6)
    np.testing.assert_allclose(A2, X)                       # a Newton seed's bracket is its point

    # two overlapping balls seen along x: at the top of their crease circle n.v jumps
    # from about -0.8 (ball 0) to +0.66 (ball 1); the balls' own silhouettes (x = 0 and
    # x = 0.9) are further away than the bracket is long
    ev, c1, r0, r1, xc, zc = two_balls()
    s2 = Surface(ev, View(direction=(1.0, 0.0, 0.0)))
    p = np.array([xc, 0.0, zc])
    jump = p / r0 - (p - c1) / r1
    A, B = p - 0.05 * jump, p + 0.05 * jump                  # ball 0's side, ball 1's side
    nv = [s2.view.towards_eye(q[None])[0] @ (q - c) / r for q, c, r in ((p, 0 * c1, r0), (p, c1, r1))]
    assert nv[0] < -0.5 and nv[1] > 0.5
    X, n, T, ref, _, _, valid, _, _ = refine_seeds(s2, np.array([SIL]), A[None], B[None], 1e-10, math.radians(35))
    assert not valid[0]


def test_a_crease_step_newton_cannot_settle_is_retried_shorter_before_it_is_bracketed(monkeypatch):
    """Two overlapping balls and a small third one over their crease circle, a little
    ahead: a crease step whose end lands under the third ball (the sheets' meeting is
    no crease there) is not settled by the sheets' Newton. With a retry left it is not
    bracketed (the caller halves it; no bracketing batch runs) and the point stays put;
    without one it is bracketed. The halved step settles on the crease circle."""
    import blobtree_ink.agents.tracer as tracer_mod
    from blobtree_ink.agents import sheets
    from blobtree_ink.agents.surface import CREASE
    c1 = np.array([0.9, 0, 0])
    r0, r1 = K * 1.5, K * 1.2
    xc = (r0 ** 2 - r1 ** 2 + 0.81) / 1.8
    rc = math.sqrt(r0 ** 2 - xc ** 2)
    ev = M.Evaluator(model_of({"type": "union", "children": [
        {"type": "point", "center": [0, 0, 0], "radius": 1.5},
        {"type": "point", "center": list(c1), "radius": 1.2},
        {"type": "point", "center": [xc + 0.1, rc * math.cos(0.5), rc * math.sin(0.5)], "radius": 0.25}]}))
    surf = Surface(ev, View(direction=(0.0, 1.0, 0.0)))
    P = np.array([[xc, rc, 0.0]])                                   # on the crease circle (plane x = xc)
    T = np.array([[0.0, 0.0, 1.0]])                                 # along it, towards the third ball
    ref = P / r0 - (P - c1) / r1
    A, _, _ = surf.project(P + [[-0.02, 0, 0]])
    B, _, _ = surf.project(P + [[0.02, 0, 0]])
    pins = sheets.record_ends(surf, A, B)[0]
    assert apart(pins[:, 0], pins[:, 1]).all()
    calls = []
    real = tracer_mod._bracket_step

    def spy(surface, kinds, *args):
        calls.append(len(kinds))
        return real(surface, kinds, *args)

    monkeypatch.setattr(tracer_mod, "_bracket_step", spy)
    step = functools.partial(trace_step, surf, np.array([CREASE]), P, T, ref, tol=1e-10,
                             crease_angle=math.radians(35), pins=pins, team=(A, B))
    st = step(np.array([0.2]), retry=np.array([True]))
    assert not st.ok[0] and calls == []
    np.testing.assert_array_equal(st.X, P)
    step(np.array([0.2]), retry=np.array([False]))
    assert calls == [1]
    st = step(np.array([0.1]), retry=np.array([True]))
    assert st.ok[0] and calls == [1]
    np.testing.assert_allclose([np.linalg.norm(st.X[0]), np.linalg.norm(st.X[0] - c1)], [r0, r1], atol=1e-9)
    assert st.X[0, 2] > 0.09


def test_a_newton_update_solves_each_system_and_gives_up_on_singular_or_far_ones():
    from blobtree_ink.agents.surface import newton_update
    rng = np.random.default_rng(4)
    m = 200
    J = rng.normal(size=(m, 3, 3))
    r = rng.normal(size=(m, 3))
    J[3] = [[1.0, 0, 0], [2.0, 0, 0], [0, 0, 1.0]]             # rows 0 and 1 parallel: singular
    J[4] = 1e-3 * np.eye(3)                                   # small but well conditioned: solved
    r[5] = 0.0                                                # no step at all: converged
    X, Q = np.zeros((m, 3)), np.zeros((m, 3))
    ok = np.zeros(m, bool)
    reach = np.full(m, 1e6)
    reach[6] = 1e-3                                           # its step is cut to half the reach
    live = newton_update(X, Q, np.arange(m), J, r, reach, 1e-12, ok)
    exact = np.linalg.solve(np.where(np.arange(m)[:, None, None] == 3, np.eye(3), J), r[:, :, None])[:, :, 0]
    solved = np.setdiff1d(np.arange(m), [3, 5, 6])
    np.testing.assert_allclose(X[solved], exact[solved], rtol=1e-10, atol=1e-12 * np.abs(exact).max())
    assert np.array_equal(X[3], np.zeros(3)) and 3 not in live and not ok[3]
    assert ok[5] and 5 not in live
    assert np.isclose(np.linalg.norm(X[6]), 0.5e-3) and np.allclose(X[6] / 0.5e-3, exact[6] / np.linalg.norm(exact[6]))
    assert 6 in live and list(live) == sorted(set(range(m)) - {3, 5})
