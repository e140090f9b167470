"""Curvature from the Hessian against analytic surfaces: sphere, long segment, torus."""
import math

import numpy as np

from blobtree_ink import model as M

KISO = math.sqrt(1 - 0.5 ** (1 / 3))


def ev_of(root):
    return M.Evaluator(M.from_dict({"format": "blobtree-1", "root": root}))


def unit_dirs(n, seed=0):
    d = np.random.default_rng(seed).normal(size=(n, 3))
    return d / np.linalg.norm(d, axis=1)[:, None]


def test_sphere_curvature_is_one_over_r():
    R = 2.0
    r = KISO * R
    ev = ev_of({"type": "point", "center": [0.3, -0.2, 0.1], "radius": R})
    d = unit_dirs(200)
    P = np.array([0.3, -0.2, 0.1]) + r * d
    c = M.curvature(ev, P)
    np.testing.assert_allclose(c["k1"], 1 / r, rtol=1e-6)
    np.testing.assert_allclose(c["k2"], 1 / r, rtol=1e-6)
    np.testing.assert_allclose(c["mean"], 1 / r, rtol=1e-6)
    np.testing.assert_allclose(c["gauss"], 1 / r ** 2, rtol=1e-6)
    np.testing.assert_allclose(c["normal"], d, atol=1e-9)
    # principal directions are tangent, unit and orthogonal
    for key in ("dir1", "dir2"):
        np.testing.assert_allclose(np.linalg.norm(c[key], axis=1), 1, atol=1e-9)
        assert np.abs(np.einsum("ij,ij->i", c[key], d)).max() < 1e-6
    assert np.abs(np.einsum("ij,ij->i", c["dir1"], c["dir2"])).max() < 1e-6


def test_long_segment_is_a_cylinder_in_the_middle():
    R = 1.0
    r = KISO * R
    ev = ev_of({"type": "segment", "a": [-5, 0, 0], "b": [5, 0, 0], "radius": R})
    ang = np.linspace(0, 2 * np.pi, 50, endpoint=False)
    P = np.stack([np.linspace(-2, 2, 50), r * np.cos(ang), r * np.sin(ang)], axis=1)
    c = M.curvature(ev, P)
    np.testing.assert_allclose(c["k1"], 1 / r, rtol=1e-6)
    np.testing.assert_allclose(c["k2"], 0, atol=1e-6)
    np.testing.assert_allclose(c["gauss"], 0, atol=1e-6)
    # the direction of zero curvature is the axis, the curved one goes around it
    np.testing.assert_allclose(np.abs(c["dir2"][:, 0]), 1, atol=1e-6)
    assert np.abs(c["dir1"][:, 0]).max() < 1e-6


def test_torus_curvature_everywhere():
    a, R = 1.0, 0.8        # the torus circle radius and the kernel radius
    b = KISO * R           # tube radius
    ev = ev_of({"type": "circle", "center": [0, 0, 0], "normal": [0, 0, 1], "circle_radius": a, "radius": R})
    u = np.linspace(0, 2 * np.pi, 24, endpoint=False)     # around the axis
    v = np.linspace(0, 2 * np.pi, 24, endpoint=False)     # around the tube
    U, V = np.meshgrid(u, v)
    U, V = U.ravel(), V.ravel()
    P = np.stack([(a + b * np.cos(V)) * np.cos(U), (a + b * np.cos(V)) * np.sin(U), b * np.sin(V)], axis=1)
    c = M.curvature(ev, P)
    k_tube = 1 / b
    k_ring = np.cos(V) / (a + b * np.cos(V))
    np.testing.assert_allclose(c["k1"], np.maximum(k_tube, k_ring), rtol=1e-6, atol=1e-6)
    np.testing.assert_allclose(c["k2"], np.minimum(k_tube, k_ring), rtol=1e-6, atol=1e-6)
    inner = np.cos(V) < -0.99
    assert np.all(c["gauss"][inner] < 0) and np.all(c["gauss"][np.cos(V) > 0.99] > 0)
