"""Creases end where they run into another crease or a third part (a triple junction):
every crease point sits where the normal really jumps (tests/core/truth.py, from the
exact field alone)."""
import numpy as np
import pytest

from blobtree_ink import model as M
from blobtree_ink.agents import Session, Settings
from blobtree_ink.blackboard.view import View

import truth

R_POINT = 2.0 * 0.45428                 # a lone point of radius 2 meets iso 0.5 here
RIM = np.sqrt(R_POINT ** 2 - 0.5 ** 2)  # the lens's rim circle, in z = 0
TUBE = 0.6 * 0.45428                    # the segment's tube radius


def lens_and_tube():
    """A lens (the intersection of two balls; a sharp rim) with a tube through its rim
    (a union): the tube's creases on the lens's faces run into the rim at (x, +-TUBE, 0)."""
    def point(c):
        return {"type": "point", "center": c, "radius": 2.0}
    return M.from_dict({"format": "blobtree-1", "root": {"type": "union", "children": [
        {"type": "intersection", "children": [point([0, 0, -0.5]), point([0, 0, 0.5])]},
        {"type": "segment", "a": [-0.2, 0, 0], "b": [1.5, 0, 0], "radius": 0.6}]}})


@pytest.mark.parametrize("res", [16, 20])
def test_creases_end_at_a_triple_junction(res):
    model = lens_and_tube()
    s = Session(model, View(eye=np.array([3.0, -4.0, 2.5])), Settings(resolution=res))
    s.request("OUTLINES")
    s.run()
    X = np.concatenate([o.points for o in s.outlines() if o.kind == "crease"])
    # no crease point where there is no crease (the two pinned sheets meet on past the
    # rim, across the tube's smooth side: a quarter of the points did)
    assert truth.on_a_crease(s.ev, X).all()
    # ... and the creases are all there: the rim outside the tube, and the tube's creases
    # on both faces up to the junctions
    a = np.linspace(0, 2 * np.pi, 720, endpoint=False)
    rim = np.stack([RIM * np.cos(a), RIM * np.sin(a), 0 * a], axis=1)
    rim = rim[~((rim[:, 0] > 0) & (np.abs(rim[:, 1]) < TUBE + 0.02))]
    step = s.step_len
    d = np.linalg.norm(rim[:, None] - X[None], axis=2).min(axis=1)
    assert d.max() < step
    junctions = np.array([[np.sqrt(RIM ** 2 - TUBE ** 2), y, 0.0] for y in (TUBE, -TUBE)])
    for j in junctions:
        near = np.linalg.norm(X - j, axis=1) < 2 * step
        assert near.any() and X[near, 2].max() > 0 and X[near, 2].min() < 0   # both faces' creases reach it
