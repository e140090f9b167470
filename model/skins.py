"""A primitive's own surface (where its field alone is iso, in its own coordinates):
its area, points laid out area-uniformly from the unit square, its outward directions,
and how its area grows outwards. model.marks lays its marks out on them."""
import numpy as np

from . import primitives as PR

def unit(v):
    return v / np.maximum(np.linalg.norm(v, axis=1, keepdims=True), 1e-300)


def _offset(radius, strength, iso):
    """The distance from the skeleton of a lone primitive's iso-surface (half its radius
    where it has none: a strength at most iso)."""
    if 0 < iso < strength:
        return radius * np.sqrt(1.0 - (iso / strength) ** (1.0 / 3.0))
    return 0.5 * radius


def _frame(normal):
    """Two unit vectors completing ``normal`` (the rotation taking z to it)."""
    n = np.asarray(normal, float) / np.linalg.norm(normal)
    if n[2] < -0.999999:
        return np.array([1.0, 0, 0]), np.array([0, -1.0, 0]), n
    a = 1.0 / (1.0 + n[2])
    e1 = np.array([1.0 - a * n[0] * n[0], -a * n[0] * n[1], -n[0]])
    e2 = np.array([-a * n[0] * n[1], 1.0 - a * n[1] * n[1], -n[1]])
    return e1, e2, n


def _sphere(u, v):
    z = 1.0 - 2.0 * u
    r = np.sqrt(np.maximum(0.0, 1.0 - z * z))
    phi = 2.0 * np.pi * v
    return np.stack([r * np.cos(phi), r * np.sin(phi), z], axis=1)


def _solve(cdf, target, lo, hi, iters=40):
    """x in [lo, hi] with cdf(x) = target for an increasing cdf (bisection, vectorised)."""
    a, b = np.full(len(target), lo), np.full(len(target), hi)
    for _ in range(iters):
        m = 0.5 * (a + b)
        below = cdf(m) < target
        a, b = np.where(below, m, a), np.where(below, b, m)
    return 0.5 * (a + b)


class Shape:
    """A primitive's own surface: ``area``, ``centre`` and ``reach`` (the farthest its
    points are from the centre), and ``points(uv)``."""

    def __init__(self, node, iso):
        self.node = node
        self.kind = type(node).__name__.lower()
        self.prm = PR.pack([node])
        if self.kind != "segment":
            self.centre = np.asarray(node.center, float)
        self.d = d = _offset(node.radius, node.strength, iso)
        if self.kind == "point":
            self.area, self.reach = 4 * np.pi * d * d, d
        elif self.kind == "segment":
            self.L = float(np.linalg.norm(np.subtract(node.b, node.a)))
            self.area = 2 * np.pi * d * self.L + 4 * np.pi * d * d
            self.centre, self.reach = 0.5 * np.add(node.a, node.b), 0.5 * self.L + d
        elif self.kind == "circle":
            self.rc = float(node.circle_radius)
            self.area, self.reach = 4 * np.pi ** 2 * max(self.rc, d) * d, self.rc + d
        elif self.kind == "disc":
            self.rc = float(node.disc_radius)
            self.rim = 2 * np.pi * d * (np.pi * self.rc + 2 * d)
            self.area, self.reach = 2 * np.pi * self.rc ** 2 + self.rim, self.rc + d
        else:
            self.H = np.asarray(node.half_size, float) + d
            faces = np.array([self.H[1] * self.H[2], self.H[0] * self.H[2], self.H[0] * self.H[1]]) * 4
            self.faces = np.repeat(faces, 2)
            self.area, self.reach = float(self.faces.sum()), float(np.linalg.norm(self.H))

    def points(self, uv):
        return getattr(self, "_" + self.kind)(uv[:, 0], uv[:, 1])

    def growth(self, Q):
        """How the area about points Q (n, 3) grows with the distance from the skeleton:
        the power of (d + t) / d (2 round a point or a segment's caps, 1 along a side, a
        circle or a disc's rim, 0 on flat faces)."""
        n = len(Q)
        if self.kind == "point":
            return np.full(n, 2.0)
        prm = self.prm
        if self.kind == "segment":
            A, AB = prm["A"][0], prm["AB"][0]
            t = (Q - A) @ AB * prm["invL2"][0]
            return np.where((t <= 0) | (t >= 1), 2.0, 1.0)
        if self.kind == "circle":
            return np.ones(n)
        if self.kind == "disc":
            D = Q - prm["C"][0]
            h = D @ prm["Nrm"][0]
            rho = np.linalg.norm(D - h[:, None] * prm["Nrm"][0], axis=1)
            return np.where(rho > self.rc * (1 - 1e-9), 1.0, 0.0)
        return np.zeros(n)

    def normals(self, Q):
        """Unit directions away from the skeleton at points Q (n, 3) of the surface."""
        _, V = PR.dist2(np.ascontiguousarray(Q.T), self.prm)
        return unit(V.T)

    def _point(self, u, v):
        return np.asarray(self.node.center, float) + self.d * _sphere(u, v)

    def _segment(self, u, v):
        """A capsule by area along its profile: cap at a, the side, cap at b."""
        A, B, d, L = np.asarray(self.node.a, float), np.asarray(self.node.b, float), self.d, self.L
        axis = (B - A) / L if L > 0 else np.array([0, 0, 1.0])
        e1, e2, _ = _frame(axis)
        cap = 2 * np.pi * d * d
        s = u * self.area
        phi = 2 * np.pi * v
        ring = np.cos(phi)[:, None] * e1 + np.sin(phi)[:, None] * e2
        out = np.empty((len(u), 3))
        a = s < cap                                         # the cap at a: 1 - cos(theta) = s / (2 pi d^2)
        c = np.clip(1.0 - s[a] / (2 * np.pi * d * d), -1, 1)
        out[a] = A + d * (np.sqrt(1 - c * c)[:, None] * ring[a] - c[:, None] * axis)
        side = (s >= cap) & (s < cap + 2 * np.pi * d * L)
        t = (s[side] - cap) / (2 * np.pi * d)
        out[side] = A + t[:, None] * axis + d * ring[side]
        b = ~(a | side)
        c = np.clip(1.0 - (self.area - s[b]) / (2 * np.pi * d * d), -1, 1)
        out[b] = B + d * (np.sqrt(1 - c * c)[:, None] * ring[b] + c[:, None] * axis)
        return out

    def _circle(self, u, v):
        """A torus (area density grows with the distance from the axis)."""
        rc, d = self.rc, self.d
        e1, e2, n = _frame(self.node.normal)
        phi = 2 * np.pi * u
        big = max(rc, d)
        psi = _solve(lambda p: (big * p + d * np.sin(p)) / (2 * np.pi * big), v, 0.0, 2 * np.pi)
        ring = np.cos(phi)[:, None] * e1 + np.sin(phi)[:, None] * e2
        return (np.asarray(self.node.center, float) + (rc + d * np.cos(psi))[:, None] * ring
                + (d * np.sin(psi))[:, None] * n)

    def _disc(self, u, v):
        """Top face, the rim (half a torus), bottom face, by area."""
        rc, d = self.rc, self.d
        e1, e2, n = _frame(self.node.normal)
        face = np.pi * rc * rc
        s = u * self.area
        phi = 2 * np.pi * v
        ring = np.cos(phi)[:, None] * e1 + np.sin(phi)[:, None] * e2
        C = np.asarray(self.node.center, float)
        out = np.empty((len(u), 3))
        top = s < face
        out[top] = C + (rc * np.sqrt(s[top] / face))[:, None] * ring[top] + d * n
        bottom = s >= face + self.rim
        out[bottom] = C + (rc * np.sqrt((self.area - s[bottom]) / face))[:, None] * ring[bottom] - d * n
        rim = ~(top | bottom)
        # psi from pi/2 (top) to -pi/2; the rim's area from the top to psi
        def cdf(p):
            return 2 * np.pi * d * (rc * (np.pi / 2 - p) + d * (1 - np.sin(p)))
        psi = _solve(lambda p: -cdf(p), -(s[rim] - face), -np.pi / 2, np.pi / 2)
        out[rim] = C + (rc + d * np.cos(psi))[:, None] * ring[rim] + (d * np.sin(psi))[:, None] * n
        return out

    def _box(self, u, v):
        """The six faces of the box grown by the offset, by area."""
        H = self.H
        C = np.asarray(self.node.center, float)
        edges = np.concatenate([[0.0], np.cumsum(self.faces)])
        s = u * self.area
        face = np.clip(np.searchsorted(edges, s, side="right") - 1, 0, 5)
        w = (s - edges[face]) / self.faces[face]
        axis, sign = face // 2, np.where(face % 2 == 0, 1.0, -1.0)
        a1, a2 = (axis + 1) % 3, (axis + 2) % 3
        out = np.empty((len(u), 3))
        rows = np.arange(len(u))
        out[rows, axis] = sign * H[axis]
        out[rows, a1] = (2 * w - 1) * H[a1]
        out[rows, a2] = (2 * v - 1) * H[a2]
        return C + out
