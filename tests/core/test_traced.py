"""The traced-point table (agents/traced.py) and how new trace points cover open
seeds: an outline stops on another one or on its own far part, never on its last
steps, and neither counts points or seeds on another sheet."""
import numpy as np

from blobtree_ink.agents import Session, Settings
from blobtree_ink.blackboard.board import KIND_ID
from blobtree_ink.blackboard.view import View

from test_massris import K


def test_a_trace_stops_on_its_own_far_part_not_its_last_steps(load_example):
    """Its own points count for a trace only beyond SELF_GAP steps along it: a
    backward half that meets the forward half stops (it used to go round a small loop
    for ever)."""
    from blobtree_ink.agents.traced import SELF_GAP
    s = Session(load_example("sphere"), View(eye=(0.0, -6.0, 0.0)), Settings(resolution=8))
    p = np.array([1.0, 0.0, 0.0])
    s.traced.remember(0, p, 7, 3, np.array([1.0, 0, 0]))
    near = p + [0.1 * s.step_len, 0, 0]
    assert s.traced.near(0, near, s.step_len, 7, 3 + SELF_GAP) is None        # its last steps
    assert s.traced.near(0, near, s.step_len, 7, 3 + SELF_GAP + 1) == (7, 3)  # its far part
    assert s.traced.near(0, near, s.step_len, 7, -(SELF_GAP + 1)) == (7, 3)   # backward half
    assert s.traced.near(0, near, s.step_len, 8) == (7, 3)                    # another outline
    assert s.traced.near(1, near, s.step_len, 8) is None                      # another kind
    assert s.traced.near(0, p + [2 * s.step_len, 0, 0], s.step_len, 8) is None
    # a point with its normal: the same sheet counts, another sheet (across a crease,
    # normals apart by more than half the crease angle) does not
    half = 0.5 * s.settings.crease_angle
    turn = lambda a: np.array([np.cos(a), np.sin(a), 0.0])
    assert s.traced.near(0, near, s.step_len, 8, n=turn(0.9 * half)) == (7, 3)
    assert s.traced.near(0, near, s.step_len, 8, n=turn(1.1 * half)) is None


def test_new_trace_points_cover_open_seeds_of_their_own_sheet_only(load_example):
    """Open seeds within 0.75 voxel of a new trace point are taken as traced, unless
    their normal shows another sheet (the inner and outer silhouettes of a thin lip
    lie that close); crease seeds, which have no one normal, are covered by distance."""
    s = Session(load_example("sphere"), View(eye=(0.0, -6.0, 0.0)), Settings(resolution=8))
    s.bb.consume(np.arange(len(s.bb.feat)))               # only the seeds made here are open
    r = K
    p = np.array([r, 0.0, 0.0])                            # on the sphere, its normal +x
    q = p + [0.0, 0.0, 0.2 * s.h]
    same = s.bb.add_features(q, np.array([r * 0.999, 0.0, r * 0.045]), q, "silhouette")   # a near p: +x sheet
    other = s.bb.add_features(q, np.array([-r, 0.0, 0.0]), q, "silhouette")              # a on the -x side
    crease = s.bb.add_features(q, np.array([-r, 0.0, 0.0]), q, "crease")
    far = s.bb.add_features(p + [0.0, 0.0, 2 * s.h], p, p, "silhouette")
    s._consume_covered(np.array([KIND_ID["silhouette"], KIND_ID["crease"]]), np.array([p, p]),
                       np.array([[1.0, 0, 0], [1.0, 0, 0]]), np.full(2, s.step_len))
    f = s.bb.feat["used"]
    assert f[same[0]] and not f[other[0]] and f[crease[0]] and not f[far[0]]


def test_points_of_a_longer_stepped_outline_count_within_its_step(load_example):
    """A subdivided voxel's trace (short steps) running along an outline traced with the
    session's step meets it: that outline's points are up to half its step from the
    line, further than the short step."""
    s = Session(load_example("sphere"), View(eye=(0.0, -6.0, 0.0)), Settings(resolution=8))
    p = np.array([1.0, 0.0, 0.0])
    s.traced.remember(0, p, 7, 3, np.array([1.0, 0, 0]))                 # the session's step
    s.traced.remember(0, p + [0, 0, 0.2], 9, 3, np.array([1.0, 0, 0]), 0.1 * s.step_len)
    fine = 0.1 * s.step_len
    assert s.traced.near(0, p + [0, 0.5 * s.step_len, 0], fine, 8) == (7, 3)
    assert s.traced.near(0, p + [0, 0.7 * s.step_len, 0], fine, 8) is None
    # a short-stepped outline's points count only within the query's radius
    assert s.traced.near(0, p + [0, 0, 0.2 + 0.5 * fine], fine, 8) == (9, 3)
    assert s.traced.near(0, p + [0, 0, 0.2 + 2 * fine], fine, 8) is None
