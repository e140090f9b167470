"""The tone marks against the exact surface (bench/inkmeasure.py, as bench/quality.py
measures them): the ink follows the light, stipples are blue noise that never touch,
hatching follows its field and does not fan out, no mark lies outside the visible model
or crosses a visible outline; the tone curve and its bad settings; determinism whatever
the stepping."""
import math
import os
import re
import sys

import numpy as np
import pytest

from blobtree_ink import model as M
from blobtree_ink import pipeline as PL
from blobtree_ink.blackboard.view import View
from blobtree_ink.strokes import style as ST
from blobtree_ink.strokes import tone as TN

sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))),
                                "bench"))
import inkmeasure as IM  # noqa: E402
import inkview as IV  # noqa: E402
import quality as Q  # noqa: E402

SMALL = {
    "lit sphere": {"type": "point", "center": [0, 0, 0], "radius": 1.0},
    "cylinder with a cavity": {"type": "difference", "children": [
        {"type": "segment", "a": [0, 0, -0.6], "b": [0, 0, 0.6], "radius": 1.2},
        {"type": "segment", "a": [0, 0, 0.15], "b": [0, 0, 1.5], "radius": 0.8}]},
    "rounded box": {"type": "box", "center": [0, 0, 0], "half_size": [0.5, 0.35, 0.3], "radius": 0.6},
    "torus": {"type": "circle", "center": [0, 0, 0], "normal": [0, 0, 1], "circle_radius": 1.0, "radius": 0.8},
}
RES = 128


def small(name):
    return M.from_dict({"format": "blobtree-1", "name": name.replace(" ", "_"), "root": SMALL[name]})


_seen = {}


def scene(name, model=None):
    """A small model (or ``model``) seen as bench/quality.py sees one: the evaluator, eye,
    light, its visible outlines, the camera cut about them and the lit picture."""
    if name not in _seen:
        ev = M.Evaluator(small(name) if model is None else model)
        centre, radius = PL.bounds(ev)
        eye = PL.three_quarter_eye(centre, radius)
        light = PL.default_light(centre, eye)
        job = PL.Job(ev, view=View(eye=eye), light=tuple(light))
        res = PL.Illustration(job).run()
        lines = [s for k in IM.OUTLINE_LAYERS for s in res.strokes.layers.get(k, ())]
        cam = IV.Camera.framing(eye, centre, np.concatenate([s.points for s in lines]), 1024)
        lit, _ = IV.cast_light(ev, cam, light, RES)
        _seen[name] = ev, eye, light, lines, cam, lit
    return _seen[name]


def figures(name, look, model=None):
    """bench/quality.py's figures of a look of a small model (or ``model``: the strokes
    beside its outlines)."""
    ev, eye, light, lines, cam, lit = scene(name, model)
    st = ST.style(look)
    layers, hatch, _ = Q.drawing(ev, eye, light, st, lines, 0)
    out, _ = Q.measure(ev, cam, lit, eye, st, layers, hatch, RES, lines)
    out["marks"] = out.pop("strokes")
    return out


@pytest.mark.parametrize("name", list(SMALL))
def test_stipples_follow_the_light_as_blue_noise_that_never_touches(name):
    f = figures(name, "stippled")
    assert f["marks"] > 1000, f
    assert f["tone_r"] >= 0.95, f
    assert f["nn_cv"] <= 0.13, f
    assert f["touching"] == 0.0, f
    assert f["evenness"] <= 0.22, f
    assert f["outside"] == 0 and f["crossing"] == 0, f
    assert 0.8 * f["mean_tone"] <= f["mean_ink"] <= 1.2 * f["mean_tone"], f        # the ink covers the tone's range


@pytest.mark.parametrize("look", ["hatched", "flocked"])
@pytest.mark.parametrize("name", list(SMALL))
def test_hatching_follows_the_light_and_its_field_without_fans(name, look):
    f = figures(name, look)
    assert f["marks"] > 100, f
    assert f["tone_r"] >= 0.97, f
    if not math.isnan(f["along"]):                      # (a sphere has no principal directions)
        assert f["along"] >= 0.95, f
    assert f["ends"] <= 10, f
    assert f["evenness"] <= 0.22, f                 # (the ink measured on the paper and evened out: strokes.density)
    assert f["outside"] == 0 and f["crossing"] == 0, f
    over = 1.1 if look == "hatched" else 1.15     # (flocks' lines overlap a little where flocks meet)
    assert 0.9 * f["mean_tone"] <= f["mean_ink"] <= over * f["mean_tone"], f


@pytest.mark.parametrize("name", list(SMALL))
def test_silhouette_shading_reaches_as_far_into_the_shade_as_the_light_asks(name):
    """Strokes from the feature lines run on into the shade until the tone no longer
    wants ink: a round part's shade is filled, not only a fringe along its silhouette."""
    f = figures(name, "silhouette-shading")
    assert f["tone_r"] >= 0.95, f
    assert f["evenness"] <= 0.3, f
    assert 0.8 * f["mean_tone"] <= f["mean_ink"] <= 1.2 * f["mean_tone"], f
    assert f["outside"] == 0 and f["crossing"] == 0, f


def test_small_patches_of_shade_get_short_marks(load_example):
    """The heart's veins: their flanks are small patches of shade that a hatching line
    crosses in a step or two. Each gets a short mark (a piece bounded by its tone) that
    runs on to where the tone ends, so the light band across the veins is inked as its
    tone asks (without the marks: tone_r 0.957, evenness 0.37; marks that stop at their
    last point inside the tone: 0.968, 0.296)."""
    f = figures("heart", "hatched", load_example("heart"))
    assert f["tone_r"] >= 0.971, f
    assert f["evenness"] <= 0.275, f
    assert 0.85 * f["mean_tone"] <= f["mean_ink"], f
    assert f["ends"] <= 10, f


def test_a_map_line_is_drawn_in_pieces_from_two_points_between_its_tone_and_the_outlines():
    """A run of a map's line is split where a step crosses a visible outline; every piece
    of at least TICK points is a mark (a small patch of shade, a strip of a face between
    two windows), a lone point is not; pieces never run from one line into the next."""
    from blobtree_ink.strokes import hatching as HT
    drawn = np.array([0, 1, 1, 0, 0, 1, 1, 1, 1, 1, 1, 0, 1, 0], bool)     # one line of 14 points
    cut = np.zeros(14, bool)
    cut[8] = True                                                    # the step 7 -> 8 crosses an outline
    assert HT._runs(drawn, cut, np.array([0]), np.array([14])) == [(1, 3), (5, 8), (8, 11)]
    cut[6] = True                                                    # and the step 5 -> 6: a lone point left
    assert HT._runs(drawn, cut, np.array([0]), np.array([14])) == [(1, 3), (6, 8), (8, 11)]
    two = np.array([0, 0, 1, 1, 1, 1, 1, 1, 1], bool)                # two lines of 4 and 5 points, drawn from
    cut = np.zeros(9, bool)                                          # the first's third point on
    cut[6] = True                                                    # the second line's step 5 -> 6
    assert HT._runs(two, cut, np.array([0, 4]), np.array([4, 5])) == [(2, 4), (4, 6), (6, 9)]


def test_a_mark_shorter_on_the_paper_than_slim_times_its_width_is_a_blot():
    """A short mark seen end on (or mostly hidden) would read as a blot: it is drawn only
    SLIM times as long as it is wide on the paper."""
    from blobtree_ink.strokes import hatching as HT
    w = np.full(2, 1.0)
    assert not HT.slim(np.array([[0.0, 0.0], [0.75 * HT.SLIM, 0.0]]), w)
    assert HT.slim(np.array([[0.0, 0.0], [1.25 * HT.SLIM, 0.0]]), w)
    assert not HT.slim(np.array([[0.0, 0.0], [1.25 * HT.SLIM, 0.0]]), np.array([1.0, 2.0]))   # its widest


def test_silhouette_shading_strokes_run_from_the_silhouette_towards_where_the_sphere_faces_the_eye():
    """On a lit sphere a stroke from the silhouette turns on past 60 degrees (the
    smarticles' usual limit: strokes stopped there would leave a ring of gaps)."""
    ev, eye, light, lines, cam, lit = scene("lit sphere")
    layers, _, _ = Q.drawing(ev, eye, light, ST.style("silhouette-shading"), lines, 0)
    turned = []
    for s in layers["Chains"]:
        a, b = s.points[0], s.points[-1]
        turned.append(np.degrees(np.arccos(np.clip(a @ b / (np.linalg.norm(a) * np.linalg.norm(b)), -1, 1))))
    assert max(turned) > 70.0, max(turned)


def test_a_cavity_in_shade_gets_its_ink():
    """The inside of the cup, in shade, is inked (a subtracted part's hollow has marks),
    also by strokes from the feature chains (from the rim's crease down its inner wall)."""
    ev, eye, light, lines, cam, lit = scene("cylinder with a cavity")
    for look in ("stippled", "hatched", "silhouette-shading"):
        job = PL.Job(ev, view=View(eye=eye), light=tuple(light), style=ST.style(look),
                     requests=(PL.Request("PLACE_STROKES"),), lines=tuple(lines))
        marks = [s for v in PL.Illustration(job).run().strokes.layers.values() for s in v]
        P = np.concatenate([s.points for s in marks])
        inside = (np.hypot(P[:, 0], P[:, 1]) < 0.8 * 0.65) & (P[:, 2] > 0.2)      # on the hollow's wall or floor
        assert inside.sum() > 20, look


def test_chain_strokes_go_down_a_hollow_from_its_rim(load_example):
    """csg_difference, a ball bitten by a smaller one towards the eye: the hollow is the
    darkest part, and the strokes from the feature chains reach it from the rim (a
    crease whose far sheet, the hollow's wall, falls away below the outer ball's
    tangent plane), so silhouette shading follows the light there too."""
    f = figures("csg_difference", "silhouette-shading", load_example("csg_difference"))
    assert f["tone_r"] >= 0.95, f
    assert f["outside"] == 0 and f["crossing"] == 0, f


def test_the_tone_curve():
    lit = np.array([0.0, 0.05, 0.3, 0.6, 0.7, 1.0])
    t = TN.tone(lit, 0.05, 0.65, 1.0)
    assert t[0] == t[1] == TN.DARKEST and t[-1] == t[-2] == 0.0
    assert np.all(np.diff(t) <= 0) and 0 < t[2] < TN.DARKEST
    flat = TN.tone(lit, 0.05, 0.65, 0.0)                  # contrast 0: one flat tone below the highlight
    assert np.allclose(flat[:4], TN.FLAT * TN.DARKEST) and flat[-1] == 0.0
    # two layers drawn over each other cover the tone
    t = np.linspace(0, TN.DARKEST, 50)
    first, rest = TN.coverage(t, "first"), TN.coverage(t, "rest")
    assert np.allclose(1 - (1 - first) * (1 - rest), t)


@pytest.mark.parametrize("change, message", [
    (dict(contrast=1.5), "contrast must be a number from 0 to 1"),
    (dict(contrast=float("nan")), "contrast must be a number from 0 to 1"),
    (dict(shade_upper=1.2), "shade_upper must be a number from 0 to 1"),
    (dict(shade_lower=0.5, shade_upper=0.5), r"shade_lower \(0.5\) must be below shade_upper \(0.5\)"),
])
def test_a_tone_curve_out_of_range_is_named(change, message):
    with pytest.raises(ValueError, match=message):
        ST.style("hatched", **change)


def test_a_light_inside_the_model_is_named():
    ev = M.Evaluator(small("lit sphere"))
    job = PL.Job(ev, light_at=(0.1, 0.0, 0.0), style=ST.style("stippled"),
                 requests=(PL.Request("OUTLINES"), PL.Request("PLACE_STROKES")))
    with pytest.raises(PL.JobError, match="the light .* is inside the model"):
        PL.Illustration(job).run()


def test_an_eye_inside_the_model_is_named():
    """A frame of a camera passing through the model draws nothing, and says why."""
    ev = M.Evaluator(small("lit sphere"))
    job = PL.Job(ev, View(eye=np.array([0.1, 0.0, 0.0])), style=ST.style("stippled"),
                 requests=(PL.Request("OUTLINES"), PL.Request("PLACE_STROKES")))
    res = PL.Illustration(job).run()
    assert not any(res.strokes.layers.values())
    assert any(re.match(r"the eye at \(0.1, 0, 0\) is inside the model", w) for w in res.warnings), res.warnings


def test_cast_shadows_darken_what_the_model_hides_from_the_sun():
    """A small ball on a big one, the sun straight above: the big ball's top, under the
    small one, is in its shadow; beside it, lit."""
    ev = M.Evaluator(M.from_dict({"format": "blobtree-1", "root": {"type": "union", "children": [
        {"type": "point", "center": [0, 0, 0], "radius": 1.0},
        {"type": "point", "center": [0, 0, 1.4], "radius": 0.5}]}}))
    top = np.array([[0.0, 0.0, 0.64], [0.5, 0.0, 0.42]])
    from blobtree_ink.model.projection import project
    P, _, g = project(ev, top, 8)
    N = -g / np.linalg.norm(g, axis=1, keepdims=True)
    lit = TN.light(ev, P, N, (0.0, 0.0, 1.0), 4 * ev.scale)
    assert lit[0] == 0.0 and lit[1] > 0.3


def test_a_look_is_the_same_however_it_is_stepped():
    """The same job stepped to its end, or stepped with its result read between steps (as
    the modal operator's worker publishes it), gives the same strokes, bit for bit."""
    ev, eye, light, lines, cam, lit = scene("torus")
    st = ST.style("stippled", hatching=True)

    def job():
        return PL.Job(M.Evaluator(small("torus")), view=View(eye=eye), light=tuple(light), style=st,
                      requests=(PL.Request("OUTLINES"), PL.Request("PLACE_STROKES")))
    a = PL.Illustration(job()).run()
    ill = PL.Illustration(job())
    while ill.step():
        ill.result()
        ill.progress()
    b = ill.result()
    from helpers import same_strokes
    same_strokes(a.strokes, b.strokes)
    assert a.strokes.count("Stipples") > 100 and a.strokes.count("Hatching") > 20
