"""Steering and flocking behaviours (Reynolds; Smarticles section 5) as pure functions
of arrays: each returns one steering vector per smarticle, to be combined with weights
(:func:`combine`) and integrated in a separate step (:func:`integrate`). The exploring
agents (agents.explore) and the stroke smarticles (strokes.smarticles) share them. Smarticles are
points, not vehicles: no local frame, and surface smarticles are put back on the
iso-surface after every step (the attractor correction F = (f(x) - iso) grad f(x),
applied as Newton steps).
"""
import numpy as np

from ..model.vectors import cross


def tangent(v, n):
    """v projected into the tangent planes of normals n."""
    return v - np.einsum("ij,ij->i", v, n)[:, None] * n


def unit(v):
    return v / np.maximum(np.linalg.norm(v, axis=-1, keepdims=True), 1e-300)


def wander(vel, normals, noise, jitter=0.5):
    """Small random changes of heading, kept in the tangent plane (the sum of the
    scaled velocity and a random displacement keeps the path from being erratic);
    ``noise``: a standard normal 3-vector per smarticle."""
    return tangent(unit(vel) + jitter * noise, normals)


def flow(field_dirs, vel):
    """Follow a flow field (principal directions, contour direction or an axis); the
    field's sign is chosen to agree with the current heading, so paths do not reverse."""
    s = np.sign(np.einsum("ij,ij->i", field_dirs, vel))
    s[s == 0] = 1.0
    return field_dirs * s[:, None]


def axis_field(normals, axis):
    """A global axis (horizontal or vertical strokes) projected on the surface."""
    return unit(tangent(np.broadcast_to(np.asarray(axis, float), normals.shape).copy(), normals))


def contour_field(normals, view_dirs):
    """The contour direction: tangent and perpendicular to the view direction."""
    return unit(cross(normals, view_dirs))


def seek(P, target):
    return unit(np.asarray(target, float) - P)


def path_following(P, V, path, radius, ahead):
    """Reynolds' path following: predict the position ``ahead`` along the heading; if
    it is farther than ``radius`` from the path (a polyline), steer to the path point
    nearest the prediction, moved on along the path by ``ahead``. Zero where on course."""
    path = np.asarray(path, float)
    pred = P + unit(V) * ahead
    a, b = path[:-1], path[1:]
    ab = b - a
    L2 = np.maximum(np.einsum("ij,ij->i", ab, ab), 1e-300)
    t = np.clip(np.einsum("nij,ij->ni", pred[:, None, :] - a[None], ab) / L2, 0.0, 1.0)
    near = a[None] + t[..., None] * ab[None]                    # (n, segments, 3)
    d = np.linalg.norm(near - pred[:, None, :], axis=2)
    k = d.argmin(axis=1)
    rows = np.arange(len(P))
    target = near[rows, k] + unit(ab[k]) * ahead
    off = d[rows, k] > radius
    return np.where(off[:, None], unit(target - P), 0.0)


def containment(P, V, region, ahead):
    """Steer back towards the region's centre when the position ``ahead`` along the
    heading would leave it (a region: agents.Region, a box or a sphere)."""
    pred = P + unit(V) * ahead
    out = ~region.contains(pred)
    centre = region.sphere[0] if region.sphere is not None else 0.5 * (region.box[0] + region.box[1])
    return np.where(out[:, None], unit(centre - P), 0.0)


def _groups(flock):
    """Each smarticle's flock as 0..m-1, and the flocks' sizes."""
    ids, inv = np.unique(np.asarray(flock), return_inverse=True)
    return inv.ravel(), np.bincount(inv.ravel(), minlength=len(ids))


def _mean(X, inv, sizes):
    return np.stack([np.bincount(inv, X[:, k], len(sizes)) for k in range(X.shape[1])], axis=1) / sizes[:, None]


def separation(P, flock, radius):
    """Steer away from flockmates closer than radius (weighted by inverse distance):
    the pairs of one flock, all flocks at once."""
    out = np.zeros_like(P)
    inv, sizes = _groups(flock)
    order = np.argsort(inv, kind="stable")
    start = np.cumsum(sizes) - sizes
    k = sizes[inv[order]]                                    # each one's flock's size, in flock order
    a = np.repeat(order, k)                                  # each member with every member of its flock
    first = np.repeat(start[inv[order]], k)
    b = order[first + np.arange(len(a)) - np.repeat(np.cumsum(k) - k, k)]
    d = P[a] - P[b]
    dist = np.linalg.norm(d, axis=1)
    near = (a != b) & (dist > 0) & (dist < radius)
    w = 1.0 / np.maximum(dist[near], 1e-12) ** 2
    np.add.at(out, a[near], d[near] * w[:, None])
    return out


def alignment(V, flock):
    """Steer towards the flock's mean heading."""
    inv, sizes = _groups(flock)
    U = unit(V)
    return _mean(U, inv, sizes)[inv] - U


def cohesion(P, flock):
    """Steer towards the flock's centre."""
    inv, sizes = _groups(flock)
    return _mean(P, inv, sizes)[inv] - P


def combine(forces, weights):
    """Weighted sum of steering vectors (names in both dicts)."""
    total = None
    for name, w in weights.items():
        if w and name in forces:
            total = w * forces[name] if total is None else total + w * forces[name]
    return total


def integrate(P, V, F, dt, speed):
    """Forward Euler: the steering force changes the velocity, the velocity the
    position; speed is clamped so each step has a fixed length on the surface."""
    V = unit(V + dt * F) * speed
    return P + dt * V, V
