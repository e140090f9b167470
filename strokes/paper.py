"""The paper: where the eye sees points of the model, for the marks whose spacing and
size are decided as drawn (Vanderhaeghe et al. 2007: marks fixed on the object,
density decided on the screen). A point's place on the paper is where it falls on the
picture plane through the model's centre (right and up as the view's: strokes.style.
view_right), so that distances between places are lengths on the paper in model units
at the model's distance, perspective included; a length across the line of sight at
the point itself is that many times ``scale`` there."""
import numpy as np

from ..model.vectors import cross


class Paper:
    def __init__(self, eye, centre):
        self.eye = np.asarray(eye, float)
        forward = np.asarray(centre, float) - self.eye
        self.reach = float(np.linalg.norm(forward)) or 1.0
        forward = forward / self.reach if np.linalg.norm(forward) > 0 else np.array([0.0, 1.0, 0.0])
        up = np.array([0.0, 0.0, 1.0]) if abs(forward[2]) < 0.99 else np.array([0.0, 1.0, 0.0])
        right = cross(forward, up)
        right /= np.linalg.norm(right)
        self.axes = np.stack([right, cross(right, forward), forward], axis=1)

    def place(self, P):
        """Places on the paper of points (n, 3) (x, y and a 0, so that 3-d neighbour
        searches take them), and how much a length across the line of sight at each
        point grows there (the model centre's depth over its own)."""
        rel = (np.asarray(P, float).reshape(-1, 3) - self.eye) @ self.axes
        scale = self.reach / np.maximum(rel[:, 2], 1e-300)
        return np.column_stack([rel[:, 0] * scale, rel[:, 1] * scale, np.zeros(len(rel))]), scale

    def facing(self, P, N):
        """Whether the surface at points P with outward normals N faces the eye."""
        return np.einsum("ij,ij->i", np.asarray(N, float), self.eye - np.asarray(P, float)) > 0


class Placed:
    """The marks a layer placed so far, over its parts, on the paper: their places and
    each one's reach (half the spacing its tone asks for there)."""

    def __init__(self):
        self.places, self.reach = np.zeros((0, 3)), np.zeros(0)

    def add(self, places, reach):
        self.places = np.vstack([self.places, places])
        self.reach = np.concatenate([self.reach, reach])


BIN = 2.0               # close_pairs sorts reaches into bins this many times wider than the last


def close_pairs(A, ra, B, rb):
    """Index pairs (i, j), i sorted, of places A[i] and B[j] on the paper (or of points in
    space) closer than twice
    the smaller of their reaches ra[i], rb[j] (each point keeps its own spacing from the
    points as dense as it or denser: a sparse point beside a dense region does not clear
    a hole in it). The reaches are sorted into bins (each BIN times the last); each bin's
    points are paired with the other set's in its bin or above, hashed at its own
    largest reach."""
    A, B = np.asarray(A, float).reshape(-1, 3), np.asarray(B, float).reshape(-1, 3)
    ra, rb = np.asarray(ra, float), np.asarray(rb, float)
    none = np.zeros(0, np.int64)
    if len(A) == 0 or len(B) == 0:
        return none, none
    top = max(ra.max(), rb.max())
    if not top > 0:
        return none, none
    low = max(min(ra.min(), rb.min()), top * 1e-6)
    ba = np.floor(np.log(np.maximum(ra, low) / low) / np.log(BIN)).astype(int)
    bb = np.floor(np.log(np.maximum(rb, low) / low) / np.log(BIN)).astype(int)
    I, J = [], []
    for k in np.union1d(ba, bb):
        for mine, theirs, flip in ((ba == k, bb >= k, False), (bb == k, ba > k, True)):
            a, b = np.flatnonzero(mine), np.flatnonzero(theirs)
            if len(a) == 0 or len(b) == 0:
                continue
            X, rx, Y, ry = (B, rb, A, ra) if flip else (A, ra, B, rb)
            i, j = _pairs(X[a], Y[b], 2.0 * rx[a].max())
            i, j = a[i], b[j]
            near = ((X[i] - Y[j]) ** 2).sum(1) < (2.0 * np.minimum(rx[i], ry[j])) ** 2
            I.append(j[near] if flip else i[near])
            J.append(i[near] if flip else j[near])
    if not I:
        return none, none
    i, j = np.concatenate(I), np.concatenate(J)
    order = np.argsort(i, kind="stable")
    return i[order], j[order]


def _pairs(A, B, r):
    """Pairs closer than r: of places on the paper (a 0 third coordinate) in the plane,
    of points in space otherwise."""
    if not (A[:, 2].any() or B[:, 2].any()):
        return pairs_2d(A, B, r)
    from ..blackboard.cells import pairs_within
    return pairs_within(A, B, r)


def pairs_2d(A, B, r):
    """Index pairs (i, j) of places A[i] and B[j] on the paper (their x and y) closer than
    r: B hashed in square cells of at least r, each place of A looking at the three rows
    of three cells about its own (a row's three cells one range of the sorted keys)."""
    A, B = np.asarray(A, float)[:, :2], np.asarray(B, float)[:, :2]
    none = np.zeros(0, np.int64)
    if len(A) == 0 or len(B) == 0 or not r > 0:
        return none, none
    lo = np.minimum(A.min(0), B.min(0))
    span = float(max((A.max(0) - lo).max(), (B.max(0) - lo).max()))
    cell = max(float(r), span / 2.0 ** 30)
    ia, ib = np.floor((A - lo) / cell).astype(np.int64) + 1, np.floor((B - lo) / cell).astype(np.int64) + 1
    width = int(max(ia[:, 0].max(), ib[:, 0].max())) + 2
    kb = ib[:, 1] * width + ib[:, 0]
    order = np.argsort(kb, kind="stable")
    kb = kb[order]
    I, J = [], []
    for dy in (-1, 0, 1):
        first = (ia[:, 1] + dy) * width + ia[:, 0] - 1
        start = np.searchsorted(kb, first, "left")
        count = np.searchsorted(kb, first + 2, "right") - start
        i = np.repeat(np.arange(len(A)), count)
        j = order[np.arange(int(count.sum())) - np.repeat(np.cumsum(count) - count - start, count)]
        near = ((A[i] - B[j]) ** 2).sum(-1) < r * r
        I.append(i[near])
        J.append(j[near])
    i, j = np.concatenate(I), np.concatenate(J)
    o = np.argsort(i, kind="stable")
    return i[o], j[o]
