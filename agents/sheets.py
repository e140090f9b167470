"""Creases as the meeting of two sheets (the dual tracking of MASSRIS section 6: one
agent on each side of a CSG crease).

Each agent of a crease team keeps the branch record of its side (model.branches: the
child every union, intersection and difference chose there). With both records pinned,
the field of each side continues smoothly across the crease, and the crease point in a
plane across it solves {f_A = iso, f_B = iso, (x - Q) . T = 0}: Newton's method, one
batched evaluation of both sheets per iteration, converges in three or four where
bisecting the bracket between the agents takes tens of projected trial points. Two
records that agree wherever both reached a site (no max or min chose differently)
cannot have a crease between them: the field is smooth there.
"""
import numpy as np

from ..model.branches import apart
from ..model.tolerances import on_surface
from ..model.vectors import cross
from .asks import Ask, run
from .surface import newton_update, unit

NEWTON_ITERS = 8
MAX_SITES = 256         # beyond this many decision sites a record (4 bytes per site and
                        # point) costs more than it saves: creases are bisected instead


def usable(surface):
    """Whether the model's branch records are small enough to keep per crease team (a
    model with no site at all has no crease: every crease candidate is a smooth bend)."""
    return surface.ev.sites.count <= MAX_SITES


def record_ends(surface, A, B):
    """:func:`record_ends_steps` run alone."""
    return run(surface.ev, record_ends_steps(surface, A, B))[0]


def record_ends_steps(surface, A, B):
    """The branch records at side points A and B: (m, 2, sites) int32, and whether each
    pair chose differently at some site both reached (a crease may lie between). A
    solver (agents.asks)."""
    m = len(A)
    _, _, table = yield Ask(np.concatenate([A, B]), record=True)
    pins = np.stack([table[:m], table[m:]], axis=1)
    return pins, apart(pins[:, 0], pins[:, 1])


def no_silhouette_steps(surface, a, b, sa, sb, pins):
    """Silhouette brackets a-b (n.v of signs sa at a, sb at b) whose ends lie on two
    sheets (``pins``): True where each sheet, continued to the other end, keeps its n.v
    sign there, so that neither turns away from the eye between the ends (the sign
    change is the crease's jump). A sheet without a gradient at the other end (beyond its
    support) tells nothing: False. A solver (agents.asks)."""
    m = len(a)
    P = np.concatenate([b, a])                  # sheet A at b, sheet B at a
    _, g = yield Ask(P, np.concatenate([pins[:, 0], pins[:, 1]]))
    nv = np.einsum("ij,ij->i", surface.normals(g), surface.view.towards_eye(P))
    seen = np.einsum("ij,ij->i", g, g) > 0
    keeps = seen & ((nv > 0) == np.concatenate([sa > 0, sb > 0]))
    return keeps[:m] & keeps[m:]


def crease_newton_steps(surface, X0, Q, T, pins, reach, tol):
    """Crease points from X0 on the meeting of the sheets pinned by ``pins`` (m, 2,
    sites), in the planes through Q across T. Returns X, the two sheets' gradients
    there (side A, side B), the field and its own gradient at X (where converged), and
    whether each converged (a step below ``tol``, within ``reach`` of Q, the sheets not
    tangent) onto the surface itself (the sheets' meeting is a crease only where no
    third part covers it). A solver (agents.asks): a generator of its evaluations."""
    X = np.array(X0, float)
    m = len(X)
    reach = np.broadcast_to(np.asarray(reach, float), (m,))
    gA, gB, F, g = np.zeros((m, 3)), np.zeros((m, 3)), np.zeros(m), np.zeros((m, 3))
    ok = np.zeros(m, bool)
    live = np.arange(m)
    iso = surface.iso
    for _ in range(NEWTON_ITERS):
        if len(live) == 0:
            break
        x = X[live]
        k = len(live)
        f, gr = yield Ask(np.concatenate([x, x]), np.concatenate([pins[live, 0], pins[live, 1]]))
        ga, gb = gr[:k], gr[k:]
        gA[live], gB[live] = ga, gb
        Tl = T[live]
        J = np.stack([ga, gb, Tl], axis=1)
        r = -np.stack([f[:k] - iso, f[k:] - iso, np.einsum("ij,ij->i", x - Q[live], Tl)], axis=1)
        live = newton_update(X, Q, live, J, r, reach, tol, ok)     # tangent sheets: singular
    rows = np.flatnonzero(ok)
    if len(rows):
        F[rows], g[rows] = yield Ask(X[rows])
        ok[rows] = on_surface(F[rows], iso)
    return X, gA, gB, F, g, ok


def switches_steps(surface, X, nA, nB, W, eps):
    """Whether the branches really switch across crease points X (sheets' normals nA, nB;
    W across the crease from side A to side B): the records of the points ``eps`` to
    either side (:func:`side_points`, returned too) choose differently at some site.
    Two pinned sheets meet on past the end of their crease (where it runs into another
    crease or a third part takes over the surface, a triple junction); there both sides
    take the same branches, and no crease is drawn. A solver (agents.asks)."""
    A, B = side_points(X, nA, nB, W, eps)
    return (yield from record_ends_steps(surface, A, B))[1], A, B


def side_points(X, nA, nB, W, eps):
    """Points a little into each sheet from crease points X (across the crease, along
    W from side A to side B, made perpendicular to the crease nA x nB)."""
    T = unit(cross(nA, nB))
    W = unit(W - np.einsum("ij,ij->i", W, T)[:, None] * T)
    return X - eps[:, None] * W, X + eps[:, None] * W
