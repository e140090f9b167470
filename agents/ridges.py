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
  along u (one batch, projected onto the surface: Surface.probed); the point climbs
  (to the top of the parabola through the three, or uphill) until q1 there is at least
  q1 to either side, then again with the probe halved FINER times: a peak, a smooth
  crest or a shoulder beside a flat face alike. Each point stays within ``reach`` of
  where it started. A peak within PEAK_PROBE of a CSG crease (the branch records to
  either side differ) is the crease's, not a ridge.
- **Seeds**: the rough mesh's vertices that face the eye with q1 at least half
  RIDGE_MIN (and the last frame's ridge points when the eye moved), corrected onto a
  peak, REFINE_BATCH of them per system iteration; of each batch the highest q1 first,
  SEED_APART steps apart. A seed starts two tasks, one each way along the ridge, each
  as soon as an agent is idle; a seed a traced ridge passes is dropped.
- **Tracing** (:class:`RidgeTraces`, every task stepped together each system
  iteration): a step ahead, corrected onto the peak within a step of the prediction.
  The first step from a seed tries the directions FAN about the one across u and
  keeps the one the corrector moved least (it lay along the ridge); later steps go
  along the chord of the last two points. A trace ends where the corrector finds no
  peak (the ridge fades, turns to face away, or q1 drops below RIDGE_MIN), where it
  turns by more than TURN, where it comes within a step of a ridge point traced before
  (agents.traced: another trace's, a kept one's, or its own beyond SELF_GAP steps: a
  loop closed), and after the session's outline limit. Its points are a "ridges"
  outline; hidden parts are removed with the others'.
"""
import numpy as np

from ..blackboard.board import KIND_ID
from ..model.curvature import curvature, view_dependent
from ..model.tolerances import NEAR_SURFACE, on_surface
from ..model.vectors import cross
from .columns import Columns, Paths
from .outline import Outline
from .sheets import record_ends
from .steering import unit

RIDGE_MIN = 4.0      # q1 of a ridge drawn, at least, over the model's size
PEAK_PROBE = 0.004   # q1's samples to either side of a point for its peak, a share of the model's size
PEAK_STEPS = 4       # corrector moves onto a peak before it gives up (a trace step's)
SEED_CLIMBS = 12     # ... a seed's (a vertex may lie half a cell from the ridge)
SEED_REACH = 4.0     # ... and how far it may move, in steps
FINER = 3            # ... and, once at a peak, halvings of the probe to locate it closer
FACING = 0.1         # n.v of a ridge point, at least (towards a silhouette q1 grows without bound)
TURN = np.radians(50.0)   # a trace ends where its chord turns by more than this in one step
FAN = np.radians([0.0, 30.0, -30.0, 60.0, -60.0])   # a first step's directions about the one across u
SEED_APART = 2.0     # a batch's seeds this many steps apart, at least
REFINE_BATCH = 1024  # candidate seeds corrected per system iteration
RIDGE = KIND_ID["ridges"]

_V = ((3,), float)


def q1(surface, P, g):
    """Signed q1 at points P (gradients g) and its unit direction on the surface."""
    q, u = view_dependent(curvature(surface.ev, P, g), surface.view.towards_eye(P))
    return q, unit(u)


def _around(surface, X, g, d):
    """Signed q1 at X, and |q1| there and ``d`` (per point) to either side along q1's
    direction (projected onto the surface), one batch; and that direction."""
    m = len(X)
    here = curvature(surface.ev, X, g)
    u = unit(view_dependent(here, surface.view.towards_eye(X))[1])
    c, _, P, _ = surface.probed(X, g, u, d, here=here)
    q, _ = view_dependent(c, surface.view.towards_eye(np.concatenate([X, P])))
    a = np.abs(q)
    return q[:m], a[:m], a[m:2 * m], a[2 * m:], u


def peak(surface, X, g, reach, climbs=PEAK_STEPS):
    """Points X (gradients g) moved onto a peak of q1 along its direction (the
    corrector). Returns X, g and whether each is an apparent ridge point that shows:
    found within ``climbs`` moves and ``reach`` (per point) of where it started, q1 at
    least RIDGE_MIN over the model's size, facing the eye by FACING.

    A point is at a peak when q1 there is at least q1 a probe's distance to either
    side. The probe starts at PEAK_PROBE; at a peak it halves, FINER times, and the point
    climbs on (a shoulder beside a flat face is located as closely as a smooth crest);
    at the finest probe it moves to the top of the parabola through the three samples
    (within half a probe, as q1 there is at least either side's: on a smooth crest its
    top, beside a shoulder at most half the finest probe). Elsewhere it climbs to that
    parabola's top, at most a probe away, or to the higher sample where the parabola
    opens upwards."""
    X, g = np.array(X, float), np.array(g, float)
    start = X.copy()
    reach = np.broadcast_to(np.asarray(reach, float), len(X))
    d = np.full(len(X), PEAK_PROBE * surface.scale)
    finest = PEAK_PROBE * surface.scale / 2 ** FINER
    ok = np.zeros(len(X), bool)
    across = np.zeros_like(X)                   # q1's direction at each point found
    # a point without a gradient (a flat field) has no normal, hence no q1
    live = np.flatnonzero(np.all(np.isfinite(X), axis=1) & np.all(np.isfinite(g), axis=1) &
                          (np.einsum("ij,ij->i", g, g) > 1e-300))
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
        # at the peak: onto the parabola's top; else a climb of at most a probe (no further
        # than the higher sample: beyond a shoulder lies a flat face)
        top = np.where(shows, np.clip(top, -0.5 * dl, 0.5 * dl), np.clip(top, -dl, dl))
        moving = shows | go
        stays = live[finer]
        live, u, top = live[moving], u[moving], top[moving]
        if len(live):
            Y, fY, gY = surface.project(X[live] + top[:, None] * u, anchor=X[live])
            near = on_surface(fY, surface.iso, NEAR_SURFACE) & (np.linalg.norm(Y - start[live], axis=1) <= reach[live])
            X[live[near]], g[live[near]] = Y[near], gY[near]
            found = near & shows[moving]
            ok[live[found]], across[live[found]] = True, u[found]
            live = live[near & ~shows[moving]]
        live = np.sort(np.concatenate([live, stays]))
    # a peak beside a crease is the crease's (its q1 there, from the Hessian across the
    # jump of the normal, means nothing): the branch records a PEAK_PROBE to either side
    # differ
    f = np.flatnonzero(ok)
    if len(f):
        D = PEAK_PROBE * surface.scale * across[f]
        ok[f[record_ends(surface, X[f] + D, X[f] - D)[1]]] = False
    return X, g, ok


class RidgeTraces:
    """The apparent ridge tasks of a session: the candidate seeds not corrected yet, the
    starts waiting for an agent (a seed's two ways), and the tasks tracing, one row
    each (its agent, its seed's serial, which is its outline's id, its way along the
    ridge, +1 or -1, its last point, gradient, direction and step index), their points
    pooled (agents.columns.Paths). Given the surface, the agent pool, the session's
    traced points (agents.traced.TracedPoints: the ridges traced, and kept from the
    last frame, end a trace that comes near), its trace step and outline length limit,
    and the candidate seeds: points with their gradients (the rough mesh's vertices)
    and the last frame's ridge outlines whose eye moved (``moved``)."""

    def __init__(self, surface, pool, traced, step_len, max_steps, V, gV, moved=()):
        self.surface, self.pool, self.traced = surface, pool, traced
        self.step_len, self.max_steps = step_len, max_steps
        moved = [np.asarray(o.points, float) for o in moved if len(o.points)]
        # candidates: (points, gradients or None: to be projected first), a batch at a time
        self._candidates = [(V[a:a + REFINE_BATCH], gV[a:a + REFINE_BATCH]) for a in range(0, len(V), REFINE_BATCH)]
        P = np.concatenate(moved) if moved else np.zeros((0, 3))
        self._candidates += [(P[a:a + REFINE_BATCH], None) for a in range(0, len(P), REFINE_BATCH)]
        self.starts = Columns(serial=((), np.int64), way=((), np.int64), p=_V, g=_V, t=_V)
        self.table = Columns(agent=((), np.int64), serial=((), np.int64), way=((), np.int64), p=_V, g=_V,
                             t=_V, arc=((), np.int64))
        self.paths = Paths()
        self.serial = 0                 # the next seed's serial
        self.started = 0                # tasks started so far
        self.done = []                  # the outlines of the tasks that ended
        self._seeded = set()            # the seeds whose point is among the traced ones

    def __len__(self):
        return len(self.table)

    def waiting(self, where):
        """Starts and candidate seeds left where ``where`` (a predicate on points) holds."""
        left = int(where(self.starts.p).sum()) if self.starts else 0
        return left + sum(int(where(P).any()) for P, _ in self._candidates)

    def _refine(self):
        """The next batch of candidates onto q1's peaks: its seeds, best first, join the
        starts."""
        P, g = self._candidates.pop(0)
        surface = self.surface
        if g is None:                        # the last frame's points: onto this frame's surface
            P, f, g = surface.project(P)
            on = on_surface(f, surface.iso, NEAR_SURFACE)
            P, g = P[on], g[on]
        facing = np.einsum("ij,ij->i", surface.normals(g), surface.view.towards_eye(P)) >= FACING
        P, g = P[facing], g[facing]
        q = q1(surface, P, g)[0]
        big = np.isfinite(q) & (q * surface.scale >= 0.5 * RIDGE_MIN)
        X, g, ok = peak(surface, P[big], g[big], reach=SEED_REACH * self.step_len, climbs=SEED_CLIMBS)
        X, g = X[ok], g[ok]
        q, u = q1(surface, X, g)
        order = np.argsort(-q, kind="stable")
        X, g, u = X[order], g[order], u[order]
        keep = _apart(X, SEED_APART * self.step_len)
        X, g, u = X[keep], g[keep], u[keep]
        k = len(X)
        serial = self.serial + np.arange(k)
        self.serial += k
        t = unit(cross(surface.normals(g), u))
        self.starts.append(2 * k, serial=np.repeat(serial, 2), way=np.tile([1, -1], k), p=np.repeat(X, 2, axis=0),
                           g=np.repeat(g, 2, axis=0), t=np.repeat(t, 2, axis=0) * np.tile([1.0, -1.0], k)[:, None])

    def assign(self, where):
        """Start tasks on the waiting starts where ``where`` (a predicate on points) holds,
        as many as there are idle agents (correcting the next batch of candidates when
        none is waiting); a start on a ridge traced already is dropped."""
        while self._candidates and not (self.starts and where(self.starts.p).any()):
            self._refine()
        if not self.starts or len(self.pool) == 0:
            return
        st = self.starts
        # the next starts in the regions, as many as there are idle agents, less those on
        # a ridge traced already (dropped)
        here = np.flatnonzero(where(st.p))[:len(self.pool)]
        hit = here[self._traced_near(st.p[here], st.serial[here], np.zeros(len(here), np.int64), st.g[here])]
        go = np.zeros(len(st), bool)
        go[here] = True
        go[hit] = False
        serial, way, P, g, t = st.serial[go], st.way[go], st.p[go], st.g[go], st.t[go]
        leave = np.ones(len(st), bool)
        leave[here] = False
        st.keep(leave)
        if not go.any():
            return
        k = len(serial)
        self.table.append(k, agent=self.pool.take(k), serial=serial, way=way, p=P, g=g, t=t, arc=0)
        self.started += k
        # a seed's point is its forward task's first, added when its first task starts
        first = ~np.isin(serial, list(self._seeded)) & ((way > 0) | ~np.isin(serial, serial[way > 0]))
        self._seeded.update(serial[first].tolist())
        n = self.surface.normals(g[first])
        self.paths.add(_path(serial[first], 1), 0, P[first], n)
        self.traced.add(RIDGE, P[first], serial[first], 0, n, self.step_len)

    def _traced_near(self, X, serial, arc, g):
        """Whether a ridge point traced so far lies within a step of each point X (its
        outline's own count beyond agents.traced.SELF_GAP steps of ``arc``)."""
        if len(X) == 0:
            return np.zeros(0, bool)
        loop = self.traced.loop(np.full(len(X), RIDGE), X, self.step_len, serial, arc, self.surface.normals(g))
        return np.array([loop.hit(i) is not None for i in range(len(X))], bool)

    def step(self):
        """One step of every ridge task."""
        tk, surface, h = self.table, self.surface, self.step_len
        if not tk:
            return
        m = len(tk)
        # the tries: one ahead for each task, the FAN of directions for a first step
        first = np.flatnonzero(tk.arc == 0)
        rows = np.concatenate([np.arange(m), np.repeat(first, len(FAN) - 1)])
        n0 = surface.normals(tk.g)
        D = tk.t[rows]
        ang = np.concatenate([np.zeros(m), np.tile(FAN[1:], len(first))])
        side = cross(n0[rows], D)
        D = np.cos(ang)[:, None] * D + np.sin(ang)[:, None] * side
        Y, _, gY = surface.project(tk.p[rows] + h * D, anchor=tk.p[rows])
        X, gX, ok = peak(surface, Y, gY, reach=h)
        chord = X - tk.p[rows]
        c = unit(chord)
        ok &= (np.linalg.norm(chord, axis=1) > 0.25 * h) & (np.einsum("ij,ij->i", c, D) >= np.cos(TURN))
        # each task's try: the one the corrector moved least, among those that worked
        moved = np.where(ok, np.linalg.norm(X - Y, axis=1), np.inf)
        order = np.lexsort((np.arange(len(rows)), moved, rows))
        lead = order[np.r_[True, rows[order][1:] != rows[order][:-1]]]
        pick = np.empty(m, np.int64)
        pick[rows[lead]] = lead
        ok = np.isfinite(moved[pick])
        X, gX, c = X[pick], gX[pick], c[pick]
        arc = tk.arc + tk.way
        ok &= np.abs(arc) < self.max_steps
        n = surface.normals(gX)
        got = np.flatnonzero(ok)
        loop = self.traced.loop(np.full(len(got), RIDGE), X[got], h, tk.serial[got], arc[got], n[got],
                                new=(np.full(len(got), RIDGE), X[got], n[got], tk.serial[got], arc[got],
                                     np.full(len(got), h)), upto=np.arange(len(got)))
        for i, r in enumerate(got.tolist()):      # in task order: a point kept before counts for the next
            if loop.hit(i) is None:
                loop.keep(i)
            else:
                ok[r] = False
        loop.commit()
        keep = np.flatnonzero(ok)
        self.paths.add(_path(tk.serial[keep], tk.way[keep]), arc[keep], X[keep], n[keep])
        tk.p, tk.g, tk.t, tk.arc = X, gX, unit(c - np.einsum("ij,ij->i", c, n)[:, None] * n), arc
        self._finish(np.flatnonzero(~ok))
        tk.keep(ok)

    def _finish(self, rows):
        """Tasks ``rows`` ended: their agents are idle again, their points an outline."""
        tk = self.table
        for r, (pts, nrm) in zip(rows.tolist(), self.paths.of(_path(tk.serial[rows], tk.way[rows]), remove=True)):
            self.pool.give_back([int(tk.agent[r])])
            if len(pts):
                self.done.append(Outline("ridges", pts, nrm, False, self.step_len))

    def active_outlines(self):
        return [Outline("ridges", pts, nrm, False, self.step_len)
                for pts, nrm in self.paths.of(_path(self.table.serial, self.table.way)) if len(pts)]


def _path(serial, way):
    """The pooled paths' key of the tasks of seeds ``serial`` going ``way``."""
    return 2 * np.asarray(serial) + (np.asarray(way) < 0)


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
