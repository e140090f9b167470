"""Valid models illustrate or fail with a named error; found by fuzzing the examples."""
import json

import numpy as np

from blobtree_ink import model as M
from blobtree_ink import pipeline as PL
from blobtree_ink.agents import Settings
from blobtree_ink.blackboard.view import View
from blobtree_ink.strokes import style as ST


def illustrate(model, style="hatched", res=12):
    ev = M.Evaluator(model)
    centre, radius = PL.bounds(ev)
    eye = PL.three_quarter_eye(centre, radius)
    st = ST.style(style)
    requests = (PL.Request("OUTLINES"),) + ((PL.Request("PLACE_STROKES"),) if st.stroke_switches() else ())
    job = PL.Job(ev, View(eye=eye), PL.default_light(centre, eye), st, requests, 0, Settings(resolution=res))
    return PL.Illustration(job).run()


def jug(**changes):
    doc = json.load(open(__import__("conftest").example_path("jug")))
    body = doc["root"]["children"][0]["children"][0]["children"]
    for path, value in changes.items():
        node = body[int(path[0])]
        node = node["child"] if path[1:] == "c" else node
        node.update(value)
    return M.from_dict(doc)


def test_features_found_in_voxels_the_blackboard_made_later_are_assigned():
    """A sharply tapered jug: the detail phase puts seeds in voxels made after the
    priorities were computed (an IndexError in the manager's assignment)."""
    model = jug(**{"0": {"rate": 19.103119538386878}})
    res = illustrate(model)
    assert res.done and len(res.strokes.layers["Silhouette"]) > 0
    assert len(res.strokes.layers["Hatching"]) > 0


def test_a_model_whose_parts_are_thinner_than_a_cell_says_so():
    """A spout 2000 units long beside a jug 4 units wide: at grid 12 a cell is 43 units
    wide and the rough mesh is empty (integers from an empty bincount broke it)."""
    doc = json.load(open(__import__("conftest").example_path("jug")))
    spout = doc["root"]["children"][0]["children"][0]["children"][2]
    spout["a"] = [2015.05, 0.0, 0.0]
    res = illustrate(M.from_dict(doc))
    assert res.done
    assert any("found no surface: the model's parts are thinner than a cell" in w for w in res.warnings)
    assert not res.strokes.layers["Silhouette"]
    assert np.isfinite(np.concatenate([s.points for s in res.strokes.layers["Hatching"]])).all()
