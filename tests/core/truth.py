"""Ground truth for traced outlines from the exact field alone (not from the sessions'
own machinery): is a point on the surface, on a silhouette, on a crease, on an apparent
ridge."""
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
    within twice the radius of X (one batch for all points)."""
    X = np.asarray(X, float)
    D = _directions()
    k = len(D)
    P = _project(ev, (X[:, None, :] + radius * D[None]).reshape(-1, 3))
    f, g = ev.field_grad(P)
    near = (np.linalg.norm(P.reshape(len(X), k, 3) - X[:, None], axis=2) < 2 * radius) & \
        (np.abs(f - ev.iso) < 1e-9).reshape(len(X), k) & (np.einsum("ij,ij->i", g, g) > 0).reshape(len(X), k)
    n = (-g / np.maximum(np.linalg.norm(g, axis=1, keepdims=True), 1e-300)).reshape(len(X), k, 3)
    cos = np.einsum("pik,pjk->pij", n, n)
    both = near[:, :, None] & near[:, None, :]
    return np.arccos(np.clip(np.where(both, cos, 1.0), -1, 1)).max(axis=(1, 2))


def on_the_surface(ev, X, rel=1e-6):
    """Whether each point lies on the iso-surface: its distance estimate |f - iso| / |grad f|
    within ``rel`` of the model's size."""
    f, g = ev.field_grad(np.asarray(X, float))
    return np.abs(f - ev.iso) <= rel * ev.scale * np.linalg.norm(g, axis=1)


def silhouette_residual(ev, X, eye):
    """|n . v| at each point (v: the unit direction towards the eye): 0 on a silhouette."""
    X = np.asarray(X, float)
    _, g = ev.field_grad(X)
    n = -g / np.linalg.norm(g, axis=1, keepdims=True)
    v = eye - X
    return np.abs(np.einsum("ij,ij->i", n, v / np.linalg.norm(v, axis=1, keepdims=True)))


def on_a_crease(ev, X, radius=CREASE_RADIUS, jump=CREASE_JUMP):
    """Whether the normal jumps by at least ``jump`` within ``radius`` (a share of the
    model's size) of each point: a crease is there."""
    return normal_spread(ev, X, radius * ev.scale) >= jump


def view_dependent(ev, X, eye, h=1e-4):
    """q1 (Judd et al. 2007) and its surface direction at X from the field alone: the
    Hessian by central differences of the gradient, the shape operator on the tangent
    plane, and the largest singular value of S J^-1 (J: the tangent plane onto the
    image plane), signed as the normal curvature along its direction. Returns q1, that
    direction (unit), the normals and the unit directions to the eye."""
    X = np.asarray(X, float)
    h = h * ev.scale
    _, g = ev.field_grad(X)
    H = np.stack([(ev.field_grad(X + h * e)[1] - ev.field_grad(X - h * e)[1]) / (2 * h) for e in np.eye(3)], axis=2)
    n = -g / np.linalg.norm(g, axis=1, keepdims=True)
    v = (eye - X) / np.linalg.norm(eye - X, axis=1, keepdims=True)
    e1 = np.cross(n, v)
    e1 /= np.linalg.norm(e1, axis=1, keepdims=True)
    e2 = np.cross(n, e1)                                 # a tangent basis
    s1, s2 = e1, np.cross(v, e1)                         # an image basis (e1 is across the view too)
    T = np.stack([e1, e2], axis=2)                       # (m, 3, 2)
    S = -np.einsum("mki,mkl,mlj->mij", T, H, T) / np.linalg.norm(g, axis=1)[:, None, None]
    J = np.stack([np.einsum("mk,mkj->mj", s, T) for s in (s1, s2)], axis=1)
    _, sig, Vt = np.linalg.svd(S @ np.linalg.inv(J))
    ab = np.einsum("mij,mj->mi", np.linalg.inv(J), Vt[:, 0])
    u = np.einsum("mkj,mj->mk", T, ab)
    sign = np.sign(np.einsum("mi,mij,mj->m", ab, S, ab))
    return sign * sig[:, 0], u / np.linalg.norm(u, axis=1, keepdims=True), n, v


def ridge_points(ev, X, eye, q_min, facing, probe):
    """Whether points X are apparent ridge points by the field alone: q1 positive and at
    least 0.99 ``q_min`` over the model's size, n.v at least 0.99 ``facing``, and within
    an eighth of ``probe`` (a share of the size) of a peak of |q1| along its direction:
    of five samples an eighth of a probe apart around the point, the largest is not an
    end one."""
    q, u, n, v = view_dependent(ev, X, eye)
    d = probe * ev.scale / 8 * u
    size = np.stack([np.abs(view_dependent(ev, _project(ev, X + k * d), eye)[0]) for k in range(-2, 3)], axis=1)
    return (q * ev.scale >= 0.99 * q_min) & (np.einsum("ij,ij->i", n, v) >= 0.99 * facing) & \
        (np.abs(np.argmax(size, axis=1) - 2) <= 1)
