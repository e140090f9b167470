"""Hidden-line removal against the exact surface: a sphere behind a sphere."""
import numpy as np

from blobtree_ink import model as M
from blobtree_ink.agents import Outline
from blobtree_ink.strokes import StrokeSet, split_visible, visible
from blobtree_ink.strokes.visibility import split_visible_many


def two_balls():
    return M.Evaluator(M.from_dict({"format": "blobtree-1", "root": {"type": "union", "children": [
        {"type": "point", "center": [0, 0, 0], "radius": 1.0},
        {"type": "point", "center": [0, 3, 0], "radius": 1.0}]}}))


def test_a_ball_hides_what_is_behind_it():
    ev = two_balls()
    eye = np.array([0.0, -10.0, 0.0])            # looking along +y: the first ball hides the second's middle
    r = 0.4543
    behind = np.array([[0, 3 - r, 0], [0.1, 3 - r + 0.02, 0.05]])       # the second ball's front, behind ball 1
    aside = np.array([[3.0, 3.0, 0.0]])                                 # empty space off to the side
    front = np.array([[0, -r, 0]])
    v = visible(ev, np.concatenate([behind, aside, front]), eye)
    np.testing.assert_array_equal(v, [False, False, True, True])


def test_strokes_are_split_where_visibility_changes():
    ev = two_balls()
    eye = np.array([0.0, -10.0, 0.0])
    # a line across the second ball's front: hidden in the middle (behind ball 1), visible at the ends
    x = np.linspace(-1.2, 1.2, 49)
    pts = np.stack([x, np.full_like(x, 3 - 0.46), np.zeros_like(x)], axis=1)
    runs = split_visible(ev, pts, eye)
    assert len(runs) == 2
    (a0, a1), (b0, b1) = runs
    assert a0 == 0 and b1 == len(x)
    hidden = x[a1:b0]
    # the shadow of ball 1 (radius r at distance 10 from the eye) on the plane y = 2.54
    r = 0.4543
    assert hidden.min() > -0.6 and hidden.max() < 0.6 and hidden.min() < -0.4 and hidden.max() > 0.4


def test_many_strokes_are_split_as_each_alone():
    """In one batch, each polyline's visible runs are those it has alone: a run never
    continues from one polyline into the next, and one shorter than min_points is
    dropped (empty and one-point polylines included)."""
    ev = two_balls()
    eye = np.array([0.0, -10.0, 0.0])
    x = np.linspace(-1.2, 1.2, 49)
    across = np.stack([x, np.full_like(x, 3 - 0.46), np.zeros_like(x)], axis=1)
    front = np.stack([0.3 * x, np.full_like(x, -1.0), np.zeros_like(x)], axis=1)      # between the eye and ball 1
    lines = [across, front[:5], np.zeros((0, 3)), across[20:29], front[:1], across[::-1], front[:2]]
    for m in (1, 2, 3):
        assert split_visible_many(ev, lines, eye, min_points=m) == \
            [split_visible_many(ev, [p], eye, min_points=m)[0] if len(p) else [] for p in lines]
    got = split_visible_many(ev, lines, eye)
    assert got[1] == [(0, 5)] and got[2] == [] and got[3] == [] and got[4] == [] and got[6] == [(0, 2)]
    assert got[5] == [(0, len(x) - got[0][1][0]), (len(x) - got[0][0][1], len(x))]


def test_stroke_set_from_outlines():
    o = Outline("silhouette", np.zeros((3, 3)), np.ones((3, 3)), True)
    s = StrokeSet.from_outlines([o, Outline("crease", np.zeros((2, 3)), np.ones((2, 3)), False)], 0.01)
    assert s.count("Silhouette") == 1 and s.count("Crease") == 1 and s.count() == 2
    st = s.layers["Silhouette"][0]
    assert st.cyclic and np.all(st.radius == 0.01) and np.all(st.opacity == 1.0)


def test_only_samples_inside_the_surface_box_are_evaluated():
    """A ray is marched from its point to where it leaves the surface's box: the samples
    a batch would take past that end are not evaluated (and the verdicts are those of
    marching every ray to its end)."""
    from blobtree_ink.blackboard.polygonise import surface_box
    ev = two_balls()
    lo, hi = surface_box(ev)
    seen = []

    class Counting:
        scale, iso, memo, bounds = ev.scale, ev.iso, ev.memo, ev.bounds

        def field(self, P):
            seen.append(np.array(P))
            return ev.field(P)

    rng = np.random.default_rng(4)
    d = rng.normal(size=(300, 3))
    P = 0.4543 * d / np.linalg.norm(d, axis=1)[:, None] + np.where(rng.random((300, 1)) < 0.5, 0.0, [[0, 3, 0]])
    eye = np.array([0.5, -10.0, 0.3])
    v = visible(Counting(), P, eye, normals=d / np.linalg.norm(d, axis=1)[:, None])
    S = np.concatenate(seen)
    pad = 1e-9 * ev.scale
    assert len(S) and np.all((S >= lo - pad) & (S <= hi + pad))
    np.testing.assert_array_equal(v, [visible(ev, p[None], eye, normals=n[None] / np.linalg.norm(n))[0]
                                      for p, n in zip(P, d)])
    assert 0 < v.sum() < len(v)
