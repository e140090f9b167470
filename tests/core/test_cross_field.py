"""The smoothed cross field's first line (strokes.cross_field): the line the first hatching
layer follows runs on continuously where the principal curvatures trade places, and a
round part is hatched round."""
import numpy as np

from blobtree_ink import model as M
from blobtree_ink import pipeline as PL
from blobtree_ink.blackboard.cells import pairs_within
from blobtree_ink.blackboard.view import View
from blobtree_ink.model.curvature import curvature
from blobtree_ink.pipeline import layers as LY
from blobtree_ink.strokes import cross_field as CF
from blobtree_ink.strokes import style as ST


def field_of(model):
    """The pipeline's cross field of a model (as a hatched look makes it) and its evaluator."""
    ev = M.Evaluator(model)
    centre, radius = PL.bounds(ev)
    ill = PL.Illustration(PL.Job(ev, view=View(eye=PL.three_quarter_eye(centre, radius)), style=ST.style("hatched"),
                                 requests=(PL.Request(PL.PLACE_STROKES),)))
    ill.step()
    return LY.cross_field(ill.canvas, 0), ill.canvas.ev


def turned_pairs(cf, D, reliable=0.5):
    """The share of neighbouring nodes (both reliable, on one sheet) whose lines D are more
    than 60 degrees apart."""
    i, j = pairs_within(cf.points, cf.points, 0.7 * cf.radius)
    keep = (i < j) & (np.einsum("ij,ij->i", cf.normals[i], cf.normals[j]) > 0.9)
    keep &= (cf.weight[i] > reliable) & (cf.weight[j] > reliable)
    i, j = i[keep], j[keep]
    assert len(i) > 1000
    return float(np.mean(np.abs(np.einsum("ij,ij->i", D[i], D[j])) < 0.5))


def test_the_first_line_runs_on_round_a_shoulder(load_example):
    """The jug's principal directions trade places round the shoulder of its belly (the
    larger curvature runs round it above, down it below): dir1 turns through a right
    angle between neighbours there; the first line does not."""
    cf, ev = field_of(load_example("jug"))
    dir1 = np.nan_to_num(curvature(ev, cf.points)["dir1"])
    assert turned_pairs(cf, dir1) > 0.005
    assert turned_pairs(cf, cf.first) < 0.002
    # the first line is one of the cross's two lines, in the tangent plane
    assert np.allclose(np.abs(np.einsum("ij,ij->i", cf.first, cf.normals)), 0.0, atol=1e-6)
    other = np.cross(cf.normals, cf.dirs)
    along = np.maximum(np.abs(np.einsum("ij,ij->i", cf.first, cf.dirs)), np.abs(np.einsum("ij,ij->i", cf.first, other)))
    assert np.allclose(along, 1.0, atol=1e-6)


def test_a_round_part_is_hatched_round():
    """A sphere has no principal directions: its first line is the level line of the
    world's up (away from the poles), and first_at carries it to any point."""
    cf, _ = field_of(M.from_dict({"format": "blobtree-1", "name": "ball",
                                  "root": {"type": "point", "center": [0, 0, 0], "radius": 1.0}}))
    N = cf.normals
    away = np.abs(N[:, 2]) < 0.8
    level = np.cross(N, [0.0, 0.0, 1.0])
    level /= np.linalg.norm(level, axis=1)[:, None]
    assert away.sum() > 100
    assert np.all(np.abs(np.einsum("ij,ij->i", cf.first, level))[away] > 0.95)
    P = cf.points[away][:50] * 1.0001
    got = cf.first_at(P, N[away][:50], np.zeros((50, 3)))
    assert np.all(np.abs(np.einsum("ij,ij->i", got, level[away][:50])) > 0.95)


def test_a_patch_whose_first_line_runs_across_all_about_it_goes_over():
    """On a plane of reliable nodes whose crosses all run along x and y, a square patch
    labelled y inside a field labelled x takes x (its seam gone); where the principal
    directions mean little the level line wins over a minority of neighbours."""
    g1 = np.arange(20.0)
    X, Y = np.meshgrid(g1, g1, indexing="ij")
    P = np.c_[X.ravel(), Y.ravel(), np.zeros(X.size)]
    n = len(P)
    dirs, other = np.tile([1.0, 0.0, 0.0], (n, 1)), np.tile([0.0, 1.0, 0.0], (n, 1))
    i, j = pairs_within(P, P, 1.5)
    keep = i != j
    i, j = i[keep], j[keep]
    g = np.ones(len(i))
    patch = (np.abs(X.ravel() - 9.5) < 2) & (np.abs(Y.ravel() - 9.5) < 2)
    first = np.where(patch[:, None], other, dirs)
    out = CF._seams_shortened(first, dirs, other, dirs, np.ones(n), i, j, g)
    assert np.allclose(out, dirs)
    # nodes with no principal directions lean to the level line (here y) and keep it
    out = CF._seams_shortened(first, dirs, other, other, np.zeros(n), i, j, g)
    assert np.allclose(out, other)


def test_the_hearts_first_lines_have_short_seams(load_example):
    """The heart (veined lobes, a valley between them): few neighbouring reliable nodes'
    first lines turn through a right angle (seams where labelling fronts met, shortened)."""
    cf, _ = field_of(load_example("heart"))
    assert turned_pairs(cf, cf.first, reliable=0.0) < 0.025
