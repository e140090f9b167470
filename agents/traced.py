"""Points of the outlines traced so far, hashed by cells of one trace step: which
outline is near a point (to start no second trace on it, to stop a trace that meets
another, or closes on itself)."""
import numpy as np

from ..blackboard.board import FEATURE_KINDS, KIND_ID

SELF_GAP = 6        # steps along an outline within which its own points do not stop it


class TracedPoints:
    def __init__(self, step_len, crease_angle):
        self.step_len = step_len
        self.cos_sheet = np.cos(0.5 * crease_angle)
        self.table = {k: {} for k in range(len(FEATURE_KINDS))}   # kind -> cell -> entries

    def _cell(self, p):
        return tuple(np.floor(p / self.step_len).astype(int))

    def remember(self, kind, p, tid, arc, n, step=None):
        """A traced point, with its outline's id, its step index along the outline
        (0 the seed, + forwards, - backwards), its normal and its outline's step (default
        the session's; at most that)."""
        step = self.step_len if step is None else step
        self.table[kind].setdefault(self._cell(p), []).append((tid, p, arc, n, step))

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
        c = self._cell(p)
        table = self.table[kind]
        for dx in (-1, 0, 1):
            for dy in (-1, 0, 1):
                for dz in (-1, 0, 1):
                    for tid, q, qa, qn, qs in table.get((c[0] + dx, c[1] + dy, c[2] + dz), ()):
                        if tid == own and (arc is None or abs(arc - qa) <= SELF_GAP):
                            continue
                        if sheet and qn @ n < self.cos_sheet:
                            continue
                        if np.linalg.norm(q - p) < max(radius, 0.6 * qs):
                            return (tid, qa)
        return None
