"""Apparent ridges (Judd et al. 2007): where the view-dependent curvature q1 (how fast
the normal turns per unit of image length) peaks along its own direction. Checked
against a view-dependent curvature computed here from the field alone (finite
differences of the gradient, not the session's curvature): on the crest of an
thin ellipsoid's rim, where symmetry puts them exactly; on the heart's blends; absent on
a sphere; along a rounded box's rounded edges; kept, or looked for again, in the next
frame."""
import numpy as np
import pytest

from blobtree_ink import model as M
from blobtree_ink.agents import Session, Settings
from blobtree_ink.agents.continuation import carried
from blobtree_ink.agents.pool import AgentPool
from blobtree_ink.agents.region import Region
from blobtree_ink.agents.ridges import RidgeTraces
from blobtree_ink.agents.surface import Surface
from blobtree_ink.agents.traced import TracedPoints
from blobtree_ink.agents.ridges import FACING, PEAK_PROBE, RIDGE_MIN, peak, q1
from blobtree_ink.blackboard.view import View
from blobtree_ink.strokes.visibility import visible

import truth
from conftest import shown_strokes

KINDS = ("silhouette", "ridges")
EYE = np.array([3.0, -4.0, 2.5])
BOX = {"type": "box", "center": [0, 0, 0], "half_size": [1.0, 0.7, 0.5], "radius": 0.3}
# an ellipsoid, thin across x, long along z: sharpest along its rim x = 0; seen from an
# eye in the plane x = 0, the mirror symmetry x -> -x puts the rim's apparent ridge
# exactly on x = 0
ELLIPSOID = {"type": "transform", "scale": [0.35, 1.0, 2.0],
             "child": {"type": "point", "center": [0, 0, 0], "radius": 2.0}}


def traced(root, eye=EYE, previous=None, resolution=20):
    s = Session(M.from_dict({"format": "blobtree-1", "root": root}) if isinstance(root, dict) else root,
                View(eye=eye), Settings(resolution=resolution, kinds=KINDS), previous=previous)
    s.request("OUTLINES")
    s.run()
    assert s.done
    out = [o for o in s.outlines() if o.kind == "ridges"]
    return s, (np.concatenate([o.points for o in out]) if out else np.zeros((0, 3)))


def assert_peaks(ev, X, eye):
    assert truth.ridge_points(ev, X, eye, RIDGE_MIN, FACING, PEAK_PROBE).all()


def test_the_session_q1_is_the_fields():
    s, X = traced(ELLIPSOID, np.array([0.0, 6.0, 1.0]))
    P = s.mesh.vertices[::7]
    _, g = s.ev.field_grad(P)
    q, u = q1(s.surface, P, g)
    qt, ut, _, _ = truth.view_dependent(s.ev, P, np.array([0.0, 6.0, 1.0]))
    ok = np.isfinite(qt) & (np.abs(qt) * s.ev.scale > 0.5)
    assert ok.sum() > 50
    assert np.allclose(q[ok], qt[ok], rtol=1e-3, atol=1e-3 / s.ev.scale)
    assert (np.abs(np.einsum("ij,ij->i", u[ok], ut[ok])) > 0.999).all()       # the same direction, up to sign


@pytest.mark.parametrize("eye", [(0.0, 6.0, 0.0), (0.0, 4.0, 3.0), (0.0, 5.0, -2.0)])
def test_a_thin_ellipsoid_has_one_along_its_rim(eye):
    eye = np.array(eye)
    s, X = traced(ELLIPSOID, eye)
    outs = [o for o in s.outlines() if o.kind == "ridges"]
    assert len(outs) == 1 and len(X) > 100                    # one whole line
    assert np.abs(X[:, 0]).max() < 2e-5 * s.ev.scale           # on the plane of symmetry
    assert X[:, 2].max() - X[:, 2].min() > 2.5                 # along most of the rim (z within +-1.82)
    assert_peaks(s.ev, X, eye)


def test_the_heart_blends_ridges_are_peaks():
    from conftest import example_path
    heart = M.load(example_path("heart"))
    s, X = traced(heart, eye=np.array([0.0, -6.0, 1.0]))
    assert len(X) > 100
    assert_peaks(s.ev, X, np.array([0.0, -6.0, 1.0]))


def test_their_hidden_parts_are_removed():
    """A ball between the eye and the ellipsoid hides the middle of its rim: the Ridges
    layer keeps what shows, every point of it visible, and no speck."""
    eye = np.array([0.0, 6.0, 0.0])
    root = {"type": "union", "children": [ELLIPSOID, {"type": "point", "center": [0.0, 2.5, 0.0], "radius": 0.8}]}
    _, X = traced(root, eye)
    ev = M.Evaluator(M.from_dict({"format": "blobtree-1", "root": root}))
    shown = visible(ev, X, eye)
    assert shown.sum() > 20 and (~shown).sum() > 5
    assert len(shown_strokes(ev, eye, KINDS, "Ridges", X)) >= 2        # the rim above and below the ball


def test_a_region_request_leaves_the_others_for_later():
    """Two ellipsoids: an outline request in a box around the left one traces its rim
    only; one over the whole model then traces the right one's too."""
    root = {"type": "union", "children": [{"type": "transform", "translate": [x, 0.0, 0.0], "child": ELLIPSOID}
                                          for x in (-1.5, 1.5)]}
    eye = np.array([0.0, 6.0, 0.0])
    s = Session(M.from_dict({"format": "blobtree-1", "root": root}), View(eye=eye), Settings(resolution=24, kinds=KINDS))
    s.request("OUTLINES", Region(box=([-3.0, -3.0, -3.0], [0.0, 3.0, 3.0])))
    s.run()
    assert s.done
    X = np.concatenate([o.points for o in s.outlines() if o.kind == "ridges"])
    assert (X[:, 0] < 0).all() and X[:, 2].max() - X[:, 2].min() > 2.5
    s.request("OUTLINES")
    s.run()
    assert s.done
    X = np.concatenate([o.points for o in s.outlines() if o.kind == "ridges"])
    right = X[X[:, 0] > 0]
    assert np.abs(right[:, 0] - 1.5).max() < 0.1 and right[:, 2].max() - right[:, 2].min() > 2.5
    assert truth.ridge_points(s.ev, X, eye, RIDGE_MIN, FACING, PEAK_PROBE).all()


def test_a_point_without_a_gradient_is_no_ridge_point():
    """The centre of a point primitive has no gradient, hence no normal and no q1: the
    corrector leaves it out, with the batch's other points as they would be alone."""
    s, X = traced(ELLIPSOID, np.array([0.0, 6.0, 0.0]))
    P = np.vstack([np.zeros(3), X[:5]])
    _, g = s.ev.field_grad(P)
    assert not g[0].any()
    q, u = q1(s.surface, P, g)
    assert np.isnan(q[0]) and np.isfinite(q[1:]).all()
    Y, _, ok = peak(s.surface, P, g, reach=s.step_len)
    alone = peak(s.surface, X[:5], g[1:], reach=s.step_len)
    assert not ok[0] and ok[1:].all() and np.array_equal(Y[1:], alone[0])


def test_a_sphere_has_none():
    """On a sphere q1 only grows towards the silhouette: no peak inside."""
    assert len(traced({"type": "point", "center": [0, 0, 0], "radius": 1.0})[1]) == 0


def test_a_rounded_box_has_them_along_its_rounded_edges():
    """The box's rounds are where q1 is large; they end in flat faces (q1 = 0), so the
    ridges sit at the rounds' shoulders or crests: never on a flat face."""
    s, X = traced(BOX)
    assert len(X) > 50
    half = np.array(BOX["half_size"])
    in_rounding = np.abs(X) > half[None] - 1e-3
    assert (in_rounding.sum(axis=1) >= 2).all()                 # off every face's flat part
    edges = {tuple(np.sign(x) * m) for x, m in zip(X, in_rounding.astype(int)) if m.sum() == 2}
    assert len(edges) >= 3                                      # several of its visible edges


def test_the_next_frame_keeps_them_or_looks_again():
    s, X = traced(ELLIPSOID, np.array([0.0, 6.0, 0.0]))
    prev = s.continuation()
    settings = Settings(resolution=20, kinds=KINDS)
    same = carried(prev, s.ev.model, View(eye=np.array([0.0, 6.0, 0.0])).key(), settings)
    assert [len(o.points) for o in same.whole if o.kind == "ridges"] == [len(X)]
    # the same eye: kept as they are, none traced again
    s2, X2 = traced(s.ev.model, np.array([0.0, 6.0, 0.0]), previous=prev)
    assert len(X2) == len(X) and np.array_equal(np.sort(X2, axis=0), np.sort(X, axis=0))
    assert s2.ridges.serial == 0
    # a moved eye: looked for again, the last frame's points among the seeds
    eye = np.array([0.0, 4.0, 3.0])
    moved = carried(prev, s.ev.model, View(eye=eye).key(), settings)
    assert not any(o.kind == "ridges" for o in moved.kept + moved.whole) and any(o.kind == "ridges" for o in moved.seeds)
    s3, X3 = traced(s.ev.model, eye, previous=prev)
    _, fresh = traced(ELLIPSOID, eye)
    assert np.abs(X3[:, 0]).max() < 2e-5 * s3.ev.scale
    assert abs(len(X3) - len(fresh)) <= 0.05 * len(fresh)
    # ... and those alone find the moved rim again (no vertex among the seeds)
    surface = Surface(s.ev, View(eye=eye))
    pool = AgentPool(100)
    rt = RidgeTraces(surface, pool, TracedPoints(s.step_len, np.radians(35.0)), s.step_len, 1000, np.zeros((0, 3)),
                     np.zeros((0, 3)), moved=[o for o in moved.seeds if o.kind == "ridges"])
    for _ in range(200):
        rt.assign(lambda P: np.ones(len(P), bool))
        rt.step()
        if not len(rt) and not rt.waiting(lambda P: np.ones(len(P), bool)):
            break
    assert pool.busy == 0 and not len(rt)
    Y = np.concatenate([o.points for o in rt.done])
    assert np.abs(Y[:, 0]).max() < 2e-5 * s.ev.scale and Y[:, 2].max() - Y[:, 2].min() > 2.5
    assert truth.ridge_points(s.ev, Y, eye, RIDGE_MIN, FACING, PEAK_PROBE).all()


def test_the_same_eye_on_the_heart_traces_none_again():
    from conftest import example_path
    heart = M.load(example_path("heart"))
    eye = np.array([0.0, -6.0, 1.0])
    s, X = traced(heart, eye)
    s2, X2 = traced(s.ev.model, eye, previous=s.continuation())
    assert s2.ridges.serial == 0 and s2.ridges.started == 0
    assert len(X2) == len(X) > 100


def test_one_agent_traces_them_all():
    """A seed's two ways take an agent each, one after the other when only one is idle."""
    one = Session(M.from_dict({"format": "blobtree-1", "root": ELLIPSOID}), View(eye=np.array([0.0, 6.0, 0.0])),
                  Settings(resolution=20, kinds=KINDS, agents=1))
    one.request("OUTLINES")
    one.run(iterations=5000)
    assert one.done
    outs = [o for o in one.outlines() if o.kind == "ridges"]
    assert len(outs) == 1                                      # the whole rim, one line
    _, many = traced(ELLIPSOID, np.array([0.0, 6.0, 0.0]))
    for end in (np.min, np.max):
        assert abs(end(outs[0].points[:, 2]) - end(many[:, 2])) < one.step_len
