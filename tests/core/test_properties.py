"""Property-based tests (hypothesis): generated valid models with every node type
illustrate or fail with a named error, and what the agents trace is right by the exact
field alone (tests/core/truth.py): every point on the surface, every silhouette point
with n.v near 0, every crease point where the normal really jumps.

Derandomised (the same examples in every run, so CI cannot flake); more examples:
BTI_PROPERTY_EXAMPLES=500."""
import os

import numpy as np
from hypothesis import HealthCheck, example, given, settings
from hypothesis import strategies as st

from blobtree_ink import model as M
from blobtree_ink import pipeline as PL
from blobtree_ink.agents import Session, Settings
from blobtree_ink.agents import ridges
from blobtree_ink.blackboard.board import FEATURE_KINDS
from blobtree_ink.blackboard.view import View

import truth

EXAMPLES = int(os.environ.get("BTI_PROPERTY_EXAMPLES", "40"))
SILHOUETTE_NV = 1e-5            # |n.v| of a traced silhouette point
CHECKED = 150                   # crease points checked per model (the truth costs ~100 projections each)

coord = st.floats(-1.0, 1.0, allow_nan=False).map(float)
vec = st.tuples(coord, coord, coord).map(list)
radius = st.floats(0.3, 1.5).map(float)
nonzero = st.tuples(coord, coord, coord).filter(lambda v: sum(x * x for x in v) > 0.01).map(list)


def leaf():
    return st.one_of(
        st.builds(lambda c, r: {"type": "point", "center": c, "radius": r}, vec, radius),
        st.builds(lambda a, b, r: {"type": "segment", "a": a, "b": b, "radius": r}, vec, vec, radius),
        st.builds(lambda c, n, cr, r: {"type": "circle", "center": c, "normal": n, "circle_radius": cr, "radius": r},
                  vec, nonzero, st.floats(0.2, 1.0).map(float), radius),
        st.builds(lambda c, n, dr, r: {"type": "disc", "center": c, "normal": n, "disc_radius": dr, "radius": r},
                  vec, nonzero, st.floats(0.1, 0.8).map(float), radius),
        st.builds(lambda c, h, r: {"type": "box", "center": c, "half_size": h, "radius": r},
                  vec, st.tuples(*[st.floats(0.0, 0.6).map(float)] * 3).map(list), st.floats(0.2, 0.8).map(float)))


def node(children):
    kids = st.lists(children, min_size=2, max_size=3)
    one = children
    scale = st.tuples(*[st.floats(0.6, 1.6).map(float)] * 3).map(list)
    angles = st.tuples(*[st.floats(-3.0, 3.0).map(float)] * 3).map(list)
    return st.one_of(
        st.builds(lambda k: {"type": "blend", "children": k}, kids),
        st.builds(lambda k, n: {"type": "ricci", "children": k, "n": n}, kids, st.sampled_from([1.0, 2.0, 4.0, 16.0])),
        st.builds(lambda k: {"type": "union", "children": k}, kids),
        st.builds(lambda k: {"type": "intersection", "children": k}, kids),
        st.builds(lambda k: {"type": "difference", "children": k}, kids),
        st.builds(lambda c, t, r, s: {"type": "transform", "child": c, "translate": t, "rotate": r, "scale": s},
                  one, vec, angles, scale),
        st.builds(lambda c, r: {"type": "twist", "child": c, "rate": r}, one, st.floats(-1.5, 1.5).map(float)),
        st.builds(lambda c, r: {"type": "taper", "child": c, "rate": r}, one, st.floats(-0.4, 0.4).map(float)),
        st.builds(lambda c, r: {"type": "bend", "child": c, "rate": r}, one,
                  st.floats(-1.0, 1.0).map(float).filter(lambda r: r == 0 or abs(r) >= 1e-9)))


models = st.recursive(leaf(), node, max_leaves=5).map(lambda root: {"format": "blobtree-1", "root": root})


def session_of(doc, kinds=Settings.kinds, resolution=12):
    """The model's session (tracing ``kinds``) run to the end from a three-quarter view,
    or None where the model has no surface (a named error: NothingToDraw)."""
    ev = M.Evaluator(M.from_dict(doc))
    try:
        centre, r = PL.bounds(ev)
    except PL.NothingToDraw:
        return None, None
    eye = PL.three_quarter_eye(centre, r)
    s = Session(ev, View(eye=eye), Settings(resolution=resolution, agents=2000, kinds=kinds))
    s.request("OUTLINES")
    s.run(iterations=400)
    return s, eye


@settings(max_examples=EXAMPLES, derandomize=True, database=None, deadline=None,
          suppress_health_check=list(HealthCheck))
@given(models)
@example({"format": "blobtree-1", "root": {"type": "intersection", "children": [   # n.v 1.4e-3 beside a crease
    {"type": "blend", "children": [{"type": "point", "center": [0.0, 0.0, 0.0], "radius": 0.75},
                                   {"type": "circle", "center": [0.0, 1.0, 0.0], "normal": [0.0, 1.0, 0.0],
                                    "circle_radius": 1.0, "radius": 1.25}]},
    {"type": "blend", "children": [{"type": "point", "center": [0.0, 0.0, 0.0], "radius": 0.3},
                                   {"type": "segment", "a": [0.0, 0.0, 1.0], "b": [0.0, 0.0, 0.5], "radius": 1.25}]}]}})
@example({"format": "blobtree-1", "root": {"type": "intersection", "children": [   # sheets meeting past a junction
    {"type": "point", "center": [0.0, 0.0, 0.25], "radius": 1.0},
    {"type": "union", "children": [{"type": "point", "center": [0.0, 0.0, 0.0], "radius": 1.0},
                                   {"type": "segment", "a": [0.0, 0.0, 0.0], "b": [0.0, 1.0, 0.0], "radius": 0.5}]}]}})
def test_generated_models_trace_right(doc):
    s, eye = session_of(doc)
    if s is None:
        return
    sil = points_on_the_surface(s, "silhouette")
    if len(sil):
        assert truth.silhouette_residual(s.ev, sil, eye).max() < SILHOUETTE_NV
    cre = points_on_the_surface(s, "crease", CHECKED)
    if len(cre):
        assert truth.on_a_crease(s.ev, cre).all()


def points_on_the_surface(s, kind, most=None):
    """Session s's outline points of ``kind`` (at most ``most``, spread along them),
    having checked that every outline point, of every kind, is finite and on the
    surface."""
    outs = s.outlines()
    for o in outs:
        assert np.isfinite(o.points).all()
        assert truth.on_the_surface(s.ev, o.points).all(), o.kind
    X = np.concatenate([o.points for o in outs if o.kind == kind] or [np.zeros((0, 3))])
    return X if most is None else X[np.linspace(0, len(X) - 1, min(len(X), most)).astype(int)]


@settings(max_examples=EXAMPLES // 2, derandomize=True, database=None, deadline=None,
          suppress_health_check=list(HealthCheck))
@given(models)
@example({"format": "blobtree-1", "root": {"type": "union", "children": [     # no ridge along a union's crease
    {"type": "point", "center": [1.0, 0.0, 0.0], "radius": 0.375},
    {"type": "point", "center": [0.75, 0.0, 0.0], "radius": 0.5}]}})
def test_generated_models_trace_every_kind_right(doc):
    """Every kind of line at once (curvature-sign lines, suggestive contours and
    apparent ridges too): the session ends, every point lies on the surface, and every
    apparent ridge point is one by the field alone."""
    s, eye = session_of(doc, FEATURE_KINDS, resolution=10)
    if s is None:
        return
    assert s.done
    X = points_on_the_surface(s, "ridges", CHECKED)
    if len(X):
        assert truth.ridge_points(s.ev, X, eye, ridges.RIDGE_MIN, ridges.FACING, ridges.PEAK_PROBE).all()


@settings(max_examples=EXAMPLES, derandomize=True, database=None, deadline=None,
          suppress_health_check=list(HealthCheck))
@given(models, st.sampled_from(["stippled", "hatched", "short-strokes"]))
def test_generated_models_illustrate_or_name_the_problem(doc, style):
    from blobtree_ink.strokes import style as ST
    ev = M.Evaluator(M.from_dict(doc))
    try:
        centre, r = PL.bounds(ev)
    except PL.NothingToDraw:
        return
    eye = PL.three_quarter_eye(centre, r)
    requests = (PL.Request("OUTLINES"), PL.Request("PLACE_STROKES"))
    job = PL.Job(ev, View(eye=eye), PL.default_light(centre, eye), ST.style(style), requests, 0,
                 Settings(resolution=10, agents=2000))
    res = PL.Illustration(job).run()
    assert res.done
    for layer in res.strokes.layers.values():
        for stroke in layer:
            assert np.isfinite(stroke.points).all() and (stroke.radius > 0).all()
