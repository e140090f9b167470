"""Tracing tasks of a session: a seed's refinement starts them (one task each way
along its outline where agents are free for both), every system iteration steps them
together (tracer.trace_step), and a finished one leaves its points as an outline.
:class:`Traces` holds the tasks as columns (one row per task) and their points in a
pool (agents.columns.Paths), with the points of every outline traced so far
(agents.traced.TracedPoints).

A task's columns: its kind and agents (one, or a crease team of two; -1: none); its
last point, direction, crease ref (n_A - n_B) and normal; the same at its seed; its
step (halved after a failed step, regrown after success) and full step (the session's,
or a subdivided voxel's seed's); its outline id; whether it goes forwards from the
seed (else backwards) and whether the other half is its own task (paired); its
points kept each way (the pool holds them) and its last forward point; a crease
team's branch records (agents.sheets) and side positions, now and at the seed; and a
crease's side record (agents.crease_seeds), now and at the seed.
"""
import numpy as np

from ..blackboard.board import FEATURE_KINDS, KIND_ID
from ..model.vectors import cross
from . import crease_seeds
from .columns import Columns, Paths
from .outline import Outline
from .tracer import Step, refine_seeds, trace_step
from .traced import NO_ARC, SELF_GAP, TracedPoints, consume_crossed

SEED_PAUSE = 3          # bisection iterations a seed's refinement takes per system iteration
SEED_ROUNDS = 6         # ... in at most this many system iterations
NARROWED = 0.9          # ... each narrowing its bracket below this fraction of its width
SHORTEST = 1.0 / 16     # a failed step is retried halved down to this fraction of the full step
FEW = 48                # tracing tasks up to which a silhouette step tries all its halvings in one batch
                        # (a batch that small costs what a call costs, whatever its size)
CLOSE = 0.75            # a trace is back at its seed within this many full steps of it,
AWAY = 2.0              # ... once it has been this many times as far from it (a trace crawling on halved
                        # steps near its seed has not come round)

_V = ((3,), float)

KEPT = -1000            # outline ids of the outlines kept from the last frame: KEPT, KEPT - 1, ...
RETRY, KEEP, TURN, END, CLOSED = range(5)        # a task's fate after a step


def halvable(h, base):
    """Whether a failed step h (of a task whose full step is ``base``) is retried halved."""
    return h > base * SHORTEST


class Traces:
    """The tracing tasks of a session. Given the surface, the blackboard (seeds come from
    it, trace samples and new seeds go to it), the agent pool, the settings (kinds,
    crease angle, step, outline length limit), the location tolerance ``tol`` and the
    session's trace step ``step_len``."""

    def __init__(self, surface, board, pool, settings, tol, step_len, sites):
        self.surface, self.board, self.pool, self.settings = surface, board, pool, settings
        self.tol, self.step_len = tol, step_len
        pins = ((2, sites), np.int32)         # sites: the length of a branch record (0: none kept)
        self.table = Columns(
            kind=((), np.int64), agents=((2,), np.int64), serial=((), np.int64), id=((), np.int64),
            p=_V, t=_V, ref=_V, last_n=_V, start=_V, start_t=_V, start_ref=_V, start_n=_V,
            h=((), float), base=((), float), fwd=((), bool), paired=((), bool),
            nf=((), np.int64), nb=((), np.int64), fwd_last=_V, reach=((), float),
            pins=pins, team_a=_V, team_b=_V, start_pins=pins, start_team_a=_V, start_team_b=_V,
            has_sides=((), bool), side_x=_V, side_dirs=((2, 3), float), side_facing=((2,), float),
            start_has_sides=((), bool), start_side_x=_V, start_side_dirs=((2, 3), float),
            start_side_facing=((2,), float))
        self.paths = Paths()                  # the points the tasks have kept
        self.serial = 0                       # the next task's serial
        self.done = []                        # the outlines of the tasks that ended
        self.traced = TracedPoints(step_len, settings.crease_angle, board.lo)
        self.lost = []                        # where traces were lost (arrays of points), not taken yet

    def __len__(self):
        return len(self.table)

    def take_lost(self):
        """The points where traces were lost (and a step ahead) since the last call."""
        P, self.lost = np.concatenate(self.lost or [np.zeros((0, 3))]), []
        return P

    # --- starting ---------------------------------------------------------------------
    def add_traced(self, outlines):
        """Outlines traced already (the last frame's, where nothing changed): they count
        as traced (no seed starts a trace on them, a trace stops where it meets them,
        the blackboard's seeds of the other kinds than creases their points cross are
        taken) and are among the results as they are."""
        crossing = []                  # (kinds, points, normals, across, steps) of the lines' points
        for k, o in enumerate(outlines):
            P, n = np.asarray(o.points, float), np.asarray(o.normals, float)
            if not len(P):
                continue
            kind = KIND_ID[o.kind]
            step = o.step or self.step_len
            self.traced.add(kind, P, KEPT - k, np.arange(len(P)), n, step)
            self.done.append(o)
            if o.kind != "crease" and len(P) > 1:
                W = cross(n, np.gradient(P, axis=0))
                W /= np.maximum(np.linalg.norm(W, axis=1, keepdims=True), 1e-300)
                crossing.append((np.full(len(P), kind), P, n, W, np.full(len(P), step)))
        if crossing:                   # their seeds taken in one batch
            consume_crossed(self.board, self.surface, self.settings.crease_angle,
                            *(np.concatenate(a) for a in zip(*crossing)))

    def extend(self, outlines, first):
        """A task at each end of the open ``outlines``, kept as traced by :meth:`add_traced`
        from its ``first``-th outline on: it traces on beyond the end as the outline's own
        (the outline's points near the end do not stop it; its other end closes it), so an
        outline that grew since the last frame (its cusp or the crease it ends at moved)
        grows on, and one cut where it could not be followed joins up again. Ends beyond
        the free agents are left as they are."""
        ends = []                      # (outline index, forwards)
        for j, o in enumerate(outlines):
            if not o.closed and len(o.points) >= 2:
                ends += [(j, True), (j, False)]
        ends = ends[:len(self.pool)]
        if not ends:
            return
        m = len(ends)
        j = np.array([e[0] for e in ends])
        fwd = np.array([e[1] for e in ends])
        P = np.array([outlines[a].points[-1 if f else 0] for a, f in ends])
        before = np.array([outlines[a].points[-2 if f else 1] for a, f in ends])
        other = np.array([outlines[a].points[0 if f else -1] for a, f in ends])
        n = np.array([outlines[a].normals[-1 if f else 0] for a, f in ends])
        T = P - before
        T /= np.maximum(np.linalg.norm(T, axis=1, keepdims=True), 1e-300)
        kinds = np.array([KIND_ID[outlines[a].kind] for a in j])
        base = np.array([outlines[a].step or self.step_len for a in j])
        length = np.array([len(outlines[a].points) for a in j])
        zeros, pins = np.zeros((m, 3)), np.full((m,) + self.table.pins.shape[1:], -2, np.int32)
        serial = self.serial + np.arange(m)
        self.serial += m
        # forwards from the last point the step indices go on from the outline's; backwards
        # from the first they go below 0; its other end is where it would close
        self.table.append(
            m, kind=kinds, agents=np.array([self.pool.take(1) + [-1] for _ in range(m)]), serial=serial,
            id=KEPT - (first + j), p=P, t=T, ref=zeros, last_n=n, start=other, start_t=T, start_ref=zeros,
            start_n=n, h=base, base=base, fwd=fwd, paired=np.ones(m, bool), nf=np.where(fwd, length, 0), nb=0,
            fwd_last=P, reach=np.full(m, np.inf), pins=pins, team_a=P, team_b=P, start_pins=pins, start_team_a=P, start_team_b=P,
            has_sides=np.zeros(m, bool), side_x=zeros, side_dirs=np.zeros((m, 2, 3)),
            side_facing=np.zeros((m, 2)), start_has_sides=np.zeros(m, bool), start_side_x=zeros,
            start_side_dirs=np.zeros((m, 2, 3)), start_side_facing=np.zeros((m, 2)))

    def start(self, ids, iteration):
        """Refine the seeds ``ids`` (taken from the blackboard) and start a task on each
        valid one that no traced outline passes."""
        f = self.board.feat
        self.board.consume(ids)
        kinds = f["kind"][ids].astype(np.int64)
        X, n, T, ref, A, B, valid, pins, opened = refine_seeds(self.surface, kinds, f["a"][ids], f["b"][ids],
                                                               self.tol, self.settings.crease_angle,
                                                               pause=SEED_PAUSE)
        self._requeue(ids[opened], A[opened], B[opened])
        m = len(ids)
        has_sides = np.zeros(m, bool)
        side_x, side_dirs, side_facing = np.zeros((m, 3)), np.zeros((m, 2, 3)), np.zeros((m, 2))
        cre = np.flatnonzero(valid & (kinds == KIND_ID["crease"]))
        if len(cre) and "silhouette" in self.settings.kinds:
            has_sides[cre] = True
            side_x[cre], side_dirs[cre], side_facing[cre] = crease_seeds.seed_sides(self.surface, X[cre], A[cre],
                                                                                    B[cre])
        base = self.settings.step * f["cell"][ids]          # the seed's scale sets its trace's step
        needs = np.where(kinds == KIND_ID["crease"], 2, 1)
        later = int(needs[valid].sum())          # agents the seeds still to start need, one way
        todo = np.flatnonzero(valid)
        # is an outline traced through the seed already (or through a seed started before it)?
        k = len(todo)
        loop = self.traced.loop(kinds[todo], X[todo], base[todo], n=n[todo], upto=np.arange(k),
                                new=(kinds[todo], X[todo], n[todo], np.zeros(k), np.zeros(k), base[todo]))
        seed, fwd, paired_, agents, tids = [], [], [], [], []
        count = len(self.done) + len(self.table)
        for j, i in enumerate(todo):
            need = int(needs[i])
            later -= need
            if loop.hit(j) is not None:
                continue
            # a task each way from the seed where agents are free for both, after every
            # seed taken has its first (a seed left open may be consumed by a trace that
            # crosses its bracket on a neighbouring outline): an outline between two
            # seeds is then traced from both ends at once, in half the iterations;
            # otherwise one task goes forwards, then backwards
            paired = len(self.pool) - later >= 2 * need
            tid = count + 1000000 * iteration
            for way in (True, False) if paired else (True,):
                seed.append(i)
                fwd.append(way)
                paired_.append(paired)
                agents.append(self.pool.take(need) + [-1] * (2 - need))
                tids.append(tid)
                count += 1
            loop.keep(j, tid)
        loop.commit()
        if not seed:
            return
        i, fwd = np.array(seed), np.array(fwd)
        serial = self.serial + np.arange(len(i))
        self.serial += len(i)
        self.table.append(
            len(i), kind=kinds[i], agents=np.array(agents), serial=serial, id=np.array(tids), p=X[i],
            t=np.where(fwd[:, None], T[i], -T[i]), ref=ref[i], last_n=n[i], start=X[i], start_t=T[i],
            start_ref=ref[i], start_n=n[i], h=base[i], base=base[i], fwd=fwd, paired=np.array(paired_),
            nf=fwd.astype(np.int64), nb=0, fwd_last=X[i], reach=0.0, pins=pins[i], team_a=A[i], team_b=B[i],
            start_pins=pins[i], start_team_a=A[i], start_team_b=B[i], has_sides=has_sides[i], side_x=side_x[i],
            side_dirs=side_dirs[i], side_facing=side_facing[i], start_has_sides=has_sides[i],
            start_side_x=side_x[i], start_side_dirs=side_dirs[i], start_side_facing=side_facing[i])
        # the forward task of each seed holds the seed as its first point
        self.paths.add(serial[fwd], 0, X[i[fwd]], n[i[fwd]])

    def _requeue(self, ids, A, B):
        """Seeds whose bisection paused (one agent action per system iteration) go back on
        the blackboard with their narrowed brackets, to be refined again in a later
        iteration; one that has paused SEED_ROUNDS times already is dropped (a bracket
        still narrowing after that many bisections holds no outline point it can reach),
        and so is one whose bracket did not narrow below NARROWED of its width in this
        round (a stuck bracket: on the train about 130 silhouette seeds came back round
        after round from the third on with their brackets' widths unchanged to within
        5 %, and the last three rounds made 8 of about 400 refinements valid)."""
        f = self.board.feat
        rounds = f["rounds"][ids] + 1
        keep = rounds < SEED_ROUNDS
        keep &= np.linalg.norm(B - A, axis=1) < NARROWED * np.linalg.norm(f["b"][ids] - f["a"][ids], axis=1)
        for k in np.unique(f["kind"][ids[keep]]):
            m = keep & (f["kind"][ids] == k)
            self.board.add_features(0.5 * (A[m] + B[m]), A[m], B[m], FEATURE_KINDS[k], f["cell"][ids[m]], rounds[m])

    # --- stepping ---------------------------------------------------------------------
    def step(self):
        """One trace step of every task; returns the blackboard rows the new points
        touched (a list of arrays)."""
        tk, settings = self.table, self.settings
        if not tk:
            return []
        m = len(tk)
        kinds, base = tk.kind, tk.base
        st, retry = self._trace_step()
        X, n, Tn, refn, ok = st.X, st.n, st.T, st.ref, st.ok
        side_seeds = self._off_creases(X, st, ok)
        rows = self.board.add_samples(X, st.f, st.g, "path")
        # how far each new point is from its outline's other end: the seed, or the forward
        # half's last point for a backward half
        other = np.where((tk.fwd | (tk.nf == 0))[:, None], tk.start, tk.fwd_last)
        apart = np.linalg.norm(X - other, axis=1)
        at_other = (apart < CLOSE * base) & (tk.reach > AWAY * CLOSE * base)
        arcs = np.where(tk.fwd, tk.nf, -(tk.nb + 1))
        # which outline each new point meets (and, for a forward half ending without its
        # pair, whether one passes its seed), in loop order: see traced.Loops
        got = np.flatnonzero(ok)
        q = np.full(m, -1)
        q[got] = np.arange(len(got))
        lone = np.flatnonzero(tk.fwd & ~tk.paired)
        sw = np.full(m, -1)
        sw[lone] = len(got) + np.arange(len(lone))
        loop = self.traced.loop(
            np.concatenate([kinds[got], kinds[lone]]), np.concatenate([X[got], tk.start[lone]]),
            np.concatenate([base[got], base[lone]]), np.concatenate([tk.id[got], tk.id[lone]]),
            np.concatenate([arcs[got], np.full(len(lone), NO_ARC)]), np.concatenate([n[got], tk.start_n[lone]]),
            new=(kinds[got], X[got], n[got], tk.id[got], arcs[got], base[got]),
            upto=np.concatenate([np.arange(len(got)), np.searchsorted(got, lone)]))
        # each task's fate, in task order (a loop's questions see the points kept before them)
        fate = np.full(m, END, np.int8)
        steps = (tk.nf + tk.nb).tolist()
        q, sw, ok_, retry_, at_other_ = q.tolist(), sw.tolist(), ok.tolist(), retry.tolist(), at_other.tolist()
        fwd, ids, lone_ = tk.fwd.tolist(), tk.id.tolist(), (tk.fwd & ~tk.paired).tolist()
        limit = settings.max_outline_steps
        for i in range(m):
            if not ok_[i]:
                if retry_[i]:
                    fate[i] = RETRY            # retry with a shorter step next iteration
                    continue
                end = "lost"
            elif steps[i] >= 4 and at_other_[i]:
                end = "closed"
            elif (hit := loop.hit(q[i])) is not None:
                # an outline is here: stop short; come round onto its own seed, it closed (a task
                # going on from a kept outline's end, id below 0, joins: it bridges, the stitching closes)
                end = "closed" if fwd[i] and ids[i] >= 0 and hit[0] == ids[i] and hit[1] <= SELF_GAP else "joined"
            elif steps[i] >= limit:
                end = "limit"
            else:
                fate[i] = KEEP
                loop.keep(q[i])
                continue
            if end == "closed":
                fate[i] = CLOSED
            elif lone_[i] and loop.hit(sw[i]) is None:
                fate[i] = TURN             # trace the other way from the seed
        loop.commit()
        lost = np.flatnonzero(~ok & ~retry & np.isin(kinds, [KIND_ID["silhouette"], KIND_ID["crease"]]))
        self.lost += [np.concatenate([tk.p[lost], tk.p[lost] + tk.t[lost] * base[lost, None]])] if len(lost) else []
        kept = np.flatnonzero(fate == KEEP)
        tk.reach[kept] = np.maximum(tk.reach[kept], apart[kept])
        self._keep_points(kept, X, n, Tn, refn, st)
        self._turn(np.flatnonzero(fate == TURN))
        tk.h[fate == RETRY] *= 0.5
        ended = np.flatnonzero(fate >= END)
        self._finish(ended, fate[ended] == CLOSED)
        tk.keep(fate < END)
        W = np.where((kinds == KIND_ID["crease"])[:, None], refn, cross(n, Tn))
        W /= np.maximum(np.linalg.norm(W, axis=1, keepdims=True), 1e-300)
        consume_crossed(self.board, self.surface, settings.crease_angle, kinds[kept], X[kept], n[kept], W[kept],
                        base[kept])
        a, b, cell = side_seeds
        if len(a):
            self.board.add_features(0.5 * (a + b), a, b, "silhouette", cell)
        return [rows]

    def _trace_step(self):
        """Every task's trace step (tracer.trace_step), and which failed ones may still
        be retried with a halved step (:func:`halvable`). With at most FEW tasks, a silhouette task tries its
        step and every halving of it down to SHORTEST in one batch and goes on with the
        longest that holds (its step is that one's): the points a step and its retries
        in later iterations would find, without an iteration per retry (a trace crawling
        round a tight turn, or ending at a crease, takes one iteration a step, not five)."""
        tk, settings = self.table, self.settings
        m = len(tk)
        retry = halvable(tk.h, tk.base)
        tries = np.zeros(m, np.int64)
        if m <= FEW:
            # a silhouette step's halvings: as many as the retries its failures would take
            h = np.where(tk.kind == KIND_ID["silhouette"], tk.h, 0.0)
            while (more := halvable(h, tk.base)).any():
                tries += more
                h = np.where(more, 0.5 * h, 0.0)
        if not tries.any():
            return trace_step(self.surface, tk.kind, tk.p, tk.t, tk.ref, tk.h, self.tol, settings.crease_angle,
                              tk.last_n, tk.pins, (tk.team_a, tk.team_b), retry), retry
        rows = np.repeat(np.arange(m), tries + 1)                    # a task's rows: its step, then halvings
        first = np.cumsum(tries + 1) - (tries + 1)
        halved = np.arange(len(rows)) - np.repeat(first, tries + 1)
        h = tk.h[rows] * 0.5 ** halved
        # a row is retried where a shorter one follows it, and a task that tries no halving
        # (a crease, or a step already the shortest) is retried as in a single step
        last = np.repeat(tries, tries + 1)
        st = trace_step(self.surface, tk.kind[rows], tk.p[rows], tk.t[rows], tk.ref[rows], h, self.tol,
                        settings.crease_angle, tk.last_n[rows], tk.pins[rows], (tk.team_a[rows], tk.team_b[rows]),
                        retry[rows] & ((halved < last) | (last == 0)))
        # each task's first try that holds, else its last
        ok_at = np.where(st.ok, halved, np.iinfo(np.int64).max)
        best = np.minimum.reduceat(ok_at, first)
        pick = first + np.where(best <= tries, best, tries)
        tk.h[:] = h[pick]
        return Step(*(a[pick] for a in st)), retry & (tries == 0)

    def _off_creases(self, X, st, ok):
        """Seed brackets (a, b, cell) of silhouettes that start on the creases the crease
        tasks stepped along (agents.crease_seeds); the tasks' side records move on."""
        tk = self.table
        if "silhouette" not in self.settings.kinds:
            return np.zeros((0, 3)), np.zeros((0, 3)), np.zeros(0)
        a, b, src, rows, now = crease_seeds.off_creases(
            self.surface.view, tk.kind, X, st.A, st.B, st.nA, st.nB, ok, tk.has_sides,
            (tk.side_x, tk.side_dirs, tk.side_facing), tk.base)
        tk.side_x[rows], tk.side_dirs[rows], tk.side_facing[rows] = now
        tk.has_sides[rows] = True
        return a, b, tk.base[src] / self.settings.step          # the trace's scale: its seeds'

    def _keep_points(self, rows, X, n, Tn, refn, st):
        """Tasks ``rows`` keep their step's point and go on from it."""
        tk = self.table
        f = tk.fwd[rows]
        self.paths.add(tk.serial[rows], np.where(f, tk.nf[rows], -(tk.nb[rows] + 1)), X[rows], n[rows])
        tk.nf[rows[f]] += 1
        tk.nb[rows[~f]] += 1
        tk.fwd_last[rows[f]] = X[rows[f]]
        tk.p[rows], tk.t[rows], tk.ref[rows], tk.last_n[rows] = X[rows], Tn[rows], refn[rows], n[rows]
        tk.pins[rows], tk.team_a[rows], tk.team_b[rows] = st.pins[rows], st.A[rows], st.B[rows]
        tk.h[rows] = np.minimum(tk.base[rows], 1.5 * tk.h[rows])

    def _turn(self, rows):
        """Forward tasks ``rows`` without a pair go back to their seed to trace backwards."""
        tk = self.table
        tk.fwd[rows] = False
        tk.reach[rows] = 0.0
        tk.p[rows], tk.t[rows], tk.ref[rows] = tk.start[rows], -tk.start_t[rows], tk.start_ref[rows]
        tk.last_n[rows] = tk.start_n[rows]
        tk.h[rows] = tk.base[rows]
        tk.pins[rows], tk.team_a[rows], tk.team_b[rows] = (tk.start_pins[rows], tk.start_team_a[rows],
                                                           tk.start_team_b[rows])
        tk.has_sides[rows], tk.side_x[rows] = tk.start_has_sides[rows], tk.start_side_x[rows]
        tk.side_dirs[rows], tk.side_facing[rows] = tk.start_side_dirs[rows], tk.start_side_facing[rows]

    def _finish(self, rows, closed):
        """Tasks ``rows`` are done, in order: their agents are idle again and their points
        become outlines (even a single point: other traces stopped short of it)."""
        tk = self.table
        paths = self.paths.of(tk.serial[rows], remove=True)
        for r, c, (pts, nrm) in zip(rows.tolist(), closed.tolist(), paths):
            self.pool.give_back(tk.agents[r].tolist())
            if len(pts):
                self.done.append(Outline(FEATURE_KINDS[tk.kind[r]], pts, nrm, c, float(tk.base[r])))

    # --- results ----------------------------------------------------------------------
    def active_outlines(self):
        """The outlines of the tasks still tracing, so far (not closed)."""
        tk = self.table
        out = []
        for r, (pts, nrm) in enumerate(self.paths.of(tk.serial)):
            if len(pts):
                out.append(Outline(FEATURE_KINDS[tk.kind[r]], pts, nrm, False, float(tk.base[r])))
        return out
