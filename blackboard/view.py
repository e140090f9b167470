"""The view the illustration is made for: perspective (an eye point) or orthographic
(a viewing direction). ``towards_eye(P)`` is the unit vector from each point to the
viewer; the silhouette is where the outward normal is perpendicular to it."""
import numpy as np


class View:
    def __init__(self, eye=None, direction=None):
        if (eye is None) == (direction is None):
            raise ValueError("a view needs exactly one of eye (perspective) or direction (orthographic)")
        self.eye = None if eye is None else np.asarray(eye, float)
        self.direction = None
        if direction is not None:
            d = np.asarray(direction, float)
            n = np.linalg.norm(d)
            if not np.isfinite(n) or n == 0:
                raise ValueError(f"view direction must be a non-zero finite vector, got {direction}")
            self.direction = d / n
        if self.eye is not None and not np.all(np.isfinite(self.eye)):
            raise ValueError(f"eye must be finite, got {eye}")

    def towards_eye(self, P):
        if self.eye is None:
            return np.broadcast_to(-self.direction, np.shape(P)).copy()
        v = self.eye - P
        return v / np.maximum(np.linalg.norm(v, axis=-1, keepdims=True), 1e-300)

    def key(self):
        return ("eye", tuple(self.eye)) if self.eye is not None else ("dir", tuple(self.direction))
