"""Frames that go on from the last one's (agents.continuation, agents.changes,
pipeline.continuation): what changed between two models, what a session keeps and what
it seeds, and that a frame going on from the last equals one from scratch within the
outline tolerance, for less work."""
from dataclasses import replace

import numpy as np

from blobtree_ink import model as M
from blobtree_ink import pipeline as PL
from blobtree_ink.agents import Session, Settings
from blobtree_ink.agents.changes import EVERYWHERE, Boxes, changed
from blobtree_ink.agents.continuation import carried
from blobtree_ink.blackboard.view import View
from blobtree_ink.model import nodes as N
from blobtree_ink.strokes import style as ST
from blobtree_ink.strokes.data import LAYER_OF_KIND
from blobtree_ink.strokes.smarticles import nearest_distance
from helpers import same_marked, same_strokes

EYE = np.array([5.0, -9.0, 4.0])


def turned(eye, radians):
    c, s = np.cos(radians), np.sin(radians)
    return np.array([[c, -s, 0], [s, c, 0], [0, 0, 1.0]]) @ eye


def doc(root, iso=0.5):
    return M.from_dict({"format": "blobtree-1", "iso": iso, "root": root})


def point(x, r=1.0):
    return {"type": "point", "center": [x, 0, 0], "radius": r}


def pair(x, op="union"):
    """Two spheres, the second at x (a union has a crease where they meet)."""
    return doc({"type": op, "children": [point(0.0), {"type": "transform", "translate": [x, 0, 0],
                                                       "child": point(0.0, 0.9)}]})


def session(model, eye, previous=None, res=20):
    ev = model if isinstance(model, M.Evaluator) else M.Evaluator(model)
    s = Session(ev, View(eye=eye), Settings(resolution=res), previous=previous, remember=True)
    s.request("OUTLINES")
    s.run()
    return s


def covered(a, b, tol):
    """The share of b's outline points within tol of a's, and of a's within tol of b's."""
    A = np.concatenate([o.points for o in a])
    B = np.concatenate([o.points for o in b])
    return min(np.mean(nearest_distance(B, A) < tol), np.mean(nearest_distance(A, B) < tol))


def test_every_few_frames_the_detail_phase_looks_everywhere():
    """Going on from the last frame while a part moves, the frames' detail phases look
    only where the field changed, but every REFRESH-th frame's everywhere (with the same
    model the last frames' walks take their place: test_walks), whether the eye moves or
    stays where it was: a small silhouette that an eye moved in an earlier frame brought
    into view away from the moving part is found within REFRESH frames."""
    from blobtree_ink.agents import continuation as CT
    for turn in (0.01, 0.0):
        prev, ages, afresh, static = session(pair(0.8), EYE).continuation(), [], [], []
        for k in range(1, CT.REFRESH + 2):
            s = session(pair(0.8 + 0.002 * k), turned(EYE, turn * k), prev)
            ages.append(s.carried.age)
            afresh.append(s._changed_here(np.array([[-1.0, 0, 0]]))[0])       # the far side of the fixed sphere
            static.append(s._static)
            prev = s.continuation()
        assert ages == list(range(1, CT.REFRESH)) + [0, 1]
        assert afresh == [False] * (CT.REFRESH - 1) + [True, False]
        assert static == [turn == 0.0] * len(ages)


def test_what_changed_between_two_models():
    assert changed(pair(0.8), pair(0.8)) is None
    renamed = M.Model(pair(0.8).root, "other", 0.5)
    assert changed(pair(0.8), renamed) is None
    boxes = changed(pair(0.8), pair(1.0))
    assert isinstance(boxes, Boxes) and len(boxes) == 2                 # the moved sphere, before and after
    K = 0.9 * np.sqrt(1 - 0.5 ** (1 / 3))
    assert boxes.contains(np.array([[0.8 + K, 0, 0], [1.0 + K, 0, 0], [1.85, 0, 0]])).all()
    assert not boxes.contains(np.array([[-0.5, 0, 0]])).any()          # beyond the moved sphere's support
    assert changed(pair(0.8), M.Model(pair(0.8).root, "pair", 0.4)) is EVERYWHERE
    assert changed(pair(0.8), pair(0.8, "blend")) is EVERYWHERE         # another operator
    three = doc({"type": "union", "children": [point(0.0), point(1.0), point(2.0)]})
    assert changed(pair(0.8), three) is EVERYWHERE                     # another shape
    r1 = doc({"type": "ricci", "n": 2, "children": [point(0.0), point(1.0)]})
    r2 = doc({"type": "ricci", "n": 3, "children": [point(0.0), point(1.0)]})
    assert changed(r1, r2) is EVERYWHERE


def test_a_session_keeps_what_did_not_change_and_seeds_what_the_eye_moved():
    first = session(pair(0.8), EYE)
    prev = first.continuation()
    assert {o.kind for o in prev.outlines} == {"silhouette", "crease"}
    same = carried(prev, pair(0.8), View(eye=EYE).key(), Settings(resolution=20))
    assert same.changed is None and same.init is prev.init and not same.seeds
    assert not same.kept and [id(o) for o in same.whole] == [id(o) for o in prev.outlines]     # as they were
    moved_eye = carried(prev, pair(0.8), View(eye=turned(EYE, 0.05)).key(), Settings(resolution=20))
    assert {o.kind for o in moved_eye.whole} == {"crease"} and {o.kind for o in moved_eye.seeds} == {"silhouette"}
    part = carried(prev, pair(0.85), View(eye=EYE).key(), Settings(resolution=20))
    assert isinstance(part.changed, Boxes) and part.init is None and not part.seeds
    kept = np.concatenate([o.points for o in part.kept + part.whole])
    assert not part.changed.contains(kept).any() and len(kept)          # only where nothing changed
    both = carried(prev, pair(0.85), View(eye=turned(EYE, 0.05)).key(), Settings(resolution=20))
    seeded = np.concatenate([o.points for o in both.seeds])             # the silhouettes outside, seen anew
    assert {o.kind for o in both.seeds} == {"silhouette"} and not both.changed.contains(seeded).any()
    shape = carried(prev, pair(0.85, "blend"), View(eye=EYE).key(), Settings(resolution=20))
    assert shape.changed is EVERYWHERE and not shape.kept + shape.whole and not shape.seeds     # as from scratch
    other = carried(prev, pair(0.8), View(eye=EYE).key(), Settings(resolution=20, kinds=("silhouette",)))
    assert other.changed is EVERYWHERE and not other.kept + other.whole and not other.seeds and other.init is None


def test_nothing_changed_keeps_the_last_frames_outlines_without_tracing():
    first = session(pair(0.8), EYE)
    again = session(first.ev, EYE, first.continuation())
    assert again.traces.serial == 0                                      # no trace started
    assert sum(len(o.points) for o in again.outlines()) == sum(len(o.points) for o in first.outlines())


def test_a_frame_going_on_from_the_last_equals_one_from_scratch_for_less_work(load_example):
    """The heart seen from an eye that turns about it: each frame, going on from the
    last, finds the outlines a scratch session finds (within half a cell, both ways;
    a small silhouette a moving eye brings into view waits for the next frame whose
    detail phase looks everywhere: agents.continuation.REFRESH), on the last frame's
    polygonisation, with a small share of the field evaluations."""
    ev = M.Evaluator(load_example("heart"))
    prev = session(ev, EYE).continuation()
    for k in (1, 2, 3):
        eye = turned(EYE, 0.04 * k)
        fresh = M.Evaluator(load_example("heart"))
        scratch = session(fresh, eye)
        before = ev.stats.points
        going = session(ev, eye, prev)
        assert going.mesh is prev.init.mesh                           # the model stayed: its polygonisation too
        assert covered(going.outlines(), scratch.outlines(), 0.5 * scratch.h) >= 0.97, k
        assert ev.stats.points - before < 0.35 * fresh.stats.points, (ev.stats.points - before, fresh.stats.points)
        prev = going.continuation()


def test_a_moved_part_is_traced_again_and_the_rest_kept(load_example):
    first = session(pair(0.8), EYE)
    going = session(pair(0.9), EYE, first.continuation())
    scratch = session(pair(0.9), EYE)
    assert covered(going.outlines(), scratch.outlines(), 0.5 * scratch.h) >= 0.99
    P = np.concatenate([o.points for o in first.outlines()])
    far = P[~going.carried.changed.contains(P)]
    got = {tuple(p) for o in going.outlines() for p in o.points}
    assert len(far) > 20 and all(tuple(p) in got for p in far)          # kept as they were, point for point


def test_other_settings_start_from_scratch(load_example):
    first = session(pair(0.8), EYE)
    s = Settings(resolution=20, kinds=("silhouette",))
    going = Session(M.Evaluator(pair(0.8)), View(eye=EYE), s, previous=first.continuation())
    going.request("OUTLINES")
    going.run()
    scratch = Session(M.Evaluator(pair(0.8)), View(eye=EYE), Settings(resolution=20, kinds=("silhouette",)))
    scratch.request("OUTLINES")
    scratch.run()
    a, b = going.outlines(), scratch.outlines()
    assert len(a) == len(b) and all(np.array_equal(x.points, y.points) for x, y in zip(a, b))


def job(model, eye, style="hatched", light=(-0.4, -0.5, 0.75)):
    requests = (PL.Request("OUTLINES"), PL.Request("PLACE_STROKES"))
    return PL.Job(model, View(eye=eye), np.array(light), ST.style(style), requests, 0, Settings(resolution=16))


def test_an_illustration_going_on_from_the_last_frame(load_example):
    """The model stays and the eye turns: the next frame takes the last one's compiled
    model (its marks, its kept paths); its marked strokes are those a frame alone draws,
    bit for bit, and its outlines are within the tolerance of a frame alone's."""
    model = load_example("pear")
    first = PL.Illustration(job(model, EYE), remember=True)
    first.run()
    prev = first.continuation()
    eye = turned(EYE, 0.05)
    going = PL.Illustration(job(model, eye), previous=prev, remember=True)
    res = going.run()
    assert going.ev is first.ev
    alone = PL.Illustration(job(model, eye))
    res_alone = alone.run()
    assert going.ev is not alone.ev
    for layer in ("Hatching",):
        a, b = res.strokes.layers[layer], res_alone.strokes.layers[layer]
        assert [s.mark for s in a] == [s.mark for s in b]
        assert all(np.array_equal(x.points, y.points) for x, y in zip(a, b))
    cell = going.session.h
    assert covered(going.sampling.outlines, alone.sampling.outlines, 0.5 * cell) >= 0.99
    sil = [np.concatenate([s.points for s in r.strokes.layers["Silhouette"]]) for r in (res, res_alone)]
    assert np.mean(nearest_distance(sil[0], sil[1]) < 0.5 * cell) > 0.98


def test_a_settled_model_makes_every_marks_path_at_once(load_example):
    """A frame whose model is the last frame's makes the wandering smarticles' paths of
    every stipple mark, in shade or not: a next frame whose eye and light moved (other
    marks in shade) makes none; a hatching map is made once and kept. Its strokes are
    those a frame alone draws (helpers.same_marked), the hatching's beside the same
    outlines (a frame that goes on traces its outlines within their tolerance of a frame
    alone's, and hatching ends where a line crosses one)."""
    model = load_example("pear")
    for style, layer, made in (("stippled", "Stipples", "paths"), ("hatched", "Hatching", "hatch map")):
        first = PL.Illustration(job(model, EYE, style), remember=True)
        first.run()
        second = PL.Illustration(job(model, turned(EYE, 0.05), style), previous=first.continuation(), remember=True)
        second.run()
        assert not first.canvas.settled and second.canvas.settled and second.ev is first.ev
        kept = {k: v if made == "hatch map" else len(v) for k, v in second.ev.memo.items() if k[0] == made}
        assert kept
        eye, light = turned(EYE, 0.4), (0.5, -0.2, 0.8)
        third = PL.Illustration(job(model, eye, style, light), previous=second.continuation(), remember=True)
        res = third.run()
        assert {k: v if made == "hatch map" else len(v) for k, v in third.ev.memo.items() if k[0] == made} == kept
        alone = job(model, eye, style, light)
        if layer == "Hatching":             # (stipples are compared where the outlines differ, helpers.same_marked)
            lines = tuple(s for name in LAYER_OF_KIND.values() for s in res.strokes.layers.get(name, ()))
            alone = replace(alone, requests=(PL.Request("PLACE_STROKES"),), lines=lines)
        alone = PL.Illustration(alone).run()
        a, b = res.strokes.layers[layer], alone.strokes.layers[layer]
        same_marked(a, b, layer)
        # marks the first frames drew none from are drawn from in the third
        drawn = {st.mark for st in first.result().strokes.layers[layer]}
        assert {st.mark for st in a} - drawn


def test_a_stopped_or_unfinished_illustration_leaves_nothing(load_example):
    ill = PL.Illustration(job(load_example("pear"), EYE), remember=True)
    assert ill.continuation() is None
    ill.step()
    ill.stop()
    ill.run()
    assert ill.continuation() is None


def test_a_model_changed_between_frames_is_compiled_again(load_example):
    model = load_example("two_spheres")
    first = PL.Illustration(job(model, EYE), remember=True)
    first.run()
    moved = M.Model(N.Transform(model.root, translate=(0.1, 0, 0)), model.name, model.iso)
    going = PL.Illustration(job(moved, EYE), previous=first.continuation(), remember=True)
    res = going.run()
    assert going.ev is not first.ev
    alone = PL.Illustration(job(moved, EYE)).run()
    a, b = res.strokes.layers["Hatching"], alone.strokes.layers["Hatching"]
    assert [s.mark for s in a] == [s.mark for s in b]


def test_the_same_eye_and_model_keep_everything(load_example):
    """Seen from where the last frame's eye was, a model that did not change keeps every
    outline of the last frame, which ran to its end: no seed, no agent, no system
    iteration (the heart's small silhouettes and walks included)."""
    for name in ("pear", "heart"):
        model = load_example(name)
        first = PL.Illustration(job(model, EYE), remember=True)
        r1 = first.run()
        going = PL.Illustration(job(model, EYE), previous=first.continuation(), remember=True)
        r2 = going.run()
        s = going.session
        assert s.carried.walks is not None and s.done
        assert s.iteration == 0 and s.traces.serial == 0 and s.explorers.started == 0
        assert len(s.bb.open_features()) == 0
        same_strokes(r1.strokes, r2.strokes)
