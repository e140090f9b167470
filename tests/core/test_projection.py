"""The damped Newton projection onto the iso-surface (model.projection), shared by the
polygoniser and the agents: points end on the surface, a step that overshoots is
retried halved in the next evaluation (no extra one), and ``steps`` bounds the number
of field evaluations."""
import numpy as np

from blobtree_ink import model as M
from blobtree_ink.agents.surface import Surface
from blobtree_ink.blackboard import polygonise as PG
from blobtree_ink.blackboard.view import View
from blobtree_ink.model.projection import newton, project
from blobtree_ink.model.tolerances import CONVERGED, field_tol

from test_massris import model_of

SPHERE = {"type": "point", "center": [0, 0, 0], "radius": 1.0}
D_ISO = np.sqrt(1 - 0.5 ** (1 / 3))        # (1 - d^2)^3 = 0.5: the surface's distance


class CountingEvaluator:
    """A real evaluator that counts its field_grad calls and the points they take."""

    def __init__(self, ev):
        self.ev, self.iso, self.scale, self.calls, self.sizes = ev, ev.iso, ev.scale, 0, []

    def field(self, P):
        return self.ev.field(P)

    def field_grad(self, P):
        self.calls += 1
        self.sizes.append(len(P))
        return self.ev.field_grad(P)


def start_points():
    rng = np.random.default_rng(3)
    d = rng.normal(size=(200, 3))
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    r = rng.uniform(0.15, 0.93, size=200)      # inside and outside; far out the gradient is tiny
    return d * r[:, None]


def test_points_end_on_the_sphere_within_the_evaluation_budget():
    ev = CountingEvaluator(M.Evaluator(model_of(SPHERE)))
    P = start_points()
    f, g = ev.field_grad(P)
    made = newton(ev, P, f, g, steps=12)
    assert made == ev.calls - 1 <= 12
    assert np.abs(f - 0.5).max() <= field_tol(0.5, CONVERGED)
    np.testing.assert_allclose(np.linalg.norm(P, axis=1), D_ISO, atol=1e-12)
    np.testing.assert_array_equal(f, ev.ev.field(P))           # f and g follow the points
    np.testing.assert_array_equal(g, ev.ev.field_grad(P)[1])


def test_an_overshooting_step_is_retried_halved_in_the_next_evaluation():
    # from d = 0.9 the gradient is small: the full Newton step jumps through the centre
    # to where |f - iso| is larger; it must not be taken, and the halved step costs no
    # evaluation of its own (each iteration evaluates once)
    ev = CountingEvaluator(M.Evaluator(model_of(SPHERE)))
    P = np.array([[0.9, 0.0, 0.0]])
    f, g = ev.field_grad(P)
    full = P - ((f - 0.5) / np.einsum("ij,ij->i", g, g))[:, None] * g
    assert abs(ev.ev.field(full)[0] - 0.5) > abs(f[0] - 0.5)     # the premise: it overshoots
    newton(ev, P, f, g, steps=20)
    assert ev.sizes == [1] * ev.calls
    assert abs(np.linalg.norm(P[0]) - D_ISO) < 1e-12
    assert ev.calls - 1 <= 12


def test_flat_points_stay_and_converged_points_are_not_evaluated_again():
    ev = CountingEvaluator(M.Evaluator(model_of(SPHERE)))
    P = np.array([[5.0, 0, 0], [D_ISO, 0, 0], [0.6, 0, 0]])      # empty space, on it, near it
    f, g = ev.field_grad(P)
    P0 = P.copy()
    newton(ev, P, f, g, steps=8)
    np.testing.assert_array_equal(P[0], P0[0])
    assert ev.calls > 2 and ev.sizes[1:] == [1] * (ev.calls - 1)     # only the third moves
    assert abs(f[2] - 0.5) <= field_tol(0.5, CONVERGED)


def test_the_polygoniser_and_the_agents_project_through_it():
    # one implementation: both callers' evaluations are newton's (plus their first)
    ev = CountingEvaluator(M.Evaluator(model_of(SPHERE)))
    P = start_points()
    Q = project(ev, P, steps=12)[0]
    first = ev.calls
    ev2 = CountingEvaluator(M.Evaluator(model_of(SPHERE)))
    P2 = P.copy()
    f2, g2 = ev2.field_grad(P2)
    newton(ev2, P2, f2, g2, steps=12)
    np.testing.assert_array_equal(Q, P2)
    assert first == ev2.calls
    surf = Surface(CountingEvaluator(M.Evaluator(model_of(SPHERE))), View(eye=(0, -6, 0)))
    R, f3, _ = surf.project(P, steps=12, max_step=0.3)
    ev3 = CountingEvaluator(M.Evaluator(model_of(SPHERE)))
    P3 = P.copy()
    f3, g3 = ev3.field_grad(P3)
    newton(ev3, P3, f3, g3, steps=12, max_step=0.3)
    np.testing.assert_array_equal(R, P3)
    assert surf.ev.calls == ev3.calls


def test_the_surface_box_is_sampled_once_per_evaluator():
    """Placing a view and polygonising both ask for the surface box: the evaluator keeps
    it (its plan is fixed), and callers get copies they may change."""
    R = 1.5
    ev = M.Evaluator(model_of({"type": "point", "center": [0.2, 0.0, -0.1], "radius": R}))
    lo, hi = PG.surface_box(ev)
    r = np.sqrt(1 - 0.5 ** (1 / 3)) * R                        # the sphere f = 0.5
    assert np.all(lo <= [0.2 - r, -r, -0.1 - r]) and np.all(hi >= [0.2 + r, r, -0.1 + r])
    assert np.all(hi - lo < 2 * r + 4 * (2 * R) / 47)           # padded by 1.5 of its 48 samples' cells
    sampled = ev.stats.points
    lo[:] = 0.0
    lo2, hi2 = PG.surface_box(ev)
    assert ev.stats.points == sampled                          # not sampled again
    assert np.all(lo2 < 0.2 - r) and np.array_equal(hi2, hi)  # and unchanged by the caller's edit
    PG.surface_box(ev, res=32)
    assert ev.stats.points > sampled                           # another sampling is its own


def full_sampling_box(ev, res, pad):
    """The surface box of every sample of the res^3 grid (what the coarse pass and the
    outward walk of layers must reproduce)."""
    lo, hi = ev.bounds
    axes = [np.linspace(lo[i], hi[i], res) for i in range(3)]
    X, Y, Z = np.meshgrid(*axes, indexing="ij")
    inside = (ev.field(np.stack([X.ravel(), Y.ravel(), Z.ravel()], axis=1)) >= ev.iso).reshape(res, res, res)
    cell = (hi - lo) / (res - 1)
    ext = [np.flatnonzero(inside.any(axis=tuple(j for j in range(3) if j != i)))[[0, -1]] for i in range(3)]
    slo = np.array([axes[i][ext[i][0]] for i in range(3)]) - pad * cell
    shi = np.array([axes[i][ext[i][1]] for i in range(3)]) + pad * cell
    return np.maximum(slo, lo - cell), np.minimum(shi, hi + cell)


def test_the_surface_box_is_that_of_every_sample_of_its_grid():
    """The walks inwards from the support box's faces give the box of sampling every
    point of the 48^3 grid, also for parts a sampling of every other point misses: a
    rod standing out of a ball between those samples, and a small ball apart from a
    big one."""
    ball = {"type": "point", "center": [0, 0, 0], "radius": 1.0}
    x = -1 + 25 * 2 / 47          # on odd samples of the 48 across the ball: between every other one
    rod = {"type": "segment", "a": [x, x, 0.2], "b": [x, x, 1.9], "radius": 0.06}
    big = {"type": "point", "center": [0, 0, 0], "radius": 1.6}
    small = {"type": "point", "center": [0.0, -1.0, 0.1], "radius": 0.2}
    for root, far in (({"type": "blend", "children": [ball, rod]}, (1, 2, 1.9)),
                      ({"type": "union", "children": [big, small]}, (0, 1, -0.9))):
        ev = M.Evaluator(model_of(root))
        lo, hi = PG.surface_box(ev)
        ref_lo, ref_hi = full_sampling_box(M.Evaluator(ev.model), 48, 1.5)
        np.testing.assert_array_equal(lo, ref_lo)
        np.testing.assert_array_equal(hi, ref_hi)
        end, axis, reach = far
        assert (hi if end else -lo)[axis] > (reach if end else -reach)     # the thin part is in the box
        blo, bhi = ev.bounds
        axes = [np.linspace(blo[i], bhi[i], 48)[::2] for i in range(3)]
        X = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, 3)
        on = X[ev.field(X) >= ev.iso, axis]
        assert (on.max() < reach) if end else (on.min() > reach)            # every other sample misses it


def test_a_flat_point_marches_towards_the_projection_of_its_anchor_row():
    # anchor_rows: a point in empty space (no gradient) moves towards the projection of
    # another point of the same batch, as if that projection were given as its anchor
    surf = Surface(M.Evaluator(model_of(SPHERE)), View(eye=(0, -6, 0)))
    P = np.array([[0.6, 0, 0], [5.0, 0.5, 0], [0, 3.0, 0], [0.2, 0.7, 0]])
    X, f, g = surf.project(P, anchor_rows=np.array([-1, 0, -1, -1]))
    A, fa, ga = surf.project(P[[0, 3]])
    np.testing.assert_array_equal(X[[0, 3]], A)
    np.testing.assert_array_equal(f[[0, 3]], fa)
    Y, fy, gy = surf.project(P[[1]], anchor=A[[0]])
    np.testing.assert_array_equal(X[1], Y[0])
    np.testing.assert_array_equal(g[1], gy[0])
    assert abs(np.linalg.norm(X[1]) - D_ISO) < 1e-12 and abs(f[1] - 0.5) <= field_tol(0.5, CONVERGED)
    np.testing.assert_array_equal(X[2], P[2])              # flat, no anchor: it stays
    assert f[2] == 0 and not g[2].any()


def test_a_crossing_stops_once_its_field_is_within_ftol():
    """refine_crossings: every crossing of the sphere along random segments ends with
    |f - iso| within ftol (or its bracket below 1e-9 of the segment: then on the sphere
    to that), evaluated no more after it got there; ftol = 0 runs each to the bracket."""
    ev = M.Evaluator(model_of(SPHERE))
    rng = np.random.default_rng(5)
    d = rng.normal(size=(300, 3))
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    A, B = d * rng.uniform(0.05, 0.42, (300, 1)), d * rng.uniform(0.48, 0.99, (300, 1))
    fA, fB = ev.field(A), ev.field(B)
    assert np.all(fA > 0.5) and np.all(fB < 0.5)
    for ftol in (0.0, 1e-6, 1e-11):
        counting = CountingEvaluator(ev)
        sizes = []

        def field(P, sizes=sizes):
            sizes.append(len(P))
            return ev.field(P)
        counting.field = field
        X = PG.refine_crossings(counting, A, B, fA.copy(), fB.copy(), ftol=ftol)
        err = np.abs(ev.field(X) - 0.5)
        # on the segment, and on the sphere to ftol or to the bracket's width
        np.testing.assert_allclose(np.cross(X, d), 0, atol=1e-15)
        assert np.all((err <= ftol) | (np.abs(np.linalg.norm(X, axis=1) - D_ISO) < 1e-9))
        if ftol == 1e-6:
            assert err.max() <= 1e-6 and err.max() > 1e-10      # stopped there, not run on
        evaluated = sum(sizes)
        if ftol == 0.0:
            full = evaluated
        else:
            assert evaluated < full
