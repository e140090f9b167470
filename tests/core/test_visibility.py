"""Hidden-line removal against the exact surface: a sphere behind a sphere."""
import numpy as np

from blobtree_ink import model as M
from blobtree_ink.agents import Outline
from blobtree_ink.strokes import StrokeSet, split_visible, visible
from blobtree_ink.strokes import visibility as V
from blobtree_ink.strokes.visibility import split_visible_many


def two_balls():
    return M.Evaluator(M.from_dict({"format": "blobtree-1", "root": {"type": "union", "children": [
        {"type": "point", "center": [0, 0, 0], "radius": 1.0},
        {"type": "point", "center": [0, 3, 0], "radius": 1.0}]}}))


def test_a_ball_hides_what_is_behind_it():
    ev = two_balls()
    eye = np.array([0.0, -10.0, 0.0])            # looking along +y: the first ball hides the second's middle
    r = 0.4543
    behind = np.array([[0, 3 - r, 0], [0.1, 3 - r + 0.02, 0.05]])       # the second ball's front, behind ball 1
    aside = np.array([[3.0, 3.0, 0.0]])                                 # empty space off to the side
    front = np.array([[0, -r, 0]])
    v = visible(ev, np.concatenate([behind, aside, front]), eye)
    np.testing.assert_array_equal(v, [False, False, True, True])


def test_strokes_are_split_where_visibility_changes():
    ev = two_balls()
    eye = np.array([0.0, -10.0, 0.0])
    # a line across the second ball's front: hidden in the middle (behind ball 1), visible at the ends
    x = np.linspace(-1.2, 1.2, 49)
    pts = np.stack([x, np.full_like(x, 3 - 0.46), np.zeros_like(x)], axis=1)
    runs = split_visible(ev, pts, eye)
    assert len(runs) == 2
    (a0, a1), (b0, b1) = (r[:2] for r in runs)
    assert a0 == 0 and b1 == len(x)
    hidden = x[a1:b0]
    # the shadow of ball 1 (radius r at distance 10 from the eye) on the plane y = 2.54
    r = 0.4543
    assert hidden.min() > -0.6 and hidden.max() < 0.6 and hidden.min() < -0.4 and hidden.max() > 0.4


def test_many_strokes_are_split_as_each_alone():
    """In one batch, each polyline's visible runs are those it has alone: a run never
    continues from one polyline into the next, and one shorter than min_points is
    dropped (empty and one-point polylines included)."""
    ev = two_balls()
    eye = np.array([0.0, -10.0, 0.0])
    x = np.linspace(-1.2, 1.2, 49)
    across = np.stack([x, np.full_like(x, 3 - 0.46), np.zeros_like(x)], axis=1)
    front = np.stack([0.3 * x, np.full_like(x, -1.0), np.zeros_like(x)], axis=1)      # between the eye and ball 1
    lines = [across, front[:5], np.zeros((0, 3)), across[20:29], front[:1], across[::-1], front[:2]]
    for m in (1, 2, 3):
        many = split_visible_many(ev, lines, eye, min_points=m)
        alone = [split_visible_many(ev, [p], eye, min_points=m)[0] if len(p) else [] for p in lines]
        assert [[r[:4] for r in rs] for rs in many] == [[r[:4] for r in rs] for rs in alone]
        for rs, qs in zip(many, alone):
            for r, q in zip(rs, qs):
                for e, f in ((r.head, q.head), (r.tail, q.tail)):
                    assert (e is None and f is None) or np.array_equal(e, f)
    got = [[r[:2] for r in rs] for rs in split_visible_many(ev, lines, eye)]
    assert got[1] == [(0, 5)] and got[2] == [] and got[3] == [] and got[4] == [] and got[6] == [(0, 2)]
    assert got[5] == [(0, len(x) - got[0][1][0]), (len(x) - got[0][0][1], len(x))]


def test_a_visible_run_ends_where_its_line_goes_behind_the_surface():
    """A coarse arc over the second ball's front, seen past the first ball from the
    side: the visible run starts, on the surface, where the ray from the arc really
    clears the first ball (not at the first visible point, up to a whole step on)."""
    ev = two_balls()
    eye = np.array([1.5, -10.0, 0.0])
    r = -float(V.project(ev, np.array([[0.0, -0.5, 0.0]]), 30)[0][0, 1])          # the balls' radius at iso
    th = np.linspace(-1.2, 1.2, 13)                                                 # steps of 0.2 rad, ~0.09 long
    arc = np.stack([r * np.sin(th), 3 - r * np.cos(th), 0 * th], axis=1)
    normals = (arc - [0, 3, 0]) / r
    (run,), = split_visible_many(ev, [arc], eye, [normals])

    def clear_of_ball_one(t):                # how far the ray from the arc at angle t passes from ball 1
        X = np.array([r * np.sin(t), 3 - r * np.cos(t), 0.0])
        d = (X - eye) / np.linalg.norm(X - eye)
        return np.linalg.norm(eye - (eye @ d) * d) - r

    lo, hi = th[run.a - 1], th[run.a]        # the shadow's edge on the arc, between them
    assert clear_of_ball_one(lo) < 0 < clear_of_ball_one(hi)
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if clear_of_ball_one(mid) < 0 else (lo, mid)
    edge = np.array([r * np.sin(hi), 3 - r * np.cos(hi), 0.0])
    assert run.b == len(arc) and run.tail is None and run.head is not None and 0 < run.lead < 1
    assert abs(ev.field(run.head[None])[0] - ev.iso) < 1e-9
    assert np.linalg.norm(run.head - edge) < 0.005 < 0.05 < np.linalg.norm(arc[run.a] - edge)
    pts = V.run_points(arc, run)
    assert len(pts) == run.b - run.a + 1 and np.array_equal(pts[0], run.head)
    assert np.allclose(V.piece(normals, run)[0], normals[run.a] + run.lead * (normals[run.a - 1] - normals[run.a]))


def test_hits_are_how_far_the_ray_goes_before_it_enters_the_solid():
    ev = two_balls()
    eye = np.array([0.0, -10.0, 0.0])
    r = 0.4543
    P = np.array([[0.0, 3 - r, 0.0], [0.0, -r, 0.0]])          # behind ball 1; ball 1's own front
    d = V.hits(ev, P, eye)
    step = V.march_step(ev)
    assert abs(d[0] - (3 - 2 * r - step)) <= step and np.isinf(d[1])


def test_a_gap_of_a_point_or_two_hit_close_by_is_drawn_through():
    """Hidden runs of at most GRAZE_POINTS points, every one hit within GRAZE steps,
    between visible points of their own polyline, are the line's own grazing surface;
    longer ones, ones hit further off, and ones at a polyline's end are real gaps."""
    hidden = np.array([0, 1, 0, 1, 1, 0, 1, 1, 1, 0, 1, 0, 1, 1, 1, 0, 1, 0, 1], bool)
    grazed = np.array([0, 1, 0, 1, 1, 0, 1, 1, 1, 0, 0, 0, 1, 1, 1, 1, 1, 1, 1], bool)
    sizes = np.array([14, 5])       # each ends hidden; the second starts hidden too
    v = V._through_grazes(hidden, grazed, sizes)
    assert v.astype(int).tolist() == [1, 1, 1, 1, 1, 1, 0, 0, 0, 1, 0, 1, 0, 0] + [0, 1, 1, 1, 0]


def ball(r=1.0, at=(0.0, 0.0, 0.0)):
    return M.Evaluator(M.from_dict({"format": "blobtree-1", "root": {"type": "point", "center": list(at),
                                                                      "radius": r}}))


def test_another_solid_turned_scaled_and_moved_hides_as_placed():
    """An occluder's matrix takes the model's points into its own coordinates, turn,
    scale and shift included: a squashed ball turned and moved in front of the model
    hides exactly what it covers in the scene."""
    ev, other = ball(), ball()
    eye = np.array([0.0, -10.0, 0.0])
    Rz = np.array([[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])         # a quarter turn about z
    S = np.diag([1.0, 2.0, 0.4])                       # long along its own y, flat along its z
    place = np.eye(4)                                  # the other's coordinates -> the scene (= the model's)
    place[:3, :3], place[:3, 3] = Rz @ S, [0.0, -3.0, 0.0]
    sight = V.Sight(ev, ((other, np.linalg.inv(place)),))
    r = -float(V.project(ev, np.array([[0.0, -0.5, 0.0]]), 30)[0][0, 1])
    # in the scene the other is wide along x (its y, turned) and flat along z: it hides the
    # model's front middle and the front beside it along x, not above it
    P = np.array([[0.0, -r, 0.0], [0.3, -np.sqrt(r * r - 0.09), 0.0], [0.0, -np.sqrt(r * r - 0.09), 0.3]])
    np.testing.assert_array_equal(V.visible(sight, P, eye), [False, False, True])
    np.testing.assert_array_equal(V.visible(ev, P, eye), [True, True, True])


def test_a_gap_another_solid_makes_close_by_is_a_gap():
    """A tiny ball just in front of one point of a line hides that point, hit as close
    as a graze would be: the line is split there (only the line's own surface grazes)."""
    ev = ball()
    r = -float(V.project(ev, np.array([[0.0, -0.5, 0.0]]), 30)[0][0, 1])
    t = np.linspace(-0.5, 0.5, 11)
    line = np.stack([r * np.sin(t), -r * np.cos(t), 0 * t], axis=1)
    eye = np.array([0.0, -10.0, 0.0])
    u = (eye - line[5]) / np.linalg.norm(eye - line[5])
    speck = ball(0.02)
    grain = -float(V.project(speck, np.array([[0.0, -0.01, 0.0]]), 30)[0][0, 1])
    at = line[5] + (V.march_step(ev) + grain + 0.5 * V.march_step(ev)) * u        # hit within GRAZE steps
    place = np.eye(4)
    place[:3, 3] = -at                                                              # the model's -> the speck's
    sight = V.Sight(ev, ((speck, place),))
    d = V.hits_each(sight, line, eye, line / r)
    assert np.isinf(d[0]).all() and np.isfinite(d[1, 5]) and d[1, 5] <= V.GRAZE * V.march_step(ev)
    assert np.isinf(np.delete(d[1], 5)).all()
    assert [run[:2] for run in V.split_visible(sight, line, eye, line / r)] == [(0, 5), (6, 11)]


def test_stroke_set_from_outlines():
    o = Outline("silhouette", np.zeros((3, 3)), np.ones((3, 3)), True)
    s = StrokeSet.from_outlines([o, Outline("crease", np.zeros((2, 3)), np.ones((2, 3)), False)], 0.01)
    assert s.count("Silhouette") == 1 and s.count("Crease") == 1 and s.count() == 2
    st = s.layers["Silhouette"][0]
    assert st.cyclic and np.all(st.radius == 0.01) and np.all(st.opacity == 1.0)


def test_only_samples_inside_the_surface_box_are_evaluated():
    """A ray is marched from its point to where it leaves the surface's box: the samples
    a batch would take past that end are not evaluated (and the verdicts are those of
    marching every ray to its end)."""
    from blobtree_ink.blackboard.polygonise import surface_box
    ev = two_balls()
    lo, hi = surface_box(ev)
    seen = []

    class Counting:
        scale, iso, memo, bounds = ev.scale, ev.iso, ev.memo, ev.bounds

        def field(self, P):
            seen.append(np.array(P))
            return ev.field(P)

    rng = np.random.default_rng(4)
    d = rng.normal(size=(300, 3))
    P = 0.4543 * d / np.linalg.norm(d, axis=1)[:, None] + np.where(rng.random((300, 1)) < 0.5, 0.0, [[0, 3, 0]])
    eye = np.array([0.5, -10.0, 0.3])
    v = visible(Counting(), P, eye, normals=d / np.linalg.norm(d, axis=1)[:, None])
    S = np.concatenate(seen)
    pad = 1e-9 * ev.scale
    assert len(S) and np.all((S >= lo - pad) & (S <= hi + pad))
    np.testing.assert_array_equal(v, [visible(ev, p[None], eye, normals=n[None] / np.linalg.norm(n))[0]
                                      for p, n in zip(P, d)])
    assert 0 < v.sum() < len(v)


def test_every_outline_point_beside_a_sharp_wedge_is_on_the_surface():
    """A rounded box minus a rod, seen from views where its silhouettes and creases go
    behind the surface beside the hollow's sharp rim (where Newton stalls between the two
    sheets): every point of every outline layer lies on the surface, the visible runs'
    ends too (|f - iso| / |grad f| within 1e-6 of the model's size), from scratch and on
    a frame going on from the last."""
    from blobtree_ink import pipeline as PL
    from blobtree_ink.agents import Settings
    from blobtree_ink.blackboard.view import View
    from blobtree_ink.strokes import style as ST
    ev = M.Evaluator(M.from_dict({"format": "blobtree-1", "root": {"type": "difference", "children": [
        {"type": "box", "center": [0, 0, 0], "half_size": [1.0, 0.6, 0.4], "radius": 0.3},
        {"type": "segment", "a": [-0.3, -1.4, 0.2], "b": [0.3, 1.4, 0.5], "radius": 0.35}]}}))
    c, r = PL.bounds(ev)
    previous, ends = None, 0
    for az, el in ((0, 10), (180, -30), (315, 10), (320, 12)):
        eye = PL.three_quarter_eye(c, r, az, el)
        job = PL.Job(ev, View(eye=eye), tuple(PL.default_light(c, eye)), ST.style("outlines"),
                     (PL.Request("OUTLINES"),), 0, Settings(resolution=12, kinds=("silhouette", "crease")))
        ill = PL.Illustration(job, previous=previous if az == 320 else None, remember=True)
        strokes = [s for layer in ill.run().strokes.layers.values() for s in layer]
        previous = ill.continuation()
        assert strokes
        P = np.concatenate([s.points for s in strokes])
        f, g = ev.field_grad(P)
        off = np.abs(f - ev.iso) / np.linalg.norm(g, axis=1)
        assert off.max() <= 1e-6 * ev.scale, (az, el, off.max() / ev.scale)
        ends += sum(not s.cyclic for s in strokes)
    assert ends > 0                                      # (lines that end where they go behind)


class _StallingBall:
    """A unit ball's field, 1 - |p|^2 (iso 0), whose gradient is lost past x = ``stall``:
    Newton cannot move a point there (as beside a sharp wedge, where it stalls)."""
    iso = 0.0

    def __init__(self, stall):
        self.stall = stall

    def field_grad(self, P):
        P = np.asarray(P, float)
        return 1.0 - (P * P).sum(axis=1), np.where(P[:, :1] > self.stall, 0.0, -2.0 * P)


def test_a_run_end_that_cannot_reach_the_surface_moves_back_along_its_step():
    """An end's point on the chord of a step that Newton cannot put onto the surface
    moves back towards the visible point, halving its share, until one reaches it (on
    the surface); where none does, the run ends at the visible point itself."""
    A, B = np.array([[0.0, 0.0, 1.0]]), np.array([[np.sin(1.0), 0.0, np.cos(1.0)]])   # on the ball, 1 rad apart
    X, s = V._onto_chord(_StallingBall(0.55), A, B, [0.9])       # x = 0.76 stalls, x = 0.38 (0.45) does not
    assert s[0] == 0.45 and abs(np.linalg.norm(X[0]) - 1.0) < 1e-12
    X, s = V._onto_chord(_StallingBall(0.01), A, B, [0.9])       # every halving stalls: the visible point
    assert s[0] == 0.0 and np.array_equal(X[0], A[0])
    X, s = V._onto_chord(_StallingBall(2.0), np.vstack([A, A]), np.vstack([B, B]), [0.9, 0.0])   # a share of 0 stays
    assert list(s) == [0.9, 0.0] and abs(np.linalg.norm(X[0]) - 1.0) < 1e-12 and np.array_equal(X[1], A[0])
