"""Exploration tasks (Table 1: find features in a region): an agent wanders on the
surface around a voxel (Reynolds wander in the tangent plane, with containment that
seeks the voxel's centre when it strays) and identifies feature points by comparing
each step with the previous one: a sign change of n.v (silhouette), of the mean
curvature, of the radial curvature on the side facing the eye (suggestive contour), or
a jump of the normal (crease). Found points go to the blackboard, where
the manager turns them into tracing tasks."""
import numpy as np

from ..blackboard.board import FEATURE_KINDS
from ..model.curvature import curvature, radial
from ..model.tolerances import NEAR_SURFACE, on_surface
from ..model.vectors import cross
from . import steering as st
from .columns import Columns

STEP = 0.35                 # an explorer's step, in voxels
JITTER = 0.6                # its wander's random change of heading
ROUND = 6                   # steps of a walk planned in one tangent plane, projected together
JUMP = 3                    # a walk's point further than JUMP steps from the last is on another part


class Explorers:
    """The exploring agents of a session and the voxels waiting for one.

    A table (agents.columns) holds one row per exploring agent: its agent, voxel and
    that voxel's centre (or its start point), its position, heading and normal, its
    last n.v, mean and radial curvature (compared with the next step's), and the steps it has
    taken. ``queue`` lists the voxel rows waiting for an explorer, in order; a voxel is
    explored at most once (``explored``); ``starts`` maps a queued voxel to a point to
    start from instead of its centre (a probe on a sheet the polygonisation missed, a
    wall of a subtracted part)."""

    def __init__(self, surface, board, pool, rng, kinds, crease_angle, steps):
        self.surface, self.board, self.pool, self.rng = surface, board, pool, rng
        self.kinds, self.crease_angle, self.steps = tuple(kinds), crease_angle, steps
        v = ((3,), float)
        self.table = Columns(agent=((), np.int64), voxel=((), np.int64), centre=v, p=v, d=v, n=v,
                             s_sil=((), float), s_curv=((), float), s_sug=((), float), steps=((), np.int64))
        self.queue = []
        self.explored = set()
        self.starts = {}
        self.started = 0            # explorers sent out so far
        self.walked = []            # (A, nA, B, nB): the pairs of walk points each compared, and their normals

    def __len__(self):
        """Exploring agents (not counting the queue)."""
        return len(self.table)

    def enqueue(self, rows):
        """Voxel rows to explore after those queued, skipping any explored already."""
        self.queue.extend(int(r) for r in rows if int(r) not in self.explored)

    def enqueue_starts(self, P, region=None):
        """Queue explorers, ahead of the others, at the start points P (in the region,
        if one): one per voxel not explored or queued from a point yet."""
        if region is not None and len(P):
            P = P[region.contains(P)]
        if len(P) == 0:
            return
        rows = []
        for row, p in zip(self.board.voxel_rows(self.board.voxel_of(P)), P):
            row = int(row)
            if row not in self.explored and row not in self.starts:
                self.starts[row] = p
                rows.append(row)
        self.queue[:0] = rows[::-1]

    def assign(self):
        """Send an idle agent to each of the first voxels of the queue (as many as there
        are idle agents): all start positions projected in one batch."""
        k = min(len(self.pool), len(self.queue))
        if k == 0:
            return
        rows, self.queue = self.queue[:k], self.queue[k:]
        self.explored.update(rows)
        bb, surface = self.board, self.surface
        centres = bb.lo + (bb.vox["ijk"][rows] + 0.5) * bb.h
        for i, r in enumerate(rows):
            if r in self.starts:            # a probe point on a sheet the polygonisation missed
                centres[i] = self.starts[r]
        P, f, g = surface.project(centres.copy())
        ok = np.all(np.isfinite(P), axis=1) & on_surface(f, surface.iso, NEAR_SURFACE)
        if not ok.any():
            return
        P, g, centres = P[ok], g[ok], centres[ok]
        rows = [r for r, k in zip(rows, ok) if k]
        n = surface.normals(g)
        d = st.unit(cross(n, self.rng.normal(size=(len(P), 3))))
        sil = np.einsum("ij,ij->i", n, surface.view.towards_eye(P))
        c = curvature(surface.ev, P, g)
        self.table.append(len(rows), agent=self.pool.take(len(rows)), voxel=rows, centre=centres, p=P, d=d, n=n,
                          s_sil=sil, s_curv=c["mean"], s_sug=self._radial(c, P), steps=0)
        self.started += len(rows)

    def _radial(self, c, P):
        """The radial curvature at P (curvature ``c``), when suggestive contours are
        looked for (else zeros)."""
        if "suggestive" not in self.kinds:
            return np.zeros(len(P))
        return radial(c, self.surface.view.towards_eye(P))[0]

    def step(self):
        """Every explorer's whole walk in one system iteration: the wander (the
        smarticles' steering behaviour; containment seeks the voxel's centre when
        further than a voxel from it) is planned ROUND steps at a time in the tangent
        plane at the walk's last point, and those points of all explorers are projected
        onto the surface in one batch. Each point is compared with the last one
        before it that landed on the surface within JUMP steps of it; feature points
        found go to the blackboard. Returns the blackboard rows the new samples touched
        (a list of arrays)."""
        ex, surface, bb = self.table, self.surface, self.board
        if not ex:
            return []
        k, m = len(ex), self.steps
        Q, f, g = np.empty((m, k, 3)), np.empty((m, k)), np.empty((m, k, 3))
        x, d, N, C = ex.p, ex.d, ex.n, ex.centre
        for r in range(0, m, ROUND):
            X = np.empty((min(ROUND, m - r), k, 3))
            for i in range(len(X)):
                D = st.wander(d, N, self.rng.normal(size=d.shape), jitter=JITTER)
                away = np.linalg.norm(x - C, axis=1) > bb.h
                D[away] += 2.0 * np.linalg.norm(C[away] - x[away], axis=1)[:, None] / bb.h * st.seek(x[away], C[away])
                d = st.unit(st.tangent(D, N))
                x = x + STEP * bb.h * d
                X[i] = x
            q, fq, gq = surface.project(X.reshape(-1, 3))
            Q[r:r + len(X)], f[r:r + len(X)], g[r:r + len(X)] = q.reshape(X.shape), fq.reshape(-1, k), gq.reshape(X.shape)
            # the next round is planned from this one's last point, in its tangent plane
            last = np.all(np.isfinite(Q[r + len(X) - 1]), axis=1) & \
                on_surface(f[r + len(X) - 1], surface.iso, NEAR_SURFACE)
            x = np.where(last[:, None], Q[r + len(X) - 1], x)
            N = np.where(last[:, None], surface.normals(np.where(last[:, None], g[r + len(X) - 1], 1.0)), N)
            d = st.unit(st.tangent(d, N))
        Q, f, g = Q.reshape(-1, 3), f.ravel(), g.reshape(-1, 3)
        ok = np.all(np.isfinite(Q), axis=1) & on_surface(f, surface.iso, NEAR_SURFACE)
        Q, f, g = Q[ok], f[ok], g[ok]
        n = surface.normals(g)
        sil = np.einsum("ij,ij->i", n, surface.view.towards_eye(Q))
        cq = curvature(surface.ev, Q, g)
        sug = self._radial(cq, Q)
        rows = bb.add_samples(Q, f, g, "path", cq) if len(Q) else np.zeros(0, np.int64)
        # each point against the last one before it on the surface (the start, at first)
        walker = np.tile(np.arange(k), m)[ok]
        order = np.argsort(walker, kind="stable")           # each walker's points in walk order
        first = np.r_[True, walker[order][1:] != walker[order][:-1]]
        prev_p = np.where(first[:, None], ex.p[walker[order]], np.roll(Q[order], 1, axis=0))
        prev_n = np.where(first[:, None], ex.n[walker[order]], np.roll(n[order], 1, axis=0))
        prev_sil = np.where(first, ex.s_sil[walker[order]], np.roll(sil[order], 1))
        prev_curv = np.where(first, ex.s_curv[walker[order]], np.roll(cq["mean"][order], 1))
        prev_sug = np.where(first, ex.s_sug[walker[order]], np.roll(sug[order], 1))
        P = Q[order]
        near = np.linalg.norm(P - prev_p, axis=1) <= JUMP * STEP * bb.h
        found = {}
        if "silhouette" in self.kinds:
            found["silhouette"] = (prev_sil > 0) != (sil[order] > 0)
        if "curvature" in self.kinds:
            curv = cq["mean"][order]
            found["curvature"] = np.isfinite(curv) & np.isfinite(prev_curv) & ((prev_curv > 0) != (curv > 0))
        if "suggestive" in self.kinds:              # on the side facing the eye
            s = sug[order]
            found["suggestive"] = np.isfinite(s) & np.isfinite(prev_sug) & ((prev_sug > 0) != (s > 0)) & \
                (sil[order] > 0) & (prev_sil > 0)
        if "crease" in self.kinds:
            found["crease"] = np.arccos(np.clip(np.einsum("ij,ij->i", prev_n, n[order]), -1, 1)) > self.crease_angle
        self.walked.append((prev_p[near], prev_n[near], P[near], n[order][near]))
        for kind in FEATURE_KINDS:
            if kind in found and (found[kind] & near).any():
                hit = found[kind] & near
                a, b = prev_p[hit], P[hit]
                bb.add_features(0.5 * (a + b), a, b, kind)
        self.pool.give_back(ex.agent.tolist())
        ex.keep(np.zeros(k, bool))
        return [rows]

    def walks(self):
        """The pairs of points the walks compared (A, nA, B, nB), all explorers'."""
        if not self.walked:
            return tuple(np.zeros((0, 3)) for _ in range(4))
        return tuple(np.concatenate(a) for a in zip(*self.walked))
