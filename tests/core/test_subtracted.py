"""Where CSG creases are: the centres of subtracted primitives in the world frame
(model.csg), the walls of the cut-away parts found from them, and a dimple smaller
than a grid cell whose crease a session traces because explorers start on its wall."""
import math

import numpy as np

from blobtree_ink import model as M
from blobtree_ink.agents import Session, Settings, detail
from blobtree_ink.blackboard.view import View
from blobtree_ink.model.csg import subtracted_centres

from test_massris import K, model_of


def test_subtracted_centres_follow_transforms_and_skip_warps():
    root = {"type": "union", "children": [
        {"type": "transform", "translate": [1.0, 2.0, 3.0], "rotate": [0.0, 0.0, math.pi / 2], "scale": [2.0, 2.0, 2.0],
         "child": {"type": "difference", "children": [
             {"type": "point", "center": [0, 0, 0], "radius": 1.0},
             {"type": "point", "center": [0.5, 0, 0], "radius": 0.2},
             {"type": "segment", "a": [0, 0.2, 0], "b": [0, 0.4, 0], "radius": 0.1}]}},
        {"type": "twist", "rate": 0.5, "child": {"type": "difference", "children": [
            {"type": "point", "center": [5, 0, 0], "radius": 1.0},
            {"type": "point", "center": [5.5, 0, 0], "radius": 0.2}]}},
        {"type": "point", "center": [9, 0, 0], "radius": 0.5}]}
    C = subtracted_centres(model_of(root).root)
    # scale 2, then +90 degrees about z, then the translation: (0.5,0,0) -> (0,1,0) + t
    expected = np.array([[1.0, 3.0, 3.0], [1.0 - 0.6, 2.0, 3.0]])
    assert len(C) == 2
    np.testing.assert_allclose(np.sort(C, axis=0), np.sort(expected, axis=0), atol=1e-12)


DIMPLE = np.array([0.0, -1.6 * K, 0.0])     # a small ball centred on a big ball's surface


def dimple_model():
    return model_of({"type": "difference", "children": [
        {"type": "point", "center": [0.0, 0.0, 0.0], "radius": 1.6},
        {"type": "point", "center": DIMPLE.tolist(), "radius": 0.25}]})


def test_walls_of_a_subtracted_part_are_on_the_surface_around_it():
    s = Session(dimple_model(), View(eye=(0.0, -6.0, 2.0)), Settings(resolution=8))
    W, C = detail.subtracted_walls(s.surface, s.h, s.ev.model.root)
    assert len(W) >= 1
    np.testing.assert_allclose(C, np.tile(DIMPLE, (len(W), 1)), atol=1e-12)     # each wall's part
    np.testing.assert_allclose(s.ev.field(W), s.ev.iso, atol=1e-9)
    assert np.all(np.linalg.norm(W - DIMPLE, axis=1) < 2 * s.h)


def test_a_dimple_smaller_than_a_cell_gets_its_crease_traced():
    """The dimple's crease circle (where the small ball's surface cuts the big one) is
    smaller than a cell of the 8^3 grid; explorers starting on its wall find it."""
    view = View(eye=(0.0, -6.0, 2.0))
    rho = 0.25 * K
    plain = Session(dimple_model(), view, Settings(resolution=8, explore_detail=False))
    plain.request("OUTLINES")
    plain.run()
    assert not any(o.kind == "crease" and np.linalg.norm(o.points - DIMPLE, axis=1).max() < 2 * rho
                   for o in plain.outlines())
    s = Session(dimple_model(), view, Settings(resolution=8))
    s.request("OUTLINES")
    s.run()
    assert s.done
    ring = [o for o in s.outlines() if o.kind == "crease" and np.linalg.norm(o.points - DIMPLE, axis=1).max() < 2 * rho]
    assert ring
    P = np.concatenate([o.points for o in ring])
    np.testing.assert_allclose(s.ev.field(P), s.ev.iso, atol=1e-9)
    # on both spheres: |p| = the big radius and |p - c| = the dimple's radius
    np.testing.assert_allclose(np.linalg.norm(P, axis=1), 1.6 * K, atol=1e-6)
    np.testing.assert_allclose(np.linalg.norm(P - DIMPLE, axis=1), rho, atol=1e-6)
    # all round the circle: the crease circle's plane is y = const; angles around its axis
    ang = np.arctan2(P[:, 2], P[:, 0])
    hist, _ = np.histogram(ang, bins=6, range=(-np.pi, np.pi))
    assert np.all(hist > 0)


def test_wall_probes_are_bounded_for_models_with_very_many_subtracted_parts(monkeypatch):
    """A hostile model may subtract up to the format's node limit: only a spread subset
    of MAX_WALL_PROBES centres is probed (here the limit is lowered to 3 of 12)."""
    holes = [{"type": "point", "center": [1.6 * K * math.cos(a), -0.0, 1.6 * K * math.sin(a)], "radius": 0.25}
             for a in np.linspace(0, 2 * math.pi, 12, endpoint=False)]
    model = model_of({"type": "difference", "children": [
        {"type": "point", "center": [0.0, 0.0, 0.0], "radius": 1.6}] + holes})
    s = Session(model, View(eye=(0.0, -6.0, 2.0)), Settings(resolution=8))
    full, _ = detail.subtracted_walls(s.surface, s.h, s.ev.model.root)
    monkeypatch.setattr(detail, "MAX_WALL_PROBES", 3)
    few, _ = detail.subtracted_walls(s.surface, s.h, s.ev.model.root)
    assert 0 < len(few) <= 3 * 6 < len(full)
