"""The traced-point table (agents/traced.py) and how new trace points cover open
seeds: an outline stops on another one or on its own far part, never on its last
steps, and neither counts points or seeds on another sheet."""
import numpy as np

from blobtree_ink.agents import Session, Settings
from blobtree_ink.agents.traced import consume_crossed
from blobtree_ink.blackboard.board import KIND_ID
from blobtree_ink.blackboard.cells import pairs_within
from blobtree_ink.blackboard.view import View

from test_massris import K, check_on_surface, model_of, run

SPHERE = {"type": "point", "center": [0, 0, 0], "radius": 1.0}


def test_a_trace_stops_on_its_own_far_part_not_its_last_steps(load_example):
    """Its own points count for a trace only beyond SELF_GAP steps along it: a
    backward half that meets the forward half stops (rather than going round a small
    loop for ever)."""
    from blobtree_ink.agents.traced import SELF_GAP
    s = Session(load_example("sphere"), View(eye=(0.0, -6.0, 0.0)), Settings(resolution=8))
    p = np.array([1.0, 0.0, 0.0])
    s.traces.traced.remember(0, p, 7, 3, np.array([1.0, 0, 0]))
    near = p + [0.1 * s.step_len, 0, 0]
    assert s.traces.traced.near(0, near, s.step_len, 7, 3 + SELF_GAP) is None        # its last steps
    assert s.traces.traced.near(0, near, s.step_len, 7, 3 + SELF_GAP + 1) == (7, 3)  # its far part
    assert s.traces.traced.near(0, near, s.step_len, 7, -(SELF_GAP + 1)) == (7, 3)   # backward half
    assert s.traces.traced.near(0, near, s.step_len, 8) == (7, 3)                    # another outline
    assert s.traces.traced.near(1, near, s.step_len, 8) is None                      # another kind
    assert s.traces.traced.near(0, p + [2 * s.step_len, 0, 0], s.step_len, 8) is None
    # a point with its normal: the same sheet counts, another sheet (across a crease,
    # normals apart by more than half the crease angle) does not
    half = 0.5 * s.settings.crease_angle
    turn = lambda a: np.array([np.cos(a), np.sin(a), 0.0])
    assert s.traces.traced.near(0, near, s.step_len, 8, n=turn(0.9 * half)) == (7, 3)
    assert s.traces.traced.near(0, near, s.step_len, 8, n=turn(1.1 * half)) is None


def test_new_trace_points_cover_the_seeds_whose_bracket_they_cross(load_example):
    """An open seed is taken as traced when its bracket crosses the new trace point's
    outline (ends either side of the plane through X across W) within 0.75 voxel of
    X, and (silhouettes) the normal where it crosses agrees (a wide bracket's ends turn
    further from it on a curved sheet). A seed of a parallel outline half a voxel
    beside it (both ends on one side) stays open, though its position is that close;
    so does a crossing seed further along the outline, and a silhouette seed whose
    normal shows another sheet (the inner and outer silhouettes of a thin lip). Crease
    seeds, which have no one normal, are covered by crossing alone."""
    s = Session(load_example("sphere"), View(eye=(0.0, -6.0, 0.0)), Settings(resolution=8))
    s.bb.consume(np.arange(len(s.bb.feat)))               # only the seeds made here are open
    h = s.h
    X = np.array([K, 0.0, 0.0])                            # on the sphere, its normal +x
    T, W = np.array([0.0, 0.0, 1.0]), np.array([0.0, -1.0, 0.0])

    def seed(kind, a, b):
        a, b = np.asarray(a, float), np.asarray(b, float)
        return s.bb.add_features(0.5 * (a + b), a[None], b[None], kind)[0]
    across = seed("silhouette", X + 0.3 * h * W + 0.2 * h * T, X - 0.3 * h * W + 0.2 * h * T)
    end_on = seed("silhouette", X + 0.1 * h * T, X - 0.4 * h * W + 0.1 * h * T)   # an end on the outline
    parallel = seed("silhouette", X + 0.35 * h * W, X + 0.75 * h * W)
    further = seed("silhouette", X + 0.3 * h * W + 1.2 * h * T, X - 0.3 * h * W + 1.2 * h * T)
    cr_across = seed("crease", X + 0.3 * h * W - 0.2 * h * T, X - 0.3 * h * W - 0.2 * h * T)
    wide = seed("silhouette", X + 1.2 * h * W - 0.3 * h * T, X - 1.2 * h * W - 0.3 * h * T)
    cos = np.cos(0.5 * s.settings.crease_angle)
    _, g = s.surface.field_grad(np.array([X + 1.2 * h * W - 0.3 * h * T, X - 1.2 * h * W - 0.3 * h * T]))
    assert (s.surface.normals(g) @ [1.0, 0, 0] < cos).all()          # both ends on a turned part of the sheet
    cr_parallel = seed("crease", X - 0.35 * h * W, X - 0.75 * h * W)
    sil, cre = KIND_ID["silhouette"], KIND_ID["crease"]
    consume_crossed(s.bb, s.surface, s.settings.crease_angle, np.array([sil, cre]), np.array([X, X]),
                    np.array([[1.0, 0, 0], [1.0, 0, 0]]),
                       np.array([W, W]), np.full(2, s.step_len))
    used = s.bb.feat["used"]
    assert used[across] and used[end_on] and used[cr_across] and used[wide]
    assert not used[parallel] and not used[further] and not used[cr_parallel]
    # another sheet: the same crossing bracket, the trace's normal facing the other way
    other = seed("silhouette", X + 0.3 * h * W + 0.2 * h * T, X - 0.3 * h * W + 0.2 * h * T)
    cr_other = seed("crease", X + 0.3 * h * W + 0.2 * h * T, X - 0.3 * h * W + 0.2 * h * T)
    consume_crossed(s.bb, s.surface, s.settings.crease_angle, np.array([sil, cre]), np.array([X, X]),
                    np.array([[-1.0, 0, 0], [-1.0, 0, 0]]),
                       np.array([W, W]), np.full(2, s.step_len))
    used = s.bb.feat["used"]
    assert not used[other] and used[cr_other]


def test_points_of_a_longer_stepped_outline_count_within_its_step(load_example):
    """A subdivided voxel's trace (short steps) running along an outline traced with the
    session's step meets it: that outline's points are up to half its step from the
    line, further than the short step."""
    s = Session(load_example("sphere"), View(eye=(0.0, -6.0, 0.0)), Settings(resolution=8))
    p = np.array([1.0, 0.0, 0.0])
    s.traces.traced.remember(0, p, 7, 3, np.array([1.0, 0, 0]))                 # the session's step
    s.traces.traced.remember(0, p + [0, 0, 0.2], 9, 3, np.array([1.0, 0, 0]), 0.1 * s.step_len)
    fine = 0.1 * s.step_len
    assert s.traces.traced.near(0, p + [0, 0.5 * s.step_len, 0], fine, 8) == (7, 3)
    assert s.traces.traced.near(0, p + [0, 0.7 * s.step_len, 0], fine, 8) is None
    # a short-stepped outline's points count only within the query's radius
    assert s.traces.traced.near(0, p + [0, 0, 0.2 + 0.5 * fine], fine, 8) == (9, 3)
    assert s.traces.traced.near(0, p + [0, 0, 0.2 + 2 * fine], fine, 8) is None


def test_pairs_within_are_those_of_every_distance():
    """The hashed pair search gives exactly the pairs closer than r that comparing every
    distance gives (points on cell boundaries and duplicates included), and open_near
    keeps each feature's nearest point, the first on ties."""
    rng = np.random.default_rng(3)
    r = 0.1
    A = np.round(rng.random((300, 3)), 1)                  # many points on cell boundaries, some equal
    B = np.concatenate([np.round(rng.random((200, 3)), 1), A[:20] + [r, 0, 0], A[20:30]])
    i, j = pairs_within(A, B, r)
    d2 = ((A[:, None] - B[None]) ** 2).sum(-1)
    want_i, want_j = np.nonzero(d2 < r * r)
    assert len(want_i) > 30
    got = set(zip(i.tolist(), j.tolist()))
    assert got == set(zip(want_i.tolist(), want_j.tolist())) and len(got) == len(i)
    assert np.all(np.diff(i) >= 0)
    # far apart in space and close in one corner: the cells grow, the pairs do not change
    C = np.concatenate([A, [[1e7, 0, 0]]])
    i2, j2 = pairs_within(C, B, r)
    assert set(zip(i2.tolist(), j2.tolist())) == got
    s = Session(model_of(SPHERE), View(eye=(0, -4.0, 0)), Settings(resolution=8))
    s.bb.consume(s.bb.open_features())
    ids = s.bb.add_features(A, A, A, "silhouette")
    got_ids, which = s.bb.open_near(B, "silhouette", r)
    has = np.flatnonzero((d2 < r * r).any(axis=1))
    np.testing.assert_array_equal(got_ids, ids[has])
    np.testing.assert_array_equal(which, d2[has].argmin(axis=1))     # argmin: the first of equal ones
    assert len(np.unique(d2[has].min(axis=1))) < len(has)             # some ties among them


def _first_near(step_len, cos_sheet, entries, kind, p, radius, own, arc, n):
    """The rule of TracedPoints.near written out plainly: of the points (in the order
    they came) of this kind in the 27 cells of one step around p, taken cell by cell
    (nested loops over dx, dy, dz), the first that counts."""
    from itertools import product
    from blobtree_ink.agents.traced import SELF_GAP
    c = np.floor(p / step_len).astype(int)
    for off in product((-1, 0, 1), repeat=3):
        for k, q, tid, qa, qn, qs in entries:
            if k != kind or tuple(np.floor(q / step_len).astype(int) - c) != off:
                continue
            if own is not None and tid == own and (arc is None or abs(arc - qa) <= SELF_GAP):
                continue
            if n is not None and kind != KIND_ID["crease"] and qn @ n < cos_sheet:
                continue
            r = max(radius, 0.6 * qs)
            if ((q - p) ** 2).sum() < r * r:
                return (tid, qa)
    return None


def test_a_loop_of_questions_sees_the_points_kept_before_each_as_if_remembered_one_by_one():
    """traced.Loops answers a loop's questions in one batch: each sees the table as of
    the loop's start and the new points the loop kept before it (not those it passed
    over, nor later ones), the first hit in the order of the plain rule (cells in
    order; within a cell the earliest point, the table's before the loop's)."""
    from blobtree_ink.agents.traced import NO_ARC, NO_OWN, TracedPoints
    rng = np.random.default_rng(7)
    ids = np.array([0, 1, 2, 3, 4, 5, -1000, -1001])      # traced outlines' and kept ones' (agents.traces.KEPT)
    step = 0.1
    tp = TracedPoints(step, np.radians(35.0))
    entries = []
    for _ in range(150):                    # the table before the loop, one by one
        k, q = int(rng.integers(0, 2)), rng.random(3) * 0.5
        nq = rng.normal(size=3)
        nq /= np.linalg.norm(nq)
        tid, qa, qs = int(rng.choice(ids)), int(rng.integers(-20, 20)), float(rng.choice([step, 0.2 * step]))
        tp.remember(k, q, tid, qa, nq, qs)
        entries.append((k, q, tid, qa, nq, qs))
    m = 120
    kinds = rng.integers(0, 2, m)
    P = rng.random((m, 3)) * 0.5
    N = rng.normal(size=(m, 3))
    N /= np.linalg.norm(N, axis=1, keepdims=True)
    N[::7] = np.nan                                      # some without a normal
    radius = rng.choice([step, 0.3 * step], m)
    own = np.where(rng.random(m) < 0.5, rng.choice(ids, m), NO_OWN)
    tids = np.where(own == NO_OWN, 0, own)                # the loop's new points' outlines
    arc = np.where(rng.random(m) < 0.7, rng.integers(-20, 20, m), NO_ARC)
    steps = rng.choice([step, 0.2 * step], m)
    loop = tp.loop(kinds, P, radius, own, arc, N, new=(kinds, P, N, tids, arc.clip(-20), steps),
                   upto=np.arange(m))
    hits = 0
    for i in range(m):
        want = _first_near(step, tp.cos_sheet, entries, kinds[i], P[i], radius[i], None if own[i] == NO_OWN else own[i],
                           None if arc[i] == NO_ARC else arc[i], None if np.isnan(N[i, 0]) else N[i])
        assert loop.hit(i) == want
        hits += want is not None
        if want is None and rng.random() < 0.8:                 # the loop keeps most of the rest
            loop.keep(i)
            entries.append((kinds[i], P[i], tids[i], max(arc[i], -20), N[i], steps[i]))
    assert 20 < hits < m - 20
    loop.commit()                                             # the kept points join the table
    for i in range(0, m, 3):
        assert tp.near(kinds[i], P[i] + 0.01, step, None) == _first_near(
            step, tp.cos_sheet, entries, kinds[i], P[i] + 0.01, step, None, None, None)


def test_a_model_far_from_the_origin_is_traced():
    """Trace points are hashed in cells counted from the blackboard's corner, not from
    0: a sphere three million units out (its cells from 0 would not pack into the
    hash's 21 bits per axis) gets its silhouette, one closed circle round it."""
    c = np.array([3e6, 0.0, 0.0])
    s = run(model_of({**SPHERE, "center": c.tolist()}), View(eye=tuple(c + [0.0, -6.0, 0.0])), resolution=16)
    out = s.outlines()
    assert len(out) == 1 and out[0].closed
    check_on_surface(s, out[0])
    ang = np.sort(np.arctan2(out[0].points[:, 2] - c[2], out[0].points[:, 0] - c[0]))
    assert np.diff(np.r_[ang, ang[0] + 2 * np.pi]).max() < 0.2           # all the way round


def test_an_outline_kept_from_the_last_frame_is_its_tasks_own(load_example):
    """Kept outlines have negative ids (agents.traces.KEPT - k): a task that goes on
    from one's end as its own is not stopped by its last steps, but is by its far part."""
    from blobtree_ink.agents.traced import SELF_GAP
    from blobtree_ink.agents.traces import KEPT
    s = Session(load_example("sphere"), View(eye=(0.0, -6.0, 0.0)), Settings(resolution=8))
    p = np.array([1.0, 0.0, 0.0])
    s.traces.traced.remember(0, p, KEPT - 2, 0, np.array([1.0, 0, 0]))
    near = p + [0.1 * s.step_len, 0, 0]
    assert s.traces.traced.near(0, near, s.step_len, KEPT - 2, -1) is None                   # its own first point
    assert s.traces.traced.near(0, near, s.step_len, KEPT - 2, SELF_GAP + 1) == (KEPT - 2, 0)   # its far part
    assert s.traces.traced.near(0, near, s.step_len, KEPT - 3, -1) == (KEPT - 2, 0)          # another kept one
    assert s.traces.traced.near(0, near, s.step_len, None) == (KEPT - 2, 0)                  # no own outline
