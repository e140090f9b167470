"""The settings of a sampling session (agents.session), checked before it starts."""
from dataclasses import dataclass

import numpy as np

from ..blackboard.board import FEATURE_KINDS
from ..model.tolerances import OUTLINE


@dataclass
class Settings:
    resolution: int = 20               # about resolution^3 cubic grid cells over the model (8..128)
    agents: int = 10000                # agents stepped together; more agents, fewer (larger) iterations
    lod: float = 0.5                   # user level of detail, 0..1
    step: float = 0.3                  # trace step, in voxel sizes
    tolerance: float = OUTLINE         # outline location, as a fraction of the model's size
    crease_angle: float = float(np.radians(35.0))
    kinds: tuple = ("silhouette", "crease")      # add "curvature" for curvature-sign lines, "suggestive" for
                                                 # suggestive contours, "ridges" for apparent ridges
    explore_steps: int = 24
    explore_detail: bool = True        # after the edge seeds, explore voxels flagged for detail
    subdivide: int = 6                 # fine cells per side of the subdivided voxels (0: none)
    max_outline_steps: int = 20000
    seed: int = 0

    def check(self):
        if not (isinstance(self.resolution, (int, np.integer)) and 8 <= self.resolution <= 128):
            raise ValueError(f"resolution must be a whole number from 8 to 128, got {self.resolution!r}")
        if not (isinstance(self.agents, (int, np.integer)) and 1 <= self.agents <= 10000):
            raise ValueError(f"agents must be a whole number from 1 to 10000, got {self.agents!r}")
        for name, lo, hi in (("lod", 0, 1), ("step", 0.01, 2), ("tolerance", 1e-12, 1e-2),
                             ("crease_angle", 0.01, 3.1)):
            v = getattr(self, name)
            if not (isinstance(v, (int, float)) and np.isfinite(v) and lo <= v <= hi):
                raise ValueError(f"{name} must be a number from {lo} to {hi}, got {v!r}")
        if isinstance(self.seed, bool) or not (isinstance(self.seed, (int, np.integer)) and 0 <= self.seed < 2**63):
            raise ValueError(f"seed must be a whole number from 0, got {self.seed!r}")
        if not (isinstance(self.subdivide, (int, np.integer)) and (self.subdivide == 0 or 2 <= self.subdivide <= 16)):
            raise ValueError(f"subdivide must be 0 or a whole number from 2 to 16, got {self.subdivide!r}")
        bad = [k for k in self.kinds if k not in FEATURE_KINDS]
        if bad or not self.kinds:
            raise ValueError(f"lines (the kinds of feature outline) must be one or more of {', '.join(FEATURE_KINDS)}, "
                             f"got {', '.join(map(str, self.kinds)) or 'none'}")
