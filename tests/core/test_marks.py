"""Marks: points of the model's own where strokes start (model.marks), their owners
(model.owners), keyed random numbers (model.keyed) and the warps' forward maps."""
import math

import numpy as np
import pytest

from blobtree_ink import model as M
from blobtree_ink.agents import Session, Settings
from blobtree_ink.blackboard.view import View
from blobtree_ink.model import keyed, nodes as N
from blobtree_ink.model import warps as W
from blobtree_ink.model.marks import surface_marks
from blobtree_ink.model.owners import NONE, Owners

K = math.sqrt(1 - 0.5 ** (1 / 3))      # sphere radius of an R=1 primitive at iso 0.5


def model_of(root):
    return M.from_dict({"format": "blobtree-1", "root": root})


def point(x=0.0, y=0.0, z=0.0, r=1.0):
    return {"type": "point", "center": [x, y, z], "radius": r}


def rough_vertices(ev, res=24):
    s = Session(ev, View(eye=np.array([5.0, -6.0, 4.0])), Settings(resolution=res, seed=1))
    return s.snapshot(stitch=False).vertices


def nearest(P, Q):
    return np.sqrt(((P[:, None, :] - Q[None, :, :]) ** 2).sum(-1)).min(axis=1)


def test_the_warps_forward_maps_invert_their_maps():
    rng = np.random.default_rng(0)
    Q = rng.uniform(-0.5, 0.5, size=(3, 500))       # where a bend of these rates is one to one
    for rate in (-0.7, 0.3, 1.2):
        for forward, back in ((W.twist_forward, W.twist_map), (W.bend_forward, W.bend_map)):
            P = forward(Q, rate)
            assert np.abs(back(P, rate, False)[0] - Q).max() < 1e-12
    P = W.taper_forward(Q, 0.8)
    assert np.abs(W.taper_map(P, 0.8, False)[0] - Q).max() < 1e-12


def test_owners_are_the_primitives_that_make_the_surface_there():
    # two blended spheres, and a bite out of the first by a third (a difference)
    model = model_of({"type": "difference", "children": [
        {"type": "blend", "children": [point(0), point(1.6)]}, point(-0.5, 0, 0.3, 0.8)]})
    ow = Owners(model)
    assert [p.node.center for p in ow.placed] == [(0, 0, 0), (1.6, 0, 0), (-0.5, 0, 0.3)]
    P = np.array([[0.1, 0.0, -0.4],         # the first sphere's underside
                  [1.9, 0.0, 0.0],          # the second's far side
                  [-0.25, 0.0, 0.15],       # in the bite: the subtracted sphere makes the surface
                  [9.0, 9.0, 9.0]])         # nothing reaches
    assert ow.of(P).tolist() == [0, 1, 2, NONE]
    union = Owners(model_of({"type": "intersection", "children": [point(0), point(0.5, r=1.2)]}))
    assert union.of(np.array([[0.9, 0, 0], [-0.4, 0, 0]])).tolist() == [0, 1]     # the smaller field


def test_marks_lie_on_the_surface_with_outward_normals_and_cover_it_without_holes():
    cases = {
        "point": point(),
        "segment": {"type": "segment", "a": [-1, 0, 0], "b": [1, 0.3, 0], "radius": 0.8},
        "circle": {"type": "circle", "center": [0, 0, 0], "normal": [0.2, 0, 1], "circle_radius": 1.0, "radius": 0.6},
        "disc": {"type": "disc", "center": [0, 0, 0], "normal": [0, 1, 0], "disc_radius": 0.8, "radius": 0.6},
        "box": {"type": "box", "center": [0, 0, 0], "half_size": [0.8, 0.4, 0.3], "radius": 0.5},
        "blend": {"type": "blend", "children": [point(), point(0.9, 0.3, 0, 0.8),
                                                {"type": "segment", "a": [0, 0, 0], "b": [0, 0, 1.2], "radius": 0.5}]},
        "warped": {"type": "bend", "rate": 0.6, "child": {"type": "twist", "rate": 0.8, "child": {
            "type": "taper", "rate": 0.3, "child": {"type": "box", "center": [0, 0, 0.3], "half_size": [0.6, 0.3, 0.9],
                                                    "radius": 0.4}}}},
        "rotated box": {"type": "transform", "rotate": [0.3, 0.5, 0.2], "scale": [1.0, 1.5, 0.8],
                        "child": {"type": "box", "center": [0, 0, 0], "half_size": [0.5, 0.4, 0.3], "radius": 0.5}},
    }
    for name, root in cases.items():
        ev = M.Evaluator(model_of(root))
        s = 0.08
        marks = surface_marks(ev, s)
        assert len(marks) > 50, name
        f, g = ev.field_grad(marks.points)
        assert np.abs(f - 0.5).max() < 1e-6, name
        assert np.abs(np.einsum("ij,ij->i", marks.normals, -g / np.linalg.norm(g, axis=1)[:, None]) - 1).max() < 1e-9
        assert np.abs(np.einsum("ij,ij->i", marks.ref, marks.normals)).max() < 1e-9, name     # tangent
        V = rough_vertices(ev)
        gap = nearest(V, marks.points)
        assert np.quantile(gap, 0.99) < 2.0 * s, (name, np.quantile(gap, 0.99) / s)      # no holes
        d = np.sort(np.sqrt(((marks.points[:, None] - marks.points[None]) ** 2).sum(-1)), axis=1)[:, 1]
        assert np.median(d) > 0.4 * s, name                          # well spread: no clumps
        assert len(np.unique(marks.keys)) == len(marks), name


def test_a_sphere_has_its_area_over_the_spacing_squared_marks():
    ev = M.Evaluator(model_of(point()))
    for s in (0.05, 0.1):
        n = len(surface_marks(ev, s))
        assert n == round(4 * math.pi * K * K / (s * s))


def test_a_coarser_spacing_keeps_a_prefix_and_a_salt_gives_another_set():
    ev = M.Evaluator(model_of({"type": "blend", "children": [point(), point(1.2, 0, 0.3, 0.9),
                                                            point(0.4, 0.9, 0, 0.7)]}))
    fine = surface_marks(ev, 0.05)
    coarse = fine.thinned(0.1)
    assert 0.2 < len(coarse) / len(fine) < 0.3
    assert set(coarse.keys.tolist()) <= set(fine.keys.tolist())
    other = surface_marks(ev, 0.05, salt=3)
    assert abs(len(other) - len(fine)) < 0.05 * len(fine)
    assert not set(other.keys.tolist()) & set(fine.keys.tolist())
    assert nearest(other.points[:50], fine.points).min() > 1e-6            # other places


def test_marks_move_with_a_rigidly_moved_model(load_example):
    model = load_example("heart")
    rot, move = (0.3, -0.2, 0.9), (1.5, -0.7, 0.2)
    moved = M.Model(N.Transform(model.root, translate=move, rotate=rot), model.name, model.iso)
    a, b = surface_marks(M.Evaluator(model), 0.12), surface_marks(M.Evaluator(moved), 0.12)
    L, t = W.transform_matrix(move, rot, (1, 1, 1))
    where = {k: i for i, k in enumerate(a.keys.tolist())}
    both = [(where[k], j) for j, k in enumerate(b.keys.tolist()) if k in where]
    assert len(both) >= 0.99 * len(a)
    i, j = np.array(both).T
    assert np.abs(a.points[i] @ L.T + t - b.points[j]).max() < 1e-9
    assert np.abs(a.ref[i] @ L.T - b.ref[j]).max() < 1e-8


def test_marks_of_a_part_stay_when_another_part_moves_away_from_it():
    def marks(x):
        return surface_marks(M.Evaluator(model_of({"type": "blend", "children": [
            point(), {"type": "transform", "translate": [x, 0, 0], "child": point(r=0.8)}]})), 0.07)
    a, b = marks(3.0), marks(3.5)               # the second sphere far from the first in both
    first_a, first_b = a.take(a.prim == 0), b.take(b.prim == 0)
    assert first_a.keys.tolist() == first_b.keys.tolist()
    assert np.abs(first_a.points - first_b.points).max() < 1e-12
    second_a, second_b = a.take(a.prim == 1), b.take(b.prim == 1)
    assert second_a.keys.tolist() == second_b.keys.tolist()
    assert np.abs(second_a.points + [0.5, 0, 0] - second_b.points).max() < 1e-12


def test_bad_spacings_are_named():
    ev = M.Evaluator(model_of(point()))
    for bad in (0.0, -1.0, float("nan"), float("inf")):
        with pytest.raises(ValueError, match="spacing must be a positive number"):
            surface_marks(ev, bad)
    with pytest.raises(ValueError, match="spacing is too small"):
        surface_marks(ev, 1e-5)


def test_keyed_numbers_belong_to_their_keys():
    keys = np.arange(20000, dtype=np.uint64)
    u = keyed.uniform(keys, 5)
    assert u.min() >= 0 and u.max() < 1 and abs(u.mean() - 0.5) < 0.01
    assert np.array_equal(keyed.uniform(keys[::-1], 5), u[::-1])            # not a stream: order is no matter
    assert np.corrcoef(u, keyed.uniform(keys, 6))[0, 1] < 0.02              # another salt, other numbers
    z = keyed.normal(keys, 1, count=3)
    assert z.shape == (20000, 3) and abs(z.mean()) < 0.02 and abs(z.std() - 1) < 0.02


def test_a_primitive_takes_model_points_to_its_own_coordinates_and_back():
    model = model_of({"type": "bend", "rate": 0.4, "child": {"type": "transform", "rotate": [0.2, 0.1, 0.3],
                                                             "translate": [0.3, 0, 0], "child": point()}})
    placed = Owners(model).placed[0]
    Q = np.random.default_rng(1).uniform(-0.5, 0.5, size=(50, 3))
    assert np.abs(placed.to_local(placed.to_model(Q)) - Q).max() < 1e-12
