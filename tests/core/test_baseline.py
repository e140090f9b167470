"""The Witkin-Heckbert baseline on the same evaluator: random-ray particles that repel,
and outlines traced only where neighbouring particles happen to straddle them."""
import math

import numpy as np

from blobtree_ink import model as M
from blobtree_ink.agents.baseline import Baseline
from blobtree_ink.blackboard.view import View

K = math.sqrt(1 - 0.5 ** (1 / 3))


def test_particles_start_on_the_surface_and_find_the_silhouette():
    ev = M.Evaluator(M.from_dict({"format": "blobtree-1", "root": {"type": "point", "center": [0, 0, 0],
                                                                   "radius": 1.0}}))
    view = View(direction=(0, 0, 1))
    b = Baseline(ev, view, particles=300, seed=2)
    assert len(b.P) == 300
    assert np.abs(ev.field(b.P) - 0.5).max() < 1e-9
    b.run(iterations=3)
    assert np.abs(ev.field(b.P) - 0.5).max() < 1e-9          # repulsion keeps them on the surface
    sil = [o for o in b.outlines() if o.kind == "silhouette"]
    assert sil
    pts = np.concatenate([o.points for o in sil])
    assert np.abs(np.linalg.norm(pts[:, :2], axis=1) - K).max() < 1e-6 and np.abs(pts[:, 2]).max() < 1e-6
    assert sum(o.length for o in sil) > 0.9 * 2 * math.pi * K


def test_a_step_respects_its_time_budget():
    ev = M.Evaluator(M.from_dict({"format": "blobtree-1", "root": {"type": "circle", "center": [0, 0, 0],
                                                                   "normal": [0, 0, 1], "circle_radius": 1.0,
                                                                   "radius": 0.8}}))
    b = Baseline(ev, View(direction=(0, 1, -1)), particles=300, seed=0)
    P0 = b.P.copy()
    b.step(budget=0.0)                   # no time for new finds: the particles still move
    assert b.iteration == 1 and not b.found
    assert np.abs(b.P - P0).max() > 0
