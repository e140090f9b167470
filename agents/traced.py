"""Points of the outlines traced so far, hashed by cells of one trace step: which
outline is near a point (to start no second trace on it, to stop a trace that meets
another, or closes on itself); and which open seeds new trace points cover."""
import math
from itertools import product

import numpy as np

from ..blackboard.board import FEATURE_KINDS, KIND_ID

SELF_GAP = 6        # steps along an outline within which its own points do not stop it


class TracedPoints:
    def __init__(self, step_len, crease_angle):
        self.step_len = step_len
        self.cos_sheet = np.cos(0.5 * crease_angle)
        self.table = {k: {} for k in range(len(FEATURE_KINDS))}   # kind -> cell -> entries

    def _cell(self, x, y, z):
        s = self.step_len
        return math.floor(x / s), math.floor(y / s), math.floor(z / s)

    def remember(self, kind, p, tid, arc, n, step=None):
        """A traced point, with its outline's id, its step index along the outline
        (0 the seed, + forwards, - backwards), its normal and its outline's step (default
        the session's; at most that). Kept as Python floats: :meth:`near` runs once per
        task and iteration, and scalar numpy arithmetic cost it most of its time."""
        step = self.step_len if step is None else step
        q = (float(p[0]), float(p[1]), float(p[2]))
        qn = (float(n[0]), float(n[1]), float(n[2]))
        self.table[kind].setdefault(self._cell(*q), []).append((tid, q, arc, qn, float(step)))

    def points(self):
        """Every traced point, of every kind, as an (m, 3) array."""
        pts = [p for table in self.table.values() for items in table.values() for _, p, _, _, _ in items]
        return np.array(pts).reshape(-1, 3)

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
        sheet = n is not None and kind != KIND_ID["crease"]
        px, py, pz = float(p[0]), float(p[1]), float(p[2])
        if sheet:
            nx, ny, nz = float(n[0]), float(n[1]), float(n[2])
        cx, cy, cz = self._cell(px, py, pz)
        cos = self.cos_sheet
        radius = float(radius)
        get = self.table[kind].get
        # the 27 cells around p, in the order of nested loops over dx, dy, dz
        for key in product((cx - 1, cx, cx + 1), (cy - 1, cy, cy + 1), (cz - 1, cz, cz + 1)):
            for tid, q, qa, qn, qs in get(key, ()):
                if tid == own and (arc is None or abs(arc - qa) <= SELF_GAP):
                    continue
                if sheet and qn[0] * nx + qn[1] * ny + qn[2] * nz < cos:
                    continue
                r = max(radius, 0.6 * qs)
                ex, ey, ez = q[0] - px, q[1] - py, q[2] - pz
                if ex * ex + ey * ey + ez * ez < r * r:
                    return (tid, qa)
        return None


def consume_crossed(session, kinds, X, n, W, steps):
    """A session's open seeds whose bracket (a polygon edge, or a finer one) crosses this
    iteration's new trace points' outline are taken as traced: its ends lie on
    either side of the plane through a new point X across ``W`` (silhouettes and
    curvature-sign lines: n x T; creases: their ref, the side normals' difference),
    and where it crosses that plane is within 0.75 of its cell (a voxel, or a
    subdivided voxel's fine cell), or of the covering trace's step if longer, of X.
    A seed merely near X is not taken: a parallel outline half a cell away (the two
    silhouettes of a fold, a suture's crease beside them) keeps its seeds. Nor
    (silhouettes, curvature-sign lines) is one whose normal shows it on another
    sheet: the inner and outer silhouettes of a thin lip lie that close."""
    cos = np.cos(0.5 * session.settings.crease_angle)
    f = session.bb.feat
    for k in np.unique(kinds):
        m = kinds == k
        ids, j = session.bb.open_near(X[m], FEATURE_KINDS[k], 1.5 * session.h)
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
            _, g = session.ev.field_grad(f["a"][ids])
            ids = ids[np.einsum("ij,ij->i", session.surface.normals(g), n[m][j]) > cos]
        session.bb.consume(ids)
