"""Agents of a session stored as arrays (MASSRIS section 6: an agent's situation,
internal data and task, one row per agent, stepped together), and the paths they
trace, pooled.

:class:`Columns` holds named numpy columns of equal length: rows come in batches
(``append``) and leave by selection (``keep``). :class:`Paths` pools the points every
tracing task has kept, each with its task's serial and its step index along the
outline (0, 1, ... forwards from the seed, -1, -2, ... backwards), so that a task's
outline is its points in step order.
"""
import numpy as np


class Columns:
    """Named columns of one length; ``spec`` maps each name to (row shape, dtype)."""

    def __init__(self, **spec):
        self._spec = spec
        for name, (shape, dtype) in spec.items():
            setattr(self, name, np.zeros((0, *shape), dtype))

    def __len__(self):
        return len(getattr(self, next(iter(self._spec))))

    def __bool__(self):
        return len(self) > 0

    def append(self, k, **rows):
        """Append k rows: a value (k rows, or one row broadcast to k) for every column."""
        if set(rows) != set(self._spec):
            raise ValueError(f"append needs exactly the columns {sorted(self._spec)}, got {sorted(rows)}")
        for name, (shape, dtype) in self._spec.items():
            v = np.broadcast_to(np.asarray(rows[name], dtype), (k, *shape))
            setattr(self, name, np.concatenate([getattr(self, name), v]))

    def keep(self, rows):
        """Only the given rows (indices or a mask), in their order."""
        for name in self._spec:
            setattr(self, name, getattr(self, name)[rows])


class Paths:
    """The points kept by tracing tasks, pooled: position, normal, the task's serial
    and the step index along its outline. Storage grows by doubling, so that a long
    trace's points cost amortised constant time each (a trace steps thousands of times)."""

    def __init__(self):
        self._n = 0
        self._pos = np.zeros((64, 3))
        self._nrm = np.zeros((64, 3))
        self._task = np.zeros(64, np.int64)
        self._arc = np.zeros(64, np.int64)

    def __len__(self):
        return self._n

    @property
    def task(self):
        return self._task[:self._n]

    @property
    def arc(self):
        return self._arc[:self._n]

    def add(self, task, arc, pos, nrm):
        """Points pos (k, 3) with normals nrm of tasks ``task`` at step indices ``arc``
        (each k values, or one for all)."""
        pos = np.asarray(pos, float).reshape(-1, 3)
        k = len(pos)
        n = self._n
        if n + k > len(self._task):
            cap = max(2 * len(self._task), n + k)
            for name in ("_pos", "_nrm", "_task", "_arc"):
                old = getattr(self, name)
                grown = np.zeros((cap, *old.shape[1:]), old.dtype)
                grown[:n] = old[:n]
                setattr(self, name, grown)
        self._pos[n:n + k] = pos
        self._nrm[n:n + k] = np.asarray(nrm, float).reshape(k, 3)
        self._task[n:n + k] = task
        self._arc[n:n + k] = arc
        self._n = n + k

    def of(self, tasks, remove=False):
        """Each task's points and normals in step order, as a list of (pos, nrm) in the
        order of ``tasks``; with ``remove``, those points leave the pool."""
        tasks = np.asarray(tasks, np.int64)
        if len(tasks) == 0:
            return []
        n = self._n
        task, arc = self._task[:n], self._arc[:n]
        rank = np.full(n, -1, np.int64)
        order = np.argsort(tasks, kind="stable")
        at = np.minimum(np.searchsorted(tasks[order], task), len(tasks) - 1)
        hit = tasks[order][at] == task
        rank[hit] = order[at[hit]]
        rows = np.flatnonzero(hit)
        rows = rows[np.lexsort((arc[rows], rank[rows]))]
        counts = np.bincount(rank[rows], minlength=len(tasks))
        pos, nrm = self._pos[rows], self._nrm[rows]
        cut = np.cumsum(counts)[:-1]
        out = list(zip(np.split(pos, cut), np.split(nrm, cut)))
        if remove and len(rows):
            left = np.flatnonzero(~hit)
            m = len(left)
            for name in ("_pos", "_nrm", "_task", "_arc"):
                a = getattr(self, name)
                a[:m] = a[left]
            self._n = m
        return out
