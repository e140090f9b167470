"""Other models of the scene that hide a model's lines (a job's occluders): what they
hide, what a frame going on takes from the last one, and what a drawing records of them
(pipeline.hiding)."""
import dataclasses

import numpy as np

from blobtree_ink import model as M
from blobtree_ink import pipeline as PL
from blobtree_ink.blackboard.view import View
from blobtree_ink.model.projection import project
from blobtree_ink.strokes import style as ST
from blobtree_ink.strokes.visibility import Sight, march_step, visible
from helpers import BALL, same_strokes


def test_another_solid_of_the_scene_hides_the_lines_behind_it():
    """A ball placed between the eye and a model (an occluder: its model and the matrix
    from the model's coordinates into the ball's) hides the model's outlines and strokes
    behind it, as the model's own parts do; the drawing's key tells the two apart."""
    model = M.from_dict({"format": "blobtree-1", "root": {"type": "segment", "a": [-1.5, 0, 0], "b": [1.5, 0, 0],
                                                          "radius": 0.8}})
    eye = np.array([0.0, -8.0, 0.0])
    ball_at = np.eye(4)
    ball_at[:3, 3] = [0.0, 4.0, 0.0]         # the ball at y = -4, in front: model point p is ball point p + (0, 4, 0)
    jobs = [PL.Job(model, View(eye=eye), requests=(PL.Request("OUTLINES"), PL.Request("PLACE_STROKES")),
                   style=ST.style("hatched"), occluders=hidden) for hidden in ((), ((M.from_dict(BALL), ball_at),))]
    alone, behind = (PL.Illustration(j).run().strokes.layers for j in jobs)
    ball = M.Evaluator(M.from_dict(BALL))
    r_ball = -float(project(ball, np.array([[0.0, -0.5, 0.0]]), 30)[0][0, 1])

    def shadowed(P):                         # behind the ball: the ray to the eye passes within its radius
        c = np.array([0.0, -4.0, 0.0])
        d = (P - eye) / np.linalg.norm(P - eye, axis=1)[:, None]
        return np.linalg.norm((c - eye) - ((c - eye) @ d.T)[:, None] * d, axis=1) < r_ball * 0.98

    for layer in ("Silhouette", "Hatching"):
        P_alone = np.concatenate([s.points for s in alone[layer]])
        P_behind = np.concatenate([s.points for s in behind[layer]])
        assert shadowed(P_alone).sum() > 10, layer             # the model alone draws lines where the ball stands
        assert not shadowed(P_behind).any(), layer
        assert len(P_behind) > 10
    sight = Sight(M.Evaluator(model), ((ball, ball_at),))
    P = np.array([[0.0, -0.45, 0.0], [1.4, -0.3, 0.6]])        # the model's front behind the ball; beside it
    np.testing.assert_array_equal(visible(sight, P, eye), [False, True])
    np.testing.assert_array_equal(visible(M.Evaluator(model), P, eye), [True, True])
    key = [j.checked().making("k") for j in jobs]
    shifted = ball_at.copy()
    shifted[0, 3] = 0.01
    moved = dataclasses.replace(jobs[1], occluders=((M.from_dict(BALL), shifted),))
    assert len({*key, moved.checked().making("k")}) == 3


def test_a_frame_going_on_takes_the_last_frames_occluders_where_they_are_the_same():
    """A frame going on from the last takes the last frame's compiled occluder (its plan
    and surface box made) where the occluder's model is the same, wherever it stands,
    and compiles one whose model changed; it draws what a frame drawn alone draws."""
    model = M.from_dict({"format": "blobtree-1", "root": {"type": "segment", "a": [-1.5, 0, 0], "b": [1.5, 0, 0],
                                                          "radius": 0.8}})
    ball_at = np.eye(4)
    ball_at[:3, 3] = [0.0, 4.0, 0.0]

    def job(ball, y):
        at = ball_at.copy()
        at[1, 3] = y
        return PL.Job(model, View(eye=np.array([0.0, -8.0, 0.0])), style=ST.style("hatched"),
                      requests=(PL.Request("OUTLINES"), PL.Request("PLACE_STROKES")), occluders=((ball, at),))

    first = PL.Illustration(job(M.from_dict(BALL), 4.0), remember=True)
    first.run()
    kept = first.continuation()
    assert len(kept.occluders) == 1 and kept.occluders[0].model == M.from_dict(BALL)
    moved = PL.Illustration(job(M.from_dict(BALL), 4.2), previous=kept, remember=True)   # an equal model, moved
    going_on = moved.run().strokes
    assert moved.continuation().occluders[0] is kept.occluders[0]
    same_strokes(going_on, PL.Illustration(job(M.from_dict(BALL), 4.2)).run().strokes)
    bigger = M.from_dict({**BALL, "root": {**BALL["root"], "radius": 1.3 * BALL["root"]["radius"]}})
    grown = PL.Illustration(job(bigger, 4.2), previous=moved.continuation())
    grown.run()
    assert grown.canvas.sight.others[0][0] is not kept.occluders[0]
    assert grown.canvas.sight.others[0][0].model == bigger


def test_a_drawing_records_which_other_models_stood_between_it_and_the_eye():
    """A result records each other model by name: the key of the model where it stood,
    and whether it stood between the eye and the drawn model; a drawing is out of date
    when one that stood between moves, changes or goes, or another comes between, not
    when one beside the view moves."""
    from blobtree_ink.pipeline import hiding as HD
    model = M.from_dict({"format": "blobtree-1", "root": {"type": "point", "center": [0.0, 0.0, 0.0], "radius": 1.0}})

    def at(x, y, z, name):
        A = np.eye(4)
        A[:3, 3] = [-x, -y, -z]                  # the other's coordinates: model point p is other point p - (x, y, z)
        return dataclasses.replace(M.from_dict(BALL), name=name), A
    eye = np.array([0.0, -8.0, 0.0])
    others = (at(0.2, -3.0, 0.0, "front"), at(6.0, 0.0, 0.0, "aside"), at(0.0, 4.0, 0.0, "behind"))
    res = PL.Illustration(PL.Job(model, View(eye=eye), occluders=others)).run()
    assert {k: v[1] for k, v in res.hiders.items()} == {"front": True, "aside": False, "behind": False}
    assert PL.Illustration(PL.Job(model, View(eye=eye))).run().hiders == {}
    ball, A = at(0.2, -3.0, 0.0, "front")
    assert HD.place_key(M.fingerprint(ball), A) == res.hiders["front"][0]
    now = dict(res.hiders)
    assert not HD.changed(res.hiders, now)
    assert not HD.changed(res.hiders, {**now, "aside": ("moved", False)})          # beside the view, then and now
    assert HD.changed(res.hiders, {**now, "aside": ("moved", True)})               # ... come between
    assert HD.changed(res.hiders, {**now, "front": ("moved", False)})              # the one between moved away
    assert HD.changed(res.hiders, {k: v for k, v in now.items() if k != "front"})  # ... or is gone
    assert not HD.changed(res.hiders, {k: v for k, v in now.items() if k != "aside"})
    assert HD.changed(res.hiders, {**now, "new": ("k", True)})                     # a new one between
    assert not HD.changed(res.hiders, {**now, "new": ("k", False)})
    assert HD.named([("a", 1), ("b", 2), ("a", 3)]) == {"a": 1, "b": 2, "a#2": 3}
    c, r = np.zeros(3), 1.0
    assert HD.between(eye, (c, r), (np.array([0.0, -3.0, 0.0]), 0.5))            # in front
    assert not HD.between(eye, (c, r), (np.array([0.0, 3.0, 0.0]), 0.5))         # behind it
    assert not HD.between(eye, (c, r), (np.array([3.0, -3.0, 0.0]), 0.5))         # beside it
    assert HD.between(eye, (c, r), (eye + [0.0, 0.1, 0.0], 0.5))                 # round the eye


def test_a_thin_occluder_before_a_big_model_is_not_stepped_over():
    """Another solid is sampled at its own size's step where that is finer than the
    model's: a thin rod a hundredth of a big model's size, standing before it, hides
    every point of the model right behind it (the model's own step is wider than the
    rod)."""
    big = M.Evaluator(M.from_dict({"format": "blobtree-1", "root": {
        "type": "segment", "a": [-50, 0, 0], "b": [50, 0, 0], "radius": 60.0}}))
    rod = M.Evaluator(M.from_dict({"format": "blobtree-1", "root": {
        "type": "segment", "a": [0, 0, -30], "b": [0, 0, 30], "radius": 0.25}}))
    eye = np.array([0.0, -400.0, 0.0])
    front = -float(project(big, np.array([[0.0, -10.0, 0.0]]), 30)[0][0, 1])          # the big model's front
    half = float(project(rod, np.array([[0.1, 0.0, 0.0]]), 30)[0][0, 0])               # the rod's half width
    assert march_step(big) > 2.5 * half                                                # it steps over the rod
    rod_at = np.eye(4)
    rod_at[:3, 3] = [0.0, 100.0, 0.0]          # the rod 100 units before the model: model p is rod p + (0, 100, 0)
    # points of the model's front in the plane x = 0, which holds the eye and the rod's axis:
    # every ray from them to the eye crosses the axis
    z = np.linspace(-10.0, 10.0, 41)
    P, _, _ = project(big, np.stack([np.zeros_like(z), np.full_like(z, -front), z], axis=1), 30)
    assert np.abs(P[:, 0]).max() < 1e-9 and np.abs(P[:, 2]).max() < 20
    assert not visible(Sight(big, ((rod, rod_at),)), P, eye).any()
    assert visible(big, P, eye).all()                                                  # the model alone: all seen


def test_a_model_wholly_hidden_by_another_is_said():
    """A small ball behind a big one, seen past it: nothing of the small ball is drawn,
    and the result says why (not an empty drawing without a word)."""
    small = M.from_dict({"format": "blobtree-1", "root": {"type": "point", "center": [0, 0, 0], "radius": 0.5}})
    big_at = np.eye(4)
    big_at[:3, 3] = [0.0, 4.0, 0.0]          # model point p is the big ball's point p + (0, 4, 0): it stands at y = -4
    big = M.from_dict({"format": "blobtree-1", "root": {"type": "point", "center": [0, 0, 0], "radius": 3.0}})
    job = PL.Job(small, View(eye=np.array([0.0, -12.0, 0.0])), requests=(PL.Request("OUTLINES"),),
                 style=ST.style("outlines"), occluders=((big, big_at),))
    res = PL.Illustration(job).run()
    assert not any(res.strokes.layers.values())
    assert any("nothing of the model is seen: the models in front of it hide" in w for w in res.warnings)
    alone = PL.Illustration(dataclasses.replace(job, occluders=())).run()
    assert alone.strokes.layers["Silhouette"] and not any("nothing of" in w for w in alone.warnings)
