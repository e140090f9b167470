"""Curvature-sign lines: where the mean curvature changes sign (the surface turns from
convex to concave), exact on smooth blends and never drawn across flat parts."""
import numpy as np
import pytest

from blobtree_ink import model as M
from blobtree_ink.agents import Session, Settings
from blobtree_ink.blackboard.view import View
from blobtree_ink.model.curvature import curvature

KINDS = ("silhouette", "crease", "curvature")
EYE = np.array([3.0, -4.0, 2.5])


def lines(root, res=20):
    s = Session(M.from_dict({"format": "blobtree-1", "root": root}), View(eye=EYE), Settings(resolution=res, kinds=KINDS))
    s.request("OUTLINES")
    s.run()
    assert s.done
    out = [o for o in s.outlines() if o.kind == "curvature"]
    return s, (np.concatenate([o.points for o in out]) if out else np.zeros((0, 3)))


def torus(R, r):
    return {"type": "circle", "center": [0, 0, 0], "normal": [0, 0, 1], "circle_radius": R,
            "radius": r / np.sqrt(1 - 0.5 ** (1 / 3))}    # a lone primitive meets iso 0.5 there


@pytest.mark.parametrize("res", [16, 24])
def test_a_fat_torus_has_them_where_cos_v_is_minus_R_over_2r(res):
    """A torus of ring radius R and tube radius r > R/2: the mean curvature
    (1/r + cos v / (R + r cos v)) / 2 vanishes on the two circles cos v = -R / (2r)."""
    R, r = 1.0, 0.6
    s, X = lines(torus(R, r), res)
    rho = np.hypot(X[:, 0], X[:, 1])
    v = np.arctan2(X[:, 2], rho - R)
    assert len(X) > 50
    np.testing.assert_allclose(np.cos(v), -R / (2 * r), atol=1e-6)
    a = np.linspace(0, 2 * np.pi, 360, endpoint=False)
    v0 = np.arccos(-R / (2 * r))
    for sv in (v0, -v0):        # both circles, all the way round
        C = np.stack([(R + r * np.cos(sv)) * np.cos(a), (R + r * np.cos(sv)) * np.sin(a), r * np.sin(sv) + 0 * a], 1)
        assert np.linalg.norm(C[:, None] - X[None], axis=2).min(axis=1).max() < s.step_len


def test_a_thin_torus_has_none():
    """r < R/2: the mean curvature is positive everywhere."""
    assert len(lines(torus(1.0, 0.4))[1]) == 0


@pytest.mark.parametrize("root", [
    {"type": "box", "center": [0, 0, 0], "half_size": [1, 0.6, 0.4], "radius": 0.5},
    {"type": "taper", "rate": 0.2, "child": {"type": "box", "center": [0, 0, 0], "half_size": [0.5, 0.6, 1],
                                             "radius": 0.4}}], ids=["box", "tapered box"])
def test_flat_faces_draw_none(root):
    """A rounded box is flat on its faces and convex elsewhere: no sign change anywhere
    (the sign of the faces' near-zero curvature is noise: 247 and 172 points were drawn)."""
    assert len(lines(root)[1]) == 0


def test_on_blended_twisted_boxes_every_point_is_a_real_sign_change():
    def box(c, h, r=0.3):
        return {"type": "box", "center": c, "half_size": h, "radius": r}
    root = {"type": "blend", "children": [
        {"type": "twist", "rate": 0.8, "child": {"type": "taper", "rate": 0.25, "child": box([0, 0, 0], [0.5, 0.3, 1.2])}},
        {"type": "transform", "translate": [0.7, 0, 0.3], "rotate": [0.3, 0.5, 0],
         "child": {"type": "twist", "rate": -0.6, "child": box([0, 0, 0], [0.3, 0.6, 0.8])}},
        {"type": "taper", "rate": -0.3, "child": box([-0.6, 0.2, -0.4], [0.4, 0.4, 0.4])}]}
    s, X = lines(root)
    assert len(X) > 100
    c = curvature(s.ev, X)
    size = np.abs(c["k1"]) + np.abs(c["k2"])
    assert np.median(np.abs(c["k1"] + c["k2"]) / size) < 1e-6
    assert (np.abs(c["k1"] + c["k2"]) / size < 0.05).all()
    assert (size * s.ev.scale >= 1.0).all()                 # curved there, not flat
    # the mean curvature changes sign across each point (probes a step to either side)
    _, g = s.ev.field_grad(X)
    n = -g / np.linalg.norm(g, axis=1, keepdims=True)
    T = np.gradient(X, axis=0)
    W = np.cross(n, T)
    W /= np.maximum(np.linalg.norm(W, axis=1, keepdims=True), 1e-300)
    inner = np.linalg.norm(np.diff(X, axis=0), axis=1) < 2 * s.step_len     # within a polyline
    rows = np.flatnonzero(np.r_[False, inner[:-1] & inner[1:], False])
    d = 0.5 * s.step_len * W[rows]
    Hp = curvature(s.ev, X[rows] + d)["mean"]
    Hm = curvature(s.ev, X[rows] - d)["mean"]
    assert np.mean(Hp * Hm < 0) > 0.95
