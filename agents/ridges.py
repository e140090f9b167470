"""Apparent ridges (Judd et al. 2007): where the view-dependent curvature q1 peaks.

q1 (model.curvature.view_dependent) is how fast the normal turns per unit of distance
on the image, at most, over the directions of the tangent plane; it is taken along its
own direction u on the surface, signed as the surface's curvature along u. An apparent
ridge runs where the size of q1 is a maximum along u, on the part of the surface that
faces the eye, and q1 is positive and large there (RIDGE_MIN over the model's size;
where it is negative, a valley, not drawn). Unlike the other kinds there is no
quantity whose sign changes once across a ridge whatever lies beside it (where a ridge
ends in a flat face, q1 beside it is zero and its derivative's sign is noise), so
ridge agents do not bracket: they climb.

- **Corrector** (:func:`peak`): q1 at a point and a probe's distance to either side
  along u (one batch, projected onto the surface); the point climbs (to the top of
  the parabola through the three, or uphill) until q1 there is at least q1 to either
  side, then again with the probe halved FINER times: a peak, a smooth crest or a
  shoulder beside a flat face alike. Each point stays within ``reach`` of where it
  started.
- **Seeds**: the rough mesh's vertices that face the eye with q1 at least half RIDGE_MIN
  (and the last frame's ridge points when the eye moved), corrected onto a peak; one
  per SEED_APART steps, the highest q1 first.
- **Tracing** (:class:`RidgeTraces`, one agent each way from a seed, all stepped
  together each system iteration): a step along the ridge (the chord of the last two
  points; from a seed, across u), corrected onto the peak no further than half a step
  from the prediction. A trace ends where the corrector finds no peak (the ridge
  fades, turns to face away, or q1 drops below RIDGE_MIN), where it turns by more
  than TURN, or where it comes within JOIN steps of a point traced before (another
  trace's, or its own far back: a loop closed), and after the session's outline limit.
  Its points are a "ridges" outline; hidden parts are removed with the others'.
"""
import numpy as np

from ..model.curvature import curvature, view_dependent
from ..model.tolerances import NEAR_SURFACE, on_surface
from .columns import Columns, Paths
from .outline import Outline
from .steering import unit

RIDGE_MIN = 4.0      # q1 of a ridge drawn, at least, over the model's size
PROBE = 0.004        # q1's samples to either side of a point for its peak, a share of the model's size
PEAK_STEPS = 4       # corrector moves onto a peak before it gives up (a trace step's)
SEED_CLIMBS = 12     # ... a seed's (a vertex may lie half a cell from the ridge)
SEED_REACH = 4.0     # ... and how far it may move, in steps
FINER = 3            # ... and, once at a peak, halvings of the probe to locate it closer
ROUND = 0.25         # a peak whose parabola's top lies within this many PROBEs of it is round: it moves there
FACING = 0.1         # n.v of a ridge point, at least (towards a silhouette q1 grows without bound)
TURN = np.radians(50.0)   # a trace ends where its chord turns by more than this in one step
JOIN = 0.6           # ... or within this many steps of a point traced before
OWN_GAP = 4          # ... its own points count from this many steps back
SEED_APART = 2.0     # seeds this many steps apart, at least

_V = ((3,), float)


def q1(surface, P, g):
    """Signed q1 at points P (gradients g) and its unit direction on the surface."""
    q, u = view_dependent(curvature(surface.ev, P, g), surface.view.towards_eye(P))
    return q, unit(u)


def _around(surface, X, g, d):
    """Signed q1 at X, and |q1| there and ``d`` (per point) to either side along q1's
    direction (projected onto the surface), one batch; and that direction."""
    m = len(X)
    _, u = q1(surface, X, g)
    D = d[:, None] * u
    P, _, gP = surface.project(np.concatenate([X + D, X - D]), anchor=np.concatenate([X, X]))
    q, _ = q1(surface, np.concatenate([X, P]), np.concatenate([g, gP]))
    a = np.abs(q)
    return q[:m], a[:m], a[m:2 * m], a[2 * m:], u


def peak(surface, X, g, reach, climbs=PEAK_STEPS):
    """Points X (gradients g) moved onto a peak of q1 along its direction (the
    corrector). Returns X, g and whether each is an apparent ridge point that shows:
    found within ``climbs`` moves and ``reach`` (per point) of where it started, q1 at
    least RIDGE_MIN over the model's size, facing the eye by FACING.

    A point is at a peak when q1 there is at least q1 a probe's distance to either
    side. The probe starts at PROBE; at a peak it halves, FINER times, and the point
    climbs on (a shoulder beside a flat face is located as closely as a smooth crest);
    at the finest probe it moves to the top of the parabola through the three samples
    where that lies within ROUND probes (a smooth crest). Elsewhere it climbs to that
    parabola's top, at most a probe away, or to the higher sample where the parabola
    opens upwards."""
    X, g = np.array(X, float), np.array(g, float)
    start = X.copy()
    reach = np.broadcast_to(np.asarray(reach, float), len(X))
    d = np.full(len(X), PROBE * surface.scale)
    finest = PROBE * surface.scale / 2 ** FINER
    ok = np.zeros(len(X), bool)
    live = np.flatnonzero(np.all(np.isfinite(X), axis=1) & np.all(np.isfinite(g), axis=1))
    for move in range(climbs + FINER + 1):
        if len(live) == 0:
            break
        Xl, gl, dl = X[live], g[live], d[live]
        signed, q, plus, minus, u = _around(surface, Xl, gl, dl)
        bend = 2 * q - plus - minus
        with np.errstate(invalid="ignore", divide="ignore"):
            top = np.nan_to_num(np.where(bend > 0, 0.5 * dl * (plus - minus) / bend, dl * np.sign(plus - minus)))
        facing = np.einsum("ij,ij->i", surface.normals(gl), surface.view.towards_eye(Xl)) >= FACING
        big = np.isfinite(q) & (q * surface.scale >= 0.5 * RIDGE_MIN) & facing
        at = big & (q >= plus) & (q >= minus)
        finer = at & (dl > 1.01 * finest)
        shows = at & ~finer & (signed * surface.scale >= RIDGE_MIN)
        d[live[finer]] *= 0.5                       # it stays, to be probed closer
        go = big & ~at & (move < climbs + FINER)
        # at the peak: onto the parabola's top where the peak is round (a shoulder's
        # parabola is no model of it: it stays); else a climb of at most a probe (no further
        # than the higher sample: beyond a shoulder lies a flat face)
        top = np.where(shows, np.where(np.abs(top) <= ROUND * dl, top, 0.0), np.clip(top, -dl, dl))
        moving = shows | go
        stays = live[finer]
        live, u, top = live[moving], u[moving], top[moving]
        if len(live):
            Y, fY, gY = surface.project(X[live] + top[:, None] * u, anchor=X[live])
            near = on_surface(fY, surface.iso, NEAR_SURFACE) & (np.linalg.norm(Y - start[live], axis=1) <= reach[live])
            X[live[near]], g[live[near]] = Y[near], gY[near]
            ok[live[near & shows[moving]]] = True
            live = live[near & ~shows[moving]]
        live = np.sort(np.concatenate([live, stays]))
    return X, g, ok


class RidgeTraces:
    """The apparent ridge tasks of a session: the seeds waiting for agents and the tasks
    tracing, one row each (its agent, seed serial, way along the ridge +1 or -1, last
    point, gradient, direction and step index), their points pooled (agents.columns.
    Paths), and every ridge point so far (kept ones too), which ends a trace that comes
    near. Given the surface, the agent pool, the session's trace step, the outline
    length limit, the rough mesh's vertices and gradients to seed from, and the last
    frame's ridge outlines to keep as they are (``kept``) or to seed from (``moved``)."""

    def __init__(self, surface, pool, step_len, max_steps, V, gV, kept=(), moved=()):
        self.surface, self.pool, self.step_len, self.max_steps = surface, pool, step_len, max_steps
        self._candidates = (V, gV, list(moved))
        self.seeds = None                        # (X, g, u) refined, best first; None: not yet
        self.table = Columns(agent=((), np.int64), serial=((), np.int64), way=((), np.int64), p=_V, g=_V,
                             t=_V, arc=((), np.int64))
        self.paths = Paths()
        self.serial = 0
        self.done = [o for o in kept if len(o.points)]
        kept_points = [np.asarray(o.points, float) for o in self.done]
        self._seen = np.concatenate(kept_points) if kept_points else np.zeros((0, 3))
        self._seen_serial = np.full(len(self._seen), -1, np.int64)    # -1: kept, nobody's own
        self._seen_arc = np.zeros(len(self._seen), np.int64)

    def __len__(self):
        return len(self.table)

    @property
    def waiting(self):
        """Seeds not started yet (before the first assignment: the candidates, as one)."""
        if self.seeds is None:
            return int(len(self._candidates[0]) + len(self._candidates[2]) > 0)
        return len(self.seeds[0])

    def _refine_seeds(self):
        """The candidates onto q1's peaks, one batch: the mesh's vertices facing the eye
        with q1 at least half RIDGE_MIN, and the last frame's ridge points."""
        V, gV, moved = self._candidates
        surface = self.surface
        if len(V):
            facing = np.einsum("ij,ij->i", surface.normals(gV), surface.view.towards_eye(V)) >= FACING
            V, gV = V[facing], gV[facing]
            q = q1(surface, V, gV)[0]
            big = np.isfinite(q) & (q * surface.scale >= 0.5 * RIDGE_MIN)
            V, gV = V[big], gV[big]
        if moved:
            P = np.concatenate([np.asarray(o.points, float) for o in moved])
            P, f, g = surface.project(P)
            near = on_surface(f, surface.iso, NEAR_SURFACE)
            V, gV = np.concatenate([V, P[near]]), np.concatenate([gV, g[near]])
        X, g, ok = peak(surface, V, gV, reach=SEED_REACH * self.step_len, climbs=SEED_CLIMBS)
        X, g = X[ok], g[ok]
        q, u = q1(surface, X, g)
        order = np.argsort(-q, kind="stable")
        X, g, u = X[order], g[order], u[order]
        keep = _apart(X, SEED_APART * self.step_len)
        self.seeds = (X[keep], g[keep], u[keep])

    def assign(self, where):
        """Start a task each way from the best seeds, as many as there are pairs of idle
        agents, skipping seeds where ``where`` (a predicate on points) is False and
        seeds a trace passed already."""
        if self.seeds is None:
            self._refine_seeds()
        X, g, u = self.seeds
        if len(X) == 0 or len(self.pool) < 2:
            return
        live = where(X) & (self._nearest(X, np.full(len(X), -2), np.zeros(len(X), np.int64)) > JOIN * self.step_len)
        X, g, u = X[live], g[live], u[live]
        k = min(len(X), len(self.pool) // 2)
        # seeds left over stay queued (those a trace passed are dropped when looked at next)
        start, self.seeds = (X[:k], g[:k], u[:k]), (X[k:], g[k:], u[k:])
        X, g, u = start
        if k == 0:
            return
        serial = self.serial + np.arange(k)
        self.serial += k
        t = unit(np.cross(self.surface.normals(g), u))
        self.table.append(2 * k, agent=self.pool.take(2 * k), serial=np.tile(serial, 2),
                          way=np.repeat([1, -1], k), p=np.tile(X, (2, 1)), g=np.tile(g, (2, 1)),
                          t=np.concatenate([t, -t]), arc=0)
        self.paths.add(2 * serial, 0, X, self.surface.normals(g))     # the seed: the forward task's
        self._remember(X, serial, np.zeros(k, np.int64))

    def step(self):
        """One step of every ridge task."""
        tk, surface, h = self.table, self.surface, self.step_len
        if not tk:
            return
        Y, _, gY = surface.project(tk.p + h * tk.t, anchor=tk.p)
        X, gX, ok = peak(surface, Y, gY, reach=0.5 * h)
        chord = X - tk.p
        length = np.linalg.norm(chord, axis=1)
        c = unit(chord)
        ok &= (length > 0.25 * h) & (np.einsum("ij,ij->i", c, tk.t) >= np.cos(TURN))
        arc = tk.arc + tk.way
        ok &= self._nearest(X, tk.serial, arc) > JOIN * h
        ok &= np.abs(arc) < self.max_steps
        ok[_clashes(X, ok, JOIN * h)] = False      # two tasks meeting in this step: the first goes on
        keep = np.flatnonzero(ok)
        self.paths.add(_path(tk.serial[keep], tk.way[keep]), arc[keep], X[keep], surface.normals(gX[keep]))
        self._remember(X[keep], tk.serial[keep], arc[keep])
        n = surface.normals(gX)
        t = unit(c - np.einsum("ij,ij->i", c, n)[:, None] * n)
        tk.p, tk.g, tk.t, tk.arc = X, gX, t, arc
        self._finish(np.flatnonzero(~ok))
        tk.keep(ok)

    def _remember(self, X, serial, arc):
        self._seen = np.concatenate([self._seen, X])
        self._seen_serial = np.concatenate([self._seen_serial, serial])
        self._seen_arc = np.concatenate([self._seen_arc, arc])

    def _nearest(self, X, serial, arc):
        """The distance from each point X to the nearest ridge point so far, leaving out
        its own task's (seed ``serial``) last OWN_GAP steps to either side of ``arc``."""
        if len(self._seen) == 0 or len(X) == 0:
            return np.full(len(X), np.inf)
        best = np.full(len(X), np.inf)
        for a in range(0, len(X), 256):           # bounded memory: 256 rows of distances at a time
            b = min(a + 256, len(X))
            d = np.linalg.norm(X[a:b, None, :] - self._seen[None, :, :], axis=2)
            own = (self._seen_serial[None, :] == serial[a:b, None]) & \
                (np.abs(self._seen_arc[None, :] - arc[a:b, None]) < OWN_GAP)
            d[own] = np.inf
            best[a:b] = d.min(axis=1)
        return best

    def _finish(self, rows):
        """Tasks ``rows`` ended: their agents are idle again, their points an outline."""
        tk = self.table
        for r, (pts, nrm) in zip(rows.tolist(), self.paths.of(_path(tk.serial[rows], tk.way[rows]))):
            self.pool.give_back([int(tk.agent[r])])
            if len(pts):
                self.done.append(Outline("ridges", pts, nrm, False, self.step_len))

    def active_outlines(self):
        return [Outline("ridges", pts, nrm, False, self.step_len)
                for pts, nrm in self.paths.of(_path(self.table.serial, self.table.way)) if len(pts)]


def _clashes(X, ok, r):
    """Rows of points X (those ``ok``) within r of an earlier row's ``ok`` point."""
    rows = np.flatnonzero(ok)
    if len(rows) < 2:
        return rows[:0]
    d = np.linalg.norm(X[rows, None, :] - X[None, rows, :], axis=2)
    near = np.triu(d < r, 1)                 # (i, j): j comes after i
    return rows[near.any(axis=0)]


def _path(serial, way):
    """The pooled paths' key of the tasks of seeds ``serial`` going ``way``."""
    return 2 * serial + (way < 0)


def _apart(X, r):
    """Which of points X (best first) to keep so that none lies within r of a kept one
    before it (greedy, on a grid of cells r wide)."""
    keep = np.zeros(len(X), bool)
    cells = {}
    keys = np.floor(X / r).astype(np.int64)
    for i, k in enumerate(map(tuple, keys.tolist())):
        near = [j for dx in (-1, 0, 1) for dy in (-1, 0, 1) for dz in (-1, 0, 1)
                for j in cells.get((k[0] + dx, k[1] + dy, k[2] + dz), ())]
        if all(np.linalg.norm(X[j] - X[i]) >= r for j in near):
            keep[i] = True
            cells.setdefault(k, []).append(i)
    return keep
