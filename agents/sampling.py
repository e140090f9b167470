"""What a sampling session hands out (agents.session.Session.snapshot): plain data the
stroke layers read, never the session's internals."""
from dataclasses import dataclass, field

import numpy as np


@dataclass(frozen=True)
class Sampling:
    """The outlines found so far (stitched, agents.outline.Outline), the rough
    polygonisation (vertices on the surface and quads indexing them), each vertex's
    normal and curvature (model.curvature's dict: normal, k1, k2, mean, gauss, dir1,
    dir2, grad_norm), the blackboard's cell size, the progress figures and whether the
    session is done."""
    outlines: list
    vertices: np.ndarray
    quads: np.ndarray
    vertex_normals: np.ndarray
    vertex_curvature: dict
    cell: float
    progress: dict = field(default_factory=dict)
    done: bool = False

    def face_centres(self):
        """Centres and normals of the rough polygonisation's faces."""
        q = self.quads
        C = self.vertices[q].mean(axis=1)
        N = self.vertex_normals[q].sum(axis=1)
        return C, N / np.maximum(np.linalg.norm(N, axis=1, keepdims=True), 1e-300)
