"""Ground truth for traced outlines from the exact field alone (not from the sessions'
own machinery): is a point on the surface, on a silhouette, on a crease."""
import numpy as np

CREASE_RADIUS = 2e-3        # a crease point must see the normal jump within this share of the model's size
CREASE_JUMP = np.radians(10.0)   # ... by at least this angle (a smooth sheet turns far less within it)


def _directions(n=96):
    """n directions spread over the sphere (a Fibonacci lattice)."""
    i = np.arange(n) + 0.5
    z = 1.0 - 2.0 * i / n
    r = np.sqrt(1.0 - z * z)
    a = np.pi * (1.0 + 5 ** 0.5) * i
    return np.stack([r * np.cos(a), r * np.sin(a), z], axis=1)


def _project(ev, P, steps=20):
    """Newton steps along the gradient onto f = iso (plain, field and gradient only)."""
    P = np.array(P, float)
    for _ in range(steps):
        f, g = ev.field_grad(P)
        gg = np.einsum("ij,ij->i", g, g)
        ok = gg > 1e-300
        P[ok] -= ((f[ok] - ev.iso) / gg[ok])[:, None] * g[ok]
    return P


def normal_spread(ev, X, radius):
    """The largest angle between the surface normals found around each point X: points
    on a sphere of ``radius`` around it projected onto the surface, those that land
    within twice the radius of X."""
    D = _directions()
    out = np.zeros(len(X))
    for i, x in enumerate(np.asarray(X, float)):
        P = _project(ev, x + radius * D)
        f, g = ev.field_grad(P)
        near = (np.linalg.norm(P - x, axis=1) < 2 * radius) & (np.abs(f - ev.iso) < 1e-9) & \
            (np.einsum("ij,ij->i", g, g) > 0)
        if near.sum() < 2:
            continue
        n = -g[near] / np.linalg.norm(g[near], axis=1, keepdims=True)
        out[i] = np.arccos(np.clip(n @ n.T, -1, 1)).max()
    return out


def on_a_crease(ev, X, radius=CREASE_RADIUS, jump=CREASE_JUMP):
    """Whether the normal jumps by at least ``jump`` within ``radius`` (a share of the
    model's size) of each point: a crease is there."""
    return normal_spread(ev, X, radius * ev.scale) >= jump
