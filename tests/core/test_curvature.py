"""Curvature from the Hessian against analytic surfaces: sphere, long segment, torus."""
import math

import numpy as np

from blobtree_ink import model as M
from blobtree_ink.model.curvature import tangent_basis
from blobtree_ink.model.projection import project
from blobtree_ink.model.vectors import cross

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


def test_hessian_along_directions_for_newton_steps():
    """The silhouette corrector's Jacobian row: the Hessian times a direction, by forward
    differences of the analytic gradient along it, one point per direction and point
    (the full Hessian by central differences takes six), error of the order of the step
    times the direction's length; a zero direction gives zero."""
    from blobtree_ink.model.curvature import field_grad_along, field_grad_hessian
    R = 2.0
    C = np.array([0.3, -0.2, 0.1])
    ev = ev_of({"type": "point", "center": list(C), "radius": R})
    P = C + KISO * R * unit_dirs(50)
    rng = np.random.default_rng(3)
    W = rng.normal(size=(50, 3)) * 4.0
    Z = np.zeros((50, 3))
    Z[::2] = rng.normal(size=(25, 3))
    before = ev.stats.points
    f, g, Hd = field_grad_along(ev, P, [W, Z])
    assert ev.stats.points - before == 3 * len(P)
    assert Hd.shape == (2, 50, 3)
    f0, g0 = ev.field_grad(P)
    np.testing.assert_array_equal(f, f0)
    np.testing.assert_array_equal(g, g0)
    # f = (1 - d2/R^2)^3: H = -6/R^2 [u^2 I - 4/R^2 u V V^T], u = 1 - d2/R^2, V = P - C
    V = P - C
    u = 1 - np.einsum("ij,ij->i", V, V) / R ** 2
    uu = u[:, None, None]
    exact = -6 / R ** 2 * (uu ** 2 * np.eye(3) - 4 / R ** 2 * uu * V[:, :, None] * V[:, None, :])
    _, _, Hc = field_grad_hessian(ev, P)
    assert np.abs(Hc - exact).max() < 1e-8
    step = 1e-5 * ev.scale
    for k, D in enumerate((W, Z)):
        want = np.einsum("nij,nj->ni", exact, D)
        err = np.abs(Hd[k] - want).max(axis=1) / np.maximum(np.linalg.norm(D, axis=1), 1e-300)
        assert err.max() < 10 * step                       # first order in the step
        assert 0.1 * step < err.max()                      # (not exact: a difference)
    np.testing.assert_array_equal(Hd[1][1::2], 0.0)        # zero directions


def test_closed_form_is_the_shape_operators_eigensystem():
    """The 2x2 closed form gives what a general symmetric eigensolver gives for the
    tangent part of -H/|g|: the principal curvatures to rounding, dir1 along its
    eigenvector, (dir1, dir2, normal) right-handed; on a blend with a bend, where the
    principal directions are nowhere aligned with the axes."""
    ev = ev_of({"type": "bend", "rate": 0.3, "child": {"type": "blend", "children": [
        {"type": "segment", "a": [-1.0, 0.0, 0.0], "b": [1.0, 0.3, 0.2], "radius": 1.0},
        {"type": "point", "center": [0.9, 0.5, 0.4], "radius": 1.1}]}})
    P, f, _ = project(ev, 1.5 * unit_dirs(2000, seed=3), 12)
    P = P[np.abs(f - ev.iso) < 1e-9]
    c = M.curvature(ev, P)
    _, g = ev.field_grad(P)
    n = -g / np.linalg.norm(g, axis=1)[:, None]
    Pm = np.eye(3)[None] - n[:, :, None] * n[:, None, :]
    S = -(Pm @ M.hessian(ev, P) @ Pm) / np.linalg.norm(g, axis=1)[:, None, None]
    w, v = np.linalg.eigh(S)
    tangent = np.argsort(np.abs(np.einsum("nik,ni->nk", v, n)), axis=1)[:, :2]     # drop the normal's
    rows = np.arange(len(P))[:, None]
    kw = w[rows, tangent]
    first = np.argmax(kw, axis=1)
    scale = np.abs(kw).max(axis=1)
    np.testing.assert_allclose(c["k1"], kw.max(axis=1), atol=1e-12 * scale.max())
    np.testing.assert_allclose(c["k2"], kw.min(axis=1), atol=1e-12 * scale.max())
    d1 = v[np.arange(len(P)), :, tangent[np.arange(len(P)), first]]
    apart = (kw.max(axis=1) - kw.min(axis=1)) > 1e-6 * scale
    assert len(P) > 300 and apart.mean() > 0.9
    np.testing.assert_allclose(np.abs(np.einsum("ij,ij->i", c["dir1"], d1))[apart], 1.0, atol=1e-9)
    np.testing.assert_allclose(np.einsum("ij,ij->i", cross(c["dir1"], c["dir2"]), c["normal"]), 1.0,
                               atol=1e-12)


def test_tangent_basis_is_orthonormal_for_any_normal():
    n = np.vstack([unit_dirs(500, seed=5), np.eye(3), -np.eye(3), [[0.0, 0.0, 0.0]]])
    e1, e2 = tangent_basis(n)
    for e in (e1, e2):
        np.testing.assert_allclose(np.linalg.norm(e, axis=1), 1.0, atol=1e-15)
        assert np.abs(np.einsum("ij,ij->i", e, n)).max() < 1e-15
    assert np.abs(np.einsum("ij,ij->i", e1, e2)).max() < 1e-15
    np.testing.assert_allclose(np.einsum("ij,ij->i", cross(e1, e2), n)[:-1], 1.0, atol=1e-15)
