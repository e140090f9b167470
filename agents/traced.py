"""Points of the outlines traced so far, hashed by cells of one trace step: which
outline is near a point (to start no second trace on it, to stop a trace that meets
another, or closes on itself); and which open seeds new trace points cover.

The points are numpy columns per kind, sorted by cell (in the order they came within
a cell). A loop over tasks asks its questions together (:meth:`TracedPoints.loop`):
against the table as of the loop's start in one batch, and against the points the loop
itself keeps before each question through the pairs found at its start, resolved as it
goes; a question alone is a loop of one."""
import numpy as np

from ..blackboard.board import FEATURE_KINDS, KIND_ID
from ..blackboard.cells import _NEIGHBOURS, pack, pack_around

SELF_GAP = 6        # steps along an outline within which its own points do not stop it
_NONE = len(_NEIGHBOURS)        # no hit: beyond the last of the 27 cells
NO_ARC = np.iinfo(np.int64).min  # a question without a step index
NO_OWN = np.iinfo(np.int64).min  # a question without an outline of its own (ids may be negative: kept ones)


class Points:
    """Trace points of one kind as columns (pos, normal, outline id, step index, step),
    with their cells' keys, sorted by key and, within a key, in the order they came."""
    def __init__(self, step_len, origin, pos=None, nrm=None, tid=None, arc=None, step=None):
        self.step_len, self.origin = step_len, origin
        self.pos = np.zeros((0, 3)) if pos is None else np.array(pos, float).reshape(-1, 3)
        m = len(self.pos)
        self.nrm = np.zeros((m, 3)) if nrm is None else np.array(nrm, float).reshape(-1, 3)
        self.tid = np.zeros(m, np.int64) if tid is None else np.array(tid, np.int64).reshape(-1)
        self.arc = np.zeros(m, np.int64) if arc is None else np.array(arc, np.int64).reshape(-1)
        self.step = np.zeros(m) if step is None else np.array(step, float).reshape(-1)
        self.key = pack(self._cells(self.pos))
        self.order = np.argsort(self.key, kind="stable")      # rows by (key, arrival)
        self.sorted_key = self.key[self.order]

    def __len__(self):
        return len(self.pos)

    def extend(self, other):
        """These points followed by ``other``'s: the columns appended, and ``other``'s rows
        merged into the sorted order after the rows of equal keys (no key computed or
        sorted again)."""
        out = Points.__new__(Points)
        out.step_len, out.origin = self.step_len, self.origin
        for c in ("pos", "nrm", "tid", "arc", "step", "key"):
            setattr(out, c, np.concatenate([getattr(self, c), getattr(other, c)]))
        at = np.searchsorted(self.sorted_key, other.sorted_key, "right")
        out.order = np.insert(self.order, at, other.order + len(self))
        out.sorted_key = np.insert(self.sorted_key, at, other.sorted_key)
        return out

    def _cells(self, P):
        return np.floor((P - self.origin) / self.step_len).astype(np.int64)

    def around(self, P):
        """(point, row, cell) for every row in the 27 cells around each point P[i]; cell
        is the index of the row's cell among them (nested loops over dx, dy, dz)."""
        keys = pack_around(self._cells(P)).ravel()
        lo = np.searchsorted(self.sorted_key, keys, "left")
        count = np.searchsorted(self.sorted_key, keys, "right") - lo
        slot = np.repeat(np.arange(len(keys)), count)
        rows = self.order[np.arange(int(count.sum())) - np.repeat(np.cumsum(count) - count - lo, count)]
        return slot // _NONE, rows, slot % _NONE


class Questions:
    """Which traced point of one kind is near each point P[i] (see :meth:`TracedPoints.near`):
    radius, own outline id (NO_OWN: none), step index (NO_ARC: none) and normal (NaN: none)."""
    def __init__(self, kind, P, radius, own, arc, n):
        self.kind = int(kind)
        self.P, self.radius, self.own, self.arc = P, np.asarray(radius, float), own, arc
        self.has_own, self.has_arc = own != NO_OWN, arc != NO_ARC
        self.has_n = np.isfinite(n).all(axis=1)
        self.n = np.where(self.has_n[:, None], n, 0.0)

    def __len__(self):
        return len(self.P)

    def accept(self, q, pts, rows, cos_sheet):
        """Whether each point pts[rows[k]] counts for question q[k]: not the asking
        outline's own within SELF_GAP steps of it (or at all, without a step index), not
        on another sheet, and within the question's radius or 0.6 of the point's step."""
        own = self.has_own[q] & (pts.tid[rows] == self.own[q])
        own &= ~self.has_arc[q] | (np.abs(self.arc[q] - pts.arc[rows]) <= SELF_GAP)
        ok = ~own
        if self.kind != KIND_ID["crease"]:
            qn, n = pts.nrm[rows], self.n[q]
            ok &= ~self.has_n[q] | ~(qn[:, 0] * n[:, 0] + qn[:, 1] * n[:, 1] + qn[:, 2] * n[:, 2] < cos_sheet)
        r = np.maximum(self.radius[q], 0.6 * pts.step[rows])
        e = pts.pos[rows] - self.P[q]
        return ok & (e[:, 0] * e[:, 0] + e[:, 1] * e[:, 1] + e[:, 2] * e[:, 2] < r * r)


class Loop:
    """The questions of one loop over tasks, in order, and the points it may keep.

    Question q is asked after the loop has decided on the points ``new`` numbered below
    ``upto[q]``; it sees the table as of the loop's start and those of them the loop
    kept (:meth:`keep`), as :meth:`TracedPoints.near` would have had they been
    remembered one by one: the first hit over the 27 cells in order, within a cell
    the earliest point (the table's before the loop's). :meth:`commit` adds the kept
    points to the table."""
    def __init__(self, traced, questions, new=None, upto=None):
        self.traced, self.questions, self.new = traced, questions, new
        m = len(questions)
        self.cell = np.full(m, _NONE, np.int64)     # the first hit's cell in the table, if any
        self.tid = np.zeros(m, np.int64)
        self.arc = np.zeros(m, np.int64)
        table = traced.table[questions.kind]
        if len(table) and m:
            q, rows, cell = table.around(questions.P)
            ok = questions.accept(q, table, rows, traced.cos_sheet)
            q, rows, cell = q[ok], rows[ok], cell[ok]
            first = np.lexsort((rows, cell, q))       # arrival order is row order
            q, rows, cell = q[first], rows[first], cell[first]
            lead = np.r_[True, q[1:] != q[:-1]] if len(q) else np.zeros(0, bool)
            q, rows, cell = q[lead], rows[lead], cell[lead]
            self.cell[q], self.tid[q], self.arc[q] = cell, table.tid[rows], table.arc[rows]
        self.later = {}                            # question -> [(cell, new point)] that would come first
        self.kept = np.zeros(0 if new is None else len(new), bool)
        if new is not None and len(new) and m:
            q, c, cell = new.around(questions.P)
            ok = (c < np.asarray(upto)[q]) & questions.accept(q, new, c, traced.cos_sheet)
            ok &= cell < self.cell[q]                # a new point wins only in an earlier cell
            q, c, cell = q[ok], c[ok], cell[ok]
            for k in np.lexsort((c, cell, q)):
                self.later.setdefault(int(q[k]), []).append((int(c[k]), int(cell[k])))

    def hit(self, q):
        """(outline id, step index) of the first point near question q, or None."""
        for c, _ in self.later.get(q, ()):
            if self.kept[c]:
                return int(self.new.tid[c]), int(self.new.arc[c])
        if self.cell[q] < _NONE:
            return int(self.tid[q]), int(self.arc[q])
        return None

    def keep(self, c, tid=None):
        """The loop keeps new point c (as part of outline ``tid``, if given now)."""
        self.kept[c] = True
        if tid is not None:
            self.new.tid[c] = tid

    def commit(self):
        if self.kept.any():
            k = np.flatnonzero(self.kept)
            n = self.new
            self.traced.add(self.questions.kind, n.pos[k], n.tid[k], n.arc[k], n.nrm[k], n.step[k])


class Loops:
    """A :class:`Loop` over questions and new points of several kinds: each kind's go to
    that kind's loop (its own table), with their order kept. ``kinds``, ``P``, ``radius``,
    ``own`` (NO_OWN: none), ``arc`` (NO_ARC: none) and ``n`` (NaN: none) per question;
    ``new``: (kinds, P, n, tid, arc, step) per new point; ``upto`` per question."""
    def __init__(self, traced, kinds, P, radius, own, arc, n, new=None, upto=None):
        kinds = np.asarray(kinds, np.int64)
        m = len(kinds)
        self.q_kind, self.q_local = kinds.tolist(), np.zeros(m, np.int64)
        nk = np.asarray(new[0], np.int64) if new is not None else np.zeros(0, np.int64)
        self.c_kind, self.c_local = nk.tolist(), np.zeros(len(nk), np.int64)
        self.loops = {}
        upto = np.zeros(m, np.int64) if upto is None else np.asarray(upto, np.int64)
        for k in np.union1d(kinds, nk).tolist():
            qi, ci = np.flatnonzero(kinds == k), np.flatnonzero(nk == k)
            self.q_local[qi], self.c_local[ci] = np.arange(len(qi)), np.arange(len(ci))
            pts = None
            if new is not None:
                _, NP, Nn, Nt, Na, Ns = new
                pts = Points(traced.step_len, traced.origin, NP[ci], Nn[ci], Nt[ci], Na[ci], Ns[ci])
            qs = Questions(k, P[qi], radius[qi], own[qi], arc[qi], n[qi])
            self.loops[k] = Loop(traced, qs, pts, np.searchsorted(ci, upto[qi]))
        self.q_local, self.c_local = self.q_local.tolist(), self.c_local.tolist()

    def hit(self, q):
        return self.loops[self.q_kind[q]].hit(self.q_local[q])

    def keep(self, c, tid=None):
        self.loops[self.c_kind[c]].keep(self.c_local[c], tid)

    def commit(self):
        for loop in self.loops.values():
            loop.commit()


class TracedPoints:
    def __init__(self, step_len, crease_angle, origin=None):
        """``origin``: where cells of one step start (a point near the model: cell
        indices stay small however far from 0 the model lies)."""
        self.step_len = step_len
        self.cos_sheet = np.cos(0.5 * crease_angle)
        self.origin = np.zeros(3) if origin is None else np.asarray(origin, float)
        self.table = {k: Points(step_len, self.origin) for k in range(len(FEATURE_KINDS))}

    def add(self, kind, P, tid, arc, n, step):
        """Traced points of one kind, with their outline's id, their step index along it
        (0 the seed, + forwards, - backwards), their normals and their outline's step."""
        new = Points(self.step_len, self.origin, P, n, np.broadcast_to(tid, (len(np.atleast_2d(P)),)),
                     np.broadcast_to(arc, (len(np.atleast_2d(P)),)),
                     np.broadcast_to(step, (len(np.atleast_2d(P)),)))
        self.table[kind] = self.table[kind].extend(new)

    def remember(self, kind, p, tid, arc, n, step=None):
        """One traced point (step: default the session's; at most that)."""
        self.add(kind, np.asarray(p, float)[None], tid, arc, np.asarray(n, float)[None],
                 self.step_len if step is None else step)

    def points(self):
        """Every traced point, of every kind, as an (m, 3) array."""
        return np.concatenate([t.pos for t in self.table.values()])

    def loop(self, kinds, P, radius, own=None, arc=None, n=None, new=None, upto=None):
        """The questions of a loop over tasks and the points it may keep (:class:`Loops`);
        own, arc and n may be None for all."""
        m = len(kinds)
        own = np.full(m, NO_OWN, np.int64) if own is None else np.asarray(own, np.int64)
        arc = np.full(m, NO_ARC, np.int64) if arc is None else np.asarray(arc, np.int64)
        n = np.full((m, 3), np.nan) if n is None else np.asarray(n, float)
        return Loops(self, kinds, np.asarray(P, float).reshape(-1, 3), np.broadcast_to(radius, (m,)), own, arc, n,
                     new, upto)

    def unknown(self, kind, P, radius):
        """Which points P (k, 3) have no traced point of this kind within radius."""
        known = self.loop(np.full(len(P), KIND_ID[kind]), P, radius)
        return np.array([known.hit(q) is None for q in range(len(P))], bool)

    def near(self, kind, p, radius, own, arc=None, n=None):
        """A traced point of this kind within radius of p, as (outline id, step index),
        or None. Points of the outline ``own`` count only given p's step index ``arc``
        and when more than SELF_GAP steps away along the outline (a trace coming round
        onto its own other end, or its backward half meeting its forward half, stops).
        Given the normal ``n`` at p, silhouette and curvature-sign points on another
        sheet (normals apart by half the crease angle: the far side of a crease, where
        a different outline ends) do not count; crease points have no one normal. A
        point of an outline traced with longer steps counts within 0.6 of its step:
        points of a smaller scale's trace that runs along it are that close to it."""
        return self.loop([kind], p, radius, None if own is None else [own], None if arc is None else [arc],
                         None if n is None else [n]).hit(0)


def consume_crossed(board, surface, crease_angle, kinds, X, n, W, steps):
    """The blackboard's open seeds whose bracket (a polygon edge, or a finer one) crosses this
    iteration's new trace points' outline are taken as traced: its ends lie on
    either side of the plane through a new point X across ``W`` (silhouettes and
    curvature-sign lines: n x T; creases: their ref, the side normals' difference),
    and where it crosses that plane is within 0.75 of its cell (a voxel, or a
    subdivided voxel's fine cell), or of the covering trace's step if longer, of X.
    A seed merely near X is not taken: a parallel outline half a cell away (the two
    silhouettes of a fold, a suture's crease beside them) keeps its seeds. Nor
    (silhouettes, curvature-sign lines) is one whose normal shows it on another
    sheet: the inner and outer silhouettes of a thin lip lie that close."""
    cos = np.cos(0.5 * crease_angle)
    f = board.feat
    for k in np.unique(kinds):
        m = kinds == k
        ids, j = board.open_near(X[m], FEATURE_KINDS[k], 1.5 * board.h)
        Xj, Wj = X[m][j], W[m][j]
        cell = f["cell"][ids]
        reach = 0.75 * np.maximum(cell, steps[m][j])
        da = np.einsum("ij,ij->i", f["a"][ids] - Xj, Wj)
        db = np.einsum("ij,ij->i", f["b"][ids] - Xj, Wj)
        on = np.minimum(np.abs(da), np.abs(db)) < 0.05 * cell
        cross = (da * db < 0) | on
        u = np.where(da != db, da / np.where(da != db, da - db, 1.0), 0.5)
        c = f["a"][ids] + np.clip(u, 0.0, 1.0)[:, None] * (f["b"][ids] - f["a"][ids])
        take = cross & (np.linalg.norm(c - Xj, axis=1) < reach)
        ids, j = ids[take], j[take]
        if len(ids) and k != KIND_ID["crease"]:
            # on the sheet of the outline: the normal where the bracket crosses it is the
            # outline point's (its ends' turn to either side of it, the more so the wider it is)
            _, g = surface.field_grad(c[take])
            ids = ids[np.einsum("ij,ij->i", surface.normals(g), n[m][j]) > cos]
        board.consume(ids)
