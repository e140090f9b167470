"""A smooth cross field on the surface for hatching (Hertzmann and Zorin 2000): the
principal directions where they are reliable, and a smooth interpolation of them where
they are not (near umbilics, on flat and spherical parts), so that hatching neither
zig-zags between the two principal directions nor fans out where they fade.

A cross is four directions at right angles about the normal; it is kept at nodes (the
model's own marks, so fixed on its parts), each as one of its directions, and compared
by the angle-times-four trick: a cross at angle a in a tangent frame is exp(4ia), so that
its four directions are one number. A node's reliability grows with how distinct its
principal curvatures are (|k1 - k2| over |k1| + |k2|) and how strongly the surface bends
there against the model's size; smoothing averages each node's cross with its
neighbours' (those within a radius whose normals agree, carried into its tangent plane),
the reliable nodes held to their principal directions. The field at any point is the
weighted mean of the nodes about it, carried into its tangent plane.
"""
import numpy as np

from ..blackboard.cells import PointHash, pairs_within
from ..model.curvature import curvature, tangent_basis

ITERATIONS = 60         # smoothing sweeps
HOLD = 8.0              # how strongly a fully reliable node keeps its principal directions (per neighbour)
DISTINCT = (0.04, 0.2)  # (|k1 - k2| / (|k1| + |k2|)): no weight below the first, full weight above the second
BENT = (0.3, 1.5)       # |k1 - k2| times the model's size: no weight below the first, full above the second
AGREE = 0.5             # nodes whose normals' cosine is below this are on other sheets: never neighbours
REACH = 1.6             # the neighbourhood's radius, in node spacings
GUESS = 0.5            # how strongly a node with no reliable directions keeps the level direction (per neighbour)
UP = np.array([0.0, 0.0, 1.0])
ROUND = 0.5             # below this reliability a node's first line is the one nearer the level line
SWEEPS = 40             # sweeps that shorten the seams between parts whose first lines differ, at most
SAME = 0.5              # two lines of a cross whose directions' |cosine| is at least this are one line


def reliability(c, size):
    """How much a point's principal directions are to be believed (0..1)."""
    k1, k2 = np.asarray(c["k1"], float), np.asarray(c["k2"], float)
    gap = np.nan_to_num(np.abs(k1 - k2))
    distinct = gap / np.maximum(np.nan_to_num(np.abs(k1) + np.abs(k2)), 1e-300)
    return _ramp(distinct, *DISTINCT) * _ramp(gap * size, *BENT)


def _ramp(x, a, b):
    t = np.clip((x - a) / (b - a), 0.0, 1.0)
    return t * t * (3 - 2 * t)


def _crosses(D, e1, e2, fold=4):
    """exp(4ia) of directions D (n, 3) in the frames (e1, e2) (exp(2ia) with ``fold`` 2:
    of lines), and how much of each lies in the plane (0 for a direction along the normal)."""
    a, b = np.einsum("ij,ij->i", D, e1), np.einsum("ij,ij->i", D, e2)
    z = (a + 1j * b) ** fold
    m = np.abs(z)
    return np.where(m > 0, z / np.maximum(m, 1e-300), 0.0), m ** (2.0 / fold)


def _direction(z, e1, e2, fold=4):
    """One direction (unit, in the frames) of the crosses exp(4ia) z (lines exp(2ia) with
    ``fold`` 2)."""
    a = np.angle(z) / fold
    return np.cos(a)[:, None] * e1 + np.sin(a)[:, None] * e2


def _labelled(dirs, normals, e1, e2, i, j, g, dir1, level, weight):
    """Which of each node's two cross lines is the first (n, 3). Where the principal
    directions mean little (weight below ROUND) it is the line nearer the level line, so
    that round parts are hatched round; from there it is carried from node to neighbour
    into the reliable parts, each node taking the line nearer its labelled neighbours'
    mean, so that the first layer runs on continuously where the principal curvatures
    trade places (round a bulb's shoulder) instead of turning through a right angle. A
    reliable part no such node reaches starts at its most reliable node, on the line
    nearer its principal direction dir1. Pairs (i, j) with weights g."""
    n = len(dirs)
    other = np.cross(normals, dirs)
    zd, _ = _crosses(dirs, e1, e2, 2)             # the two lines are zd and -zd
    first = _nearer(dirs, other, level)
    done = weight < ROUND
    order = np.argsort(-weight, kind="stable")
    start = 0
    while True:
        grew = True
        while grew:
            k = ~done[i] & done[j]
            ii, jj = i[k], j[k]
            zj, inplane = _crosses(first[jj], e1[ii], e2[ii], 2)
            total = (np.bincount(ii, g[k] * inplane * zj.real, n) + 1j * np.bincount(ii, g[k] * inplane * zj.imag, n))
            new = ~done & (np.bincount(ii, minlength=n) > 0)
            grew = bool(new.any())
            near_d = (np.conj(zd) * total).real >= 0
            first[new] = np.where(near_d[new][:, None], dirs[new], other[new])
            done |= new
        if done.all():
            return _seams_shortened(first, dirs, other, level, weight, i, j, g)
        while done[order[start]]:
            start += 1
        s = order[start]
        first[s] = _nearer(dirs[s:s + 1], other[s:s + 1], dir1[s:s + 1])[0]
        done[s] = True


def _seams_shortened(first, dirs, other, level, weight, i, j, g):
    """The first lines relabelled so that the seams where they turn through a right angle
    are short and few: each node takes, of its two lines, the one its neighbours' first
    lines (weights g) lie nearer, leaning to the level line as much as its principal
    directions mean little; half the nodes (by a fixed alternation) at a sweep, until
    none changes. A patch whose first line runs across all about it goes over to theirs;
    a seam that must be (where the field turns round a point) straightens and shortens."""
    n = len(first)
    lean = np.bincount(i, g, n) * (1.0 - weight) * np.clip(1.0 - weight / ROUND, 0.0, 1.0)
    lean *= np.einsum("ij,ij->i", level, dirs) ** 2 - np.einsum("ij,ij->i", level, other) ** 2
    half = (np.arange(n) * 0x9E3779B1 >> 7) & 1
    still = 0                                       # sweeps in a row that changed nothing
    for sweep in range(SWEEPS):
        fj = first[j]
        vote = g * (np.einsum("ij,ij->i", fj, dirs[i]) ** 2 - np.einsum("ij,ij->i", fj, other[i]) ** 2)
        score = np.bincount(i, vote, n) + lean
        want = np.where((score >= 0)[:, None], dirs, other)
        change = (np.abs(np.einsum("ij,ij->i", want, first)) < SAME) & (half == sweep % 2)
        still = 0 if change.any() else still + 1
        if still == 2:                              # neither half changes
            break
        first = np.where(change[:, None], want, first)
    return first


def _nearer(a, b, w):
    """Per row, the line a or b (n, 3) nearer the direction w."""
    pick = np.abs(np.einsum("ij,ij->i", a, w)) >= np.abs(np.einsum("ij,ij->i", b, w))
    return np.where(pick[:, None], a, b)


class CrossField:
    """The smoothed cross field of a model, at nodes (points and outward normals) ``spacing``
    apart; ``size``: the model's size (the square root of its surface's area)."""

    def __init__(self, ev, points, normals, spacing, size):
        self.points = np.asarray(points, float).reshape(-1, 3)
        self.normals = np.asarray(normals, float).reshape(-1, 3)
        self.radius = REACH * float(spacing)
        n = len(self.points)
        self.e1, self.e2 = tangent_basis(self.normals)
        if n == 0:
            self.dirs = self.first = np.zeros((0, 3))
            self.hash = PointHash(self.points, self.radius)
            return
        c = curvature(ev, self.points)
        self.weight = reliability(c, size)
        # where the principal directions mean nothing, start from (and lean a little to)
        # the level lines of the model's up: a sphere is hatched round, as artists do
        level = np.cross(self.normals, np.where(np.abs(self.normals @ UP)[:, None] < 0.99, UP, [1.0, 0.0, 0.0]))
        d1 = np.where((self.weight > 0)[:, None], np.nan_to_num(c["dir1"]), level)
        z0, _ = _crosses(d1, self.e1, self.e2)
        zl, _ = _crosses(level, self.e1, self.e2)
        i, j = pairs_within(self.points, self.points, self.radius)
        keep = (i != j) & (np.einsum("ij,ij->i", self.normals[i], self.normals[j]) > AGREE)
        i, j = i[keep], j[keep]
        dist = np.linalg.norm(self.points[i] - self.points[j], axis=1)
        g = (1.0 - (dist / self.radius) ** 2) ** 2
        degree = np.bincount(i, g, n)
        degree = np.maximum(degree, 1e-3)
        dirs = level.copy()               # (the principal directions come in through the held term alone, so
        for _ in range(ITERATIONS):       # the field is as continuous in them as their reliability)
            zj, inplane = _crosses(dirs[j], self.e1[i], self.e2[i])
            total = degree * (HOLD * self.weight * z0 + GUESS * (1.0 - self.weight) * zl)
            total = total + np.bincount(i, (g * inplane) * zj.real, n) + 1j * np.bincount(i, (g * inplane) * zj.imag, n)
            some = np.abs(total) > 0
            dirs[some] = _direction(total[some], self.e1[some], self.e2[some])
        self.dirs = dirs
        self.first = _labelled(dirs, self.normals, self.e1, self.e2, i, j, g, np.nan_to_num(c["dir1"]), level,
                               self.weight)
        self.hash = PointHash(self.points, self.radius)

    def at(self, P, N, fallback):
        """One direction of the cross at points P (n, 3) with outward normals N: the
        nodes within reach weighed by distance (those on other sheets left out), carried
        into each point's tangent plane; ``fallback`` (n, 3) where no node is near."""
        return self._mean(P, N, fallback, self.dirs, 4)

    def first_at(self, P, N, fallback):
        """The first of the cross's two lines at points P (n, 3) with outward normals N
        (the one the first hatching layer follows, its sign meaningless), as :meth:`at`."""
        return self._mean(P, N, fallback, self.first, 2)

    def _mean(self, P, N, fallback, dirs, fold):
        P, N = np.asarray(P, float).reshape(-1, 3), np.asarray(N, float).reshape(-1, 3)
        out = np.array(fallback, float).reshape(-1, 3)
        if len(P) == 0 or len(self.points) == 0:
            return out
        i, j = self.hash.pairs(P)
        keep = np.einsum("ij,ij->i", N[i], self.normals[j]) > AGREE
        i, j = i[keep], j[keep]
        e1, e2 = tangent_basis(N)
        zj, inplane = _crosses(dirs[j], e1[i], e2[i], fold)
        dist = np.linalg.norm(P[i] - self.points[j], axis=1)
        g = (1.0 - (dist / self.radius) ** 2) ** 2 * inplane
        n = len(P)
        total = np.bincount(i, g * zj.real, n) + 1j * np.bincount(i, g * zj.imag, n)
        some = np.abs(total) > 1e-9 * np.maximum(np.bincount(i, g, n), 1e-300)
        out[some] = _direction(total[some], e1[some], e2[some], fold)
        return out


def branch(cross, normals, along):
    """Of the four directions of the crosses (one of them: ``cross``), the one nearest
    ``along`` (n, 3): a heading or a wanted direction."""
    pick = _nearer(cross, np.cross(normals, cross), along)
    s = np.sign(np.einsum("ij,ij->i", pick, along))
    return pick * np.where(s == 0, 1.0, s)[:, None]


def turned(cross, normals, degrees):
    """The crosses turned about the normals (45: the diagonals)."""
    t = np.radians(degrees)
    return np.cos(t) * cross + np.sin(t) * np.cross(normals, cross)
