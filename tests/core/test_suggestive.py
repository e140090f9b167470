"""Suggestive contours (DeCarlo et al. 2003): zeros of the radial curvature, growing
towards the eye, on the visible side; checked on a torus against its analytic
curvature (not the session's), absent where the surface is convex, hidden lines
removed, and a moved eye looks for them again."""
import numpy as np

from blobtree_ink import model as M
from blobtree_ink.agents import Session, Settings
from blobtree_ink.agents.continuation import carried
from blobtree_ink.blackboard.view import View
from blobtree_ink.model.curvature import curvature, radial
from blobtree_ink.strokes.visibility import visible
from conftest import shown_strokes
from test_curvature_lines import torus

KINDS = ("silhouette", "suggestive")
EYE = np.array([3.0, -4.0, 2.5])
R, r = 1.0, 0.4                       # a thin torus: saddle-shaped inside (cos v < 0)


def model(root):
    return M.from_dict({"format": "blobtree-1", "root": root})


def traced(root, eye=EYE, kinds=KINDS):
    s = Session(model(root), View(eye=eye), Settings(resolution=20, kinds=kinds))
    s.request("OUTLINES")
    s.run()
    assert s.done
    out = [o for o in s.outlines() if o.kind == "suggestive"]
    return s, (np.concatenate([o.points for o in out]) if out else np.zeros((0, 3)))


def torus_frame(X):
    """The torus's own description of points on it: tube angle v, the unit normal and
    the principal directions (along the ring, along the tube) with their curvatures."""
    rho = np.hypot(X[:, 0], X[:, 1])
    ring = np.stack([X[:, 0] / rho, X[:, 1] / rho, 0 * rho], 1)       # away from the axis
    v = np.arctan2(X[:, 2], rho - R)
    n = np.cos(v)[:, None] * ring + np.sin(v)[:, None] * [0, 0, 1.0]
    along_ring = np.cross([0, 0, 1.0], ring)
    along_tube = np.cross(n, along_ring)
    k_ring = np.cos(v) / (R + r * np.cos(v))
    return v, n, along_ring, along_tube, k_ring, np.full(len(X), 1.0 / r)


def radial_truth(X, eye):
    """The torus's radial curvature at X seen from eye (analytic), and w."""
    _, n, d1, d2, k1, k2 = torus_frame(X)
    to_eye = (eye - X) / np.linalg.norm(eye - X, axis=1, keepdims=True)
    a, b = np.einsum("ij,ij->i", to_eye, d1), np.einsum("ij,ij->i", to_eye, d2)
    return (k1 * a * a + k2 * b * b) / (a * a + b * b), a[:, None] * d1 + b[:, None] * d2, n, to_eye


def onto_torus(P):
    rho = np.hypot(P[:, 0], P[:, 1])
    c = np.stack([R * P[:, 0] / rho, R * P[:, 1] / rho, 0 * rho], 1)   # nearest point of the ring
    d = P - c
    return c + r * d / np.linalg.norm(d, axis=1, keepdims=True)


def test_a_torus_seen_obliquely_has_them_inside_where_the_radial_curvature_vanishes():
    s, X = traced(torus(R, r))
    assert len(X) > 20
    kr, w, n, to_eye = radial_truth(X, EYE)
    v = torus_frame(X)[0]
    np.testing.assert_allclose(np.linalg.norm(X - onto_torus(X), axis=1), 0, atol=1e-7)   # on the torus
    assert np.abs(kr * r).max() < 1e-4                              # a zero of the radial curvature
    assert (np.cos(v) < 0).all()                                    # inside: where the torus is saddle-shaped
    assert (np.einsum("ij,ij->i", n, to_eye) > 0).all()             # facing the eye
    # growing towards the eye: the radial curvature a little along w, minus a little against it
    e = 0.01 * r * w / np.linalg.norm(w, axis=1, keepdims=True)
    ahead, behind = radial_truth(onto_torus(X + e), EYE)[0], radial_truth(onto_torus(X - e), EYE)[0]
    assert (ahead > 0).all() and (behind < 0).all()


def test_a_convex_surface_has_none():
    """A sphere and an ellipsoid: the radial curvature is positive everywhere (at every
    vertex of the rough mesh), so no line; the torus's changes sign, and it has some."""
    egg = {"type": "transform", "scale": [1.6, 1.0, 0.7], "child": {"type": "point", "center": [0, 0, 0],
                                                                     "radius": 1.0}}
    for root, convex in (({"type": "point", "center": [0, 0, 0], "radius": 1.0}, True), (egg, True),
                         (torus(R, r), False)):
        s, X = traced(root)
        V = s.mesh.vertices
        kr = radial(curvature(s.ev, V), s.view.towards_eye(V))[0]
        assert (kr > 0).all() == convex and (len(X) == 0) == convex


def test_their_hidden_parts_are_removed():
    """A ball between the eye and the torus hides some of its suggestive contours: the
    layer keeps what shows, every point of it visible, and no speck (a visible piece
    shorter than SPECK trace steps)."""
    root = {"type": "union", "children": [torus(R, r), {"type": "point", "center": [1.44, -1.957, 1.319],
                                                          "radius": 1.0}]}
    _, X = traced(root)
    ev = M.Evaluator(model(root))
    shown = visible(ev, X, EYE)
    assert shown.sum() > 5 and (~shown).sum() > 5
    shown_strokes(ev, EYE, KINDS, "Suggestive", X)


def test_a_moved_eye_looks_for_them_again():
    """They move with the eye: kept when it stays, seeded from the last frame's when it
    moves (never kept as they were)."""
    s, X = traced(torus(R, r))
    prev = s.continuation()
    settings = Settings(resolution=20, kinds=KINDS)
    same = carried(prev, s.ev.model, View(eye=EYE).key(), settings)
    assert any(o.kind == "suggestive" for o in same.whole)
    c, sn = np.cos(0.05), np.sin(0.05)
    moved = np.array([[c, -sn, 0], [sn, c, 0], [0, 0, 1.0]]) @ EYE
    other = carried(prev, s.ev.model, View(eye=moved).key(), settings)
    assert not any(o.kind == "suggestive" for o in other.kept + other.whole)
    assert any(o.kind == "suggestive" for o in other.seeds)
    going = Session(s.ev, View(eye=moved), settings, previous=prev)
    going.request("OUTLINES")
    going.run()
    Y = np.concatenate([o.points for o in going.outlines() if o.kind == "suggestive"])
    assert np.abs(radial_truth(Y, moved)[0] * r).max() < 1e-4
    assert np.abs(radial_truth(Y, EYE)[0] * r).max() > 1e-3          # this eye's, not the last one's
