"""Regions a request can be restricted to: a box or a sphere (plain data)."""
import numpy as np


class Region:
    def __init__(self, box=None, sphere=None):
        if (box is None) == (sphere is None):
            raise ValueError("a region is either a box (lo, hi) or a sphere (center, radius)")
        self.box = None if box is None else (np.asarray(box[0], float), np.asarray(box[1], float))
        self.sphere = None if sphere is None else (np.asarray(sphere[0], float), float(sphere[1]))
        vals = [*self.box] if self.box else [self.sphere[0], np.array([self.sphere[1]])]
        if not all(np.all(np.isfinite(v)) for v in vals):
            raise ValueError("region bounds must be finite")
        if self.box is not None and np.any(self.box[1] < self.box[0]):
            raise ValueError("region box must have lo <= hi")
        if self.sphere is not None and not self.sphere[1] > 0:
            raise ValueError("region sphere radius must be > 0")

    def contains(self, P):
        P = np.atleast_2d(P)
        if self.box is not None:
            return np.all((P >= self.box[0]) & (P <= self.box[1]), axis=1)
        return np.linalg.norm(P - self.sphere[0], axis=1) <= self.sphere[1]
