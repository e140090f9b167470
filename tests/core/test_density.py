"""Hatching as dark on the paper as its tone asks (strokes.density): a first drawing of
a map's lines measured on a grid of the paper against the tone the eye sees there, and
the gain that evens it out."""
import numpy as np

from blobtree_ink import model as M
from blobtree_ink import pipeline as PL
from blobtree_ink.model.owners import owners
from blobtree_ink.pipeline import framing as FR
from blobtree_ink.pipeline import layers as LY
from blobtree_ink.strokes import style as ST
from blobtree_ink.strokes import density as DN
from blobtree_ink.strokes import hatch_map as HM
from blobtree_ink.strokes.data import Stroke
from blobtree_ink.strokes.paper import Paper

import test_tone_marks as TM


def test_a_gain_is_bilinear_between_cell_centres_and_one_off_its_grid():
    g = DN.Gain(np.array([10.0, 20.0]), 0.5, np.array([[1.0, 2.0], [3.0, 4.0]]))     # rows along y
    at = g.at(np.array([[10.0, 20.0], [10.5, 20.0], [10.0, 20.5], [10.25, 20.25], [10.5, 20.5],
                        [9.9, 20.0], [10.0, 21.0]]))
    assert np.allclose(at, [1.0, 2.0, 3.0, 2.5, 4.0, 1.0, 1.0])


def test_ink_counts_each_segment_as_long_and_as_wide_as_it_is_on_the_paper():
    """A line 2 long and 0.02 wide, ten units from the eye as the paper's centre is
    (scale 1), covers 0.04 of the paper; seen from twice as far, a quarter of that."""
    x = np.linspace(-1.0, 1.0, 21)
    line = Stroke(np.c_[x, np.zeros(21), np.zeros(21)], np.full(21, 0.01), np.ones(21))
    near = Paper((0.0, -10.0, 0.0), (0.0, 0.0, 0.0))
    grid = DN.ink(near, [line], np.array([-2.0, -2.0]), 0.1, (41, 41))
    assert np.isclose(grid.sum() * 0.1 ** 2, 0.04)
    assert np.count_nonzero(grid.sum(axis=1)) == 1              # one row of cells, along the line
    far = Paper((0.0, -20.0, 0.0), (0.0, -10.0, 0.0))           # the line 20 from the eye, the paper at 10
    assert np.isclose(DN.ink(far, [line], np.array([-2.0, -2.0]), 0.1, (41, 41)).sum() * 0.1 ** 2, 0.01)
    assert DN.ink(near, [line], np.array([5.0, 5.0]), 0.1, (4, 4)).sum() == 0.0      # off the grid


def without(hmap, towards, radius):
    """A sphere's hatching map without the lines that come within ``radius`` (of the
    sphere's radius) of its point ``towards`` a direction."""
    r = float(np.median(np.linalg.norm(hmap.points, axis=1)))
    centre, radius = r * np.asarray(towards) / np.linalg.norm(towards), r * radius
    sizes = hmap.sizes()
    line = np.repeat(np.arange(len(sizes)), sizes)
    near = np.zeros(len(sizes), bool)
    near[line[np.linalg.norm(hmap.points - centre, axis=1) < radius]] = True
    keep = np.flatnonzero(~near)
    rows = np.concatenate([np.arange(hmap.start[k], hmap.start[k] + sizes[k]) for k in keep])
    kept = sizes[keep]
    return HM.HatchMap(hmap.points[rows], hmap.normals[rows], np.repeat(np.arange(len(keep)), kept),
                       hmap.level[keep], hmap.key[keep], np.cumsum(kept) - kept, hmap.spacing, hmap.levels)


def test_a_patch_of_the_map_left_without_lines_is_inked_by_the_lines_about_it(monkeypatch):
    """A lit sphere whose hatching map has lost its lines over a patch in its shade (as
    where a wrinkled surface cuts its lines short): the lines about the patch widen and
    bring their next level in, so the drawing keeps the tone's evenness; without the
    gain the patch is a pale hole."""
    monkeypatch.setattr(TM, "_seen", {})           # (a scene of its own: the holed map stays with its evaluator)
    ev, eye, light, lines, cam, lit = TM.scene("lit sphere")
    shade = -np.asarray(light, float) + 0.6 * (np.asarray(eye, float) / np.linalg.norm(eye))
    build = HM.build                                            # (towards a point in shade, facing the eye)
    monkeypatch.setattr(HM, "build", lambda *a, **k: without(build(*a, **k), shade, 0.4))
    holed = TM.figures("lit sphere", "hatched", TM.small("lit sphere"))
    monkeypatch.setattr(DN, "GAIN", 1.0)
    pale = TM.figures("lit sphere", "hatched", TM.small("lit sphere"))
    assert holed["evenness"] <= 0.19 and pale["evenness"] >= 0.205, (holed, pale)
    assert holed["tone_r"] > pale["tone_r"] + 0.005, (holed, pale)


def capsule_layer(surface="all", eye=None):
    """A real hatching layer (pipeline.layers) of a capsule lying along x, seen from -y,
    lit from the right of the eye, and its hatching map."""
    model = M.from_dict({"format": "blobtree-1", "name": "capsule", "root": {
        "type": "segment", "a": [-1.5, 0, 0], "b": [1.5, 0, 0], "radius": 1.0}})
    ev = M.Evaluator(model)
    centre, radius = PL.bounds(ev)
    eye = np.asarray(centre) + np.array([0.0, -4.0 * radius, 0.0]) if eye is None else np.asarray(eye, float)
    light = np.array([1.0, -1.0, 0.0]) / np.sqrt(2.0)                # from the right of the eye
    cv = LY.Canvas(ev, eye, light, FR.line_radius(ev), FR.stroke_unit(ev))
    st = ST.style("hatched", surface=surface) if surface != "all" else ST.style("hatched")
    layer = LY._layer(cv, st, None, 0, LY._share(st, False), (None, None), st.hatch_steps, None, ())
    return layer, LY.hatch_map(cv, st, 0, False, LY.marks_of(cv, "hatching", owners(ev), 0)), ev


def test_the_tone_asked_is_of_the_surface_the_eye_sees_in_each_cell():
    """The capsule's asked coverage covers a patch of the paper as long and as high as
    its map's lines (x along the grid's columns, y along its rows), darker on its side
    turned from the light; nothing off the model."""
    layer, hmap, ev = capsule_layer()
    q = layer.paper.place(hmap.points)[0][:, :2]
    cell = 0.05 * (q[:, 0].max() - q[:, 0].min())
    origin = q.min(axis=0) - 5 * cell
    shape = (int((q[:, 1].max() - origin[1]) / cell) + 6, int((q[:, 0].max() - origin[0]) / cell) + 6)
    want = DN.asked(layer, origin, cell, shape)
    rows, cols = np.nonzero(want > 0)
    wide, high = (cols.max() - cols.min() + 1) * cell, (rows.max() - rows.min() + 1) * cell
    assert abs(wide - (q[:, 0].max() - q[:, 0].min())) < 3 * cell
    assert abs(high - (q[:, 1].max() - q[:, 1].min())) < 3 * cell
    assert wide > 1.8 * high                                   # (the capsule is 5 long and 2 high)
    left, right = want[:, : shape[1] // 2].sum(), want[:, shape[1] // 2:].sum()
    assert left > 1.25 * right                                 # the end turned from the light the darker
    assert want[0].max() == 0 and want[:, 0].max() == 0


def test_lines_that_give_no_ink_get_the_largest_gain_where_the_tone_asks_for_ink():
    layer, hmap, ev = capsule_layer()
    g = DN.measure(layer, hmap, [])
    want = DN._blur(DN.asked(layer, g.origin, g.cell, g.grid.shape), DN.SMOOTH)
    assert np.array_equal(g.grid == DN.GAIN, want > DN.FAINT)
    assert (g.grid[want <= DN.FAINT] == 1.0).all() and (want > DN.FAINT).any()


def test_a_style_hatching_only_convex_parts_asks_nothing_of_the_others():
    """The capsule's surface is all convex: hatching its concave parts asks nothing."""
    layer, hmap, ev = capsule_layer()
    g = DN.measure(layer, hmap, [], within=lambda P: np.zeros(len(P), bool))
    assert (g.grid == 1.0).all()


def test_a_model_seen_from_very_near_gets_a_bounded_grid(monkeypatch):
    """The eye just off the capsule's end, most of the model beside and behind it: the
    grid spans the map's points in front of the eye that face it; where that would take
    more than MOST_CELLS cells it takes fewer, wider ones; the gain is finite."""
    layer, hmap, ev = capsule_layer(eye=(-2.05, -0.05, 0.02))         # (its end at x = -1.95)
    g = DN.measure(layer, hmap, [])
    assert g.cell == DN.CELL * hmap.spacing and g.grid.size > 20_000 and np.isfinite(g.grid).all()
    monkeypatch.setattr(DN, "MOST_CELLS", 5000)
    g = DN.measure(layer, hmap, [])
    assert g.cell > DN.CELL * hmap.spacing and g.grid.size <= 5000 and np.isfinite(g.grid).all()
