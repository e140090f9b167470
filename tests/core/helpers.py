"""Small helpers shared by core tests."""
import numpy as np

BALL = {"format": "blobtree-1", "root": {"type": "point", "center": [0.0, 0.0, 0.0], "radius": 1.0}}     # a point primitive at the origin


def near_surface_points(ev, n, seed=0, band=0.35):
    """Random points inside the support bounds whose field is within +-band of iso."""
    rng = np.random.default_rng(seed)
    lo, hi = ev.bounds
    out = []
    got = 0
    for _ in range(200):
        P = rng.uniform(lo, hi, size=(20000, 3))
        f = ev.field(P)
        keep = P[np.abs(f - ev.iso) < band]
        out.append(keep)
        got += len(keep)
        if got >= n:
            break
    return np.concatenate(out)[:n]


def fd_gradient(ev, P, h=1e-6):
    G = np.zeros_like(P)
    for k in range(3):
        e = np.zeros(3)
        e[k] = h
        G[:, k] = (ev.field(P + e) - ev.field(P - e)) / (2 * h)
    return G


def job_for(load_example, name, style="outlines", res=16, seed=0, requests=None, **style_changes):
    """A pipeline job for an example seen from a fixed three-quarter view, lit from the
    viewer's upper left: outlines, and the style's strokes when it has any."""
    from blobtree_ink import model as M
    from blobtree_ink import pipeline as PL
    from blobtree_ink.agents import Settings
    from blobtree_ink.blackboard.view import View
    from blobtree_ink.strokes import style as ST
    ev = M.Evaluator(load_example(name))
    centre, radius = PL.bounds(ev)
    eye = PL.three_quarter_eye(centre, radius)
    st = ST.style(style, **style_changes)
    if requests is None:
        requests = [PL.Request("OUTLINES")]
        if st.stroke_switches():
            requests.append(PL.Request("PLACE_STROKES"))
    return PL.Job(ev, View(eye=eye), PL.default_light(centre, eye), st, tuple(requests), seed, Settings(resolution=res))


def same_strokes(a, b):
    """Two stroke sets hold the same strokes, bit for bit."""
    assert {k: len(v) for k, v in a.layers.items()} == {k: len(v) for k, v in b.layers.items()}
    for name in a.layers:
        for x, y in zip(a.layers[name], b.layers[name]):
            assert np.array_equal(x.points, y.points) and np.array_equal(x.radius, y.radius)
            assert np.array_equal(x.opacity, y.opacity) and x.cyclic == y.cyclic and x.dots == y.dots


def same_marked(a, b, layer):
    """A marked layer's strokes of two frames are the same strokes, by their marks, bit
    for bit; but the stipples, which are drawn finer beside the outlines, where the
    outlines differ within their tolerance (a frame after others traces them from
    theirs): there a dot's size differs by a part of a line's width, and one that shrank to nothing may be
    kept in one and not in the other (under a fifth of the largest dot, both: a light
    tone's dots are small)."""
    if layer == "Stipples":
        largest = max(st.radius[0] for st in a)
        a, b = ({st.mark: st for st in x} for x in (a, b))
        assert all(x[k].radius[0] < 0.2 * largest for x in (a, b) for k in set(a) ^ set(b) if k in x)
        assert all(abs(a[k].radius[0] - b[k].radius[0]) < 0.25 * largest for k in set(a) & set(b))
        a, b = ([x[k] for k in sorted(set(a) & set(b))] for x in (a, b))
    assert len(a) > 20 and [st.mark for st in a] == [st.mark for st in b], layer
    assert all(np.array_equal(x.points, y.points) for x, y in zip(a, b)), layer
