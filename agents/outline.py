"""Feature outlines as plain data: polylines by kind, each point with its normal, and
the step they were traced with."""
from dataclasses import dataclass

import numpy as np

from .stitch import stitch


@dataclass
class Outline:
    kind: str
    points: np.ndarray
    normals: np.ndarray
    closed: bool
    step: float = 0.0           # the trace step it was traced with (0: not known)

    @property
    def length(self):
        p = np.vstack([self.points, self.points[:1]]) if self.closed else self.points
        return float(np.linalg.norm(np.diff(p, axis=0), axis=1).sum())


def total_length(outlines):
    """The summed length of outlines (their segments in one batch; a closed one's
    closing segment included)."""
    outlines = [o for o in outlines if len(o.points)]
    if not outlines:
        return 0.0
    P = np.concatenate([np.vstack([o.points, o.points[:1]]) if o.closed else o.points for o in outlines])
    seg = np.linalg.norm(np.diff(P, axis=0), axis=1)
    ends = np.cumsum([len(o.points) + bool(o.closed) for o in outlines])[:-1] - 1   # no segment across outlines
    seg[ends] = 0.0
    return float(seg.sum())


def stitch_scales(outlines, link=2.5):
    """Fragments stitched into whole polylines with those traced at their own scale
    (within ``link`` of their step): a subdivided voxel's small outlines (a wheel's
    holes) lie closer together than the session's step."""
    out = []
    for step in sorted({o.step for o in outlines}):
        out += stitch([o for o in outlines if o.step == step], link * step,
                      lambda *a, step=step: Outline(*a, step=step))
    return out
