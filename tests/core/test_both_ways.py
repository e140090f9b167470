"""A seed starts a task each way along its outline when agents are free for both:
the outline is traced from both ends at once, in half the iterations, and the two
halves stitch into one closed polyline."""
import numpy as np

from blobtree_ink.agents import Session, Settings
from blobtree_ink.blackboard.board import KIND_ID
from blobtree_ink.blackboard.view import View

from test_massris import K, check_on_surface, circle, coverage, model_of, polyline_samples


def one_seed_session(agents, explore_detail=False):
    """A sphere's silhouette from one seed: every other polygon-edge seed is withdrawn
    (and detail exploration is off), so that the whole circle is traced from it."""
    s = Session(model_of({"type": "point", "center": [0, 0, 0], "radius": 1.0}), View(direction=(0, 0, 1)),
                Settings(resolution=16, agents=agents, explore_detail=explore_detail))
    s.request("OUTLINES")
    ids = s._open_seeds()
    assert len(ids) > 10 and np.all(s.bb.feat["kind"][ids] == KIND_ID["silhouette"])
    s.bb.consume(ids[1:])
    return s


def one_seed_run(agents):
    s = one_seed_session(agents)
    s.run()
    assert s.done
    return s


def test_a_seed_traces_its_outline_both_ways_at_once():
    one, both = one_seed_run(agents=1), one_seed_run(agents=2)
    ref = circle(np.zeros(3), np.array([0, 0, 1.0]), K)
    for s in (one, both):
        (o,) = s.outlines()
        assert o.kind == "silhouette" and o.closed
        check_on_surface(s, o)
        worst, covered = coverage(polyline_samples(o), ref, 0.01 * K)
        assert covered == 1.0, (worst, covered)
    # the circle takes about 2 pi r / step steps: one task walks them all (then a last
    # step finds its start), two tasks half each
    steps = 2 * np.pi * K / one.step_len
    assert abs(one.iteration - steps) < 4
    assert abs(both.iteration - steps / 2) < 4


def test_the_detail_phase_starts_while_the_last_few_traces_run():
    """Once the edge seeds are taken and at most DETAIL_AFTER traces are left, the
    detail phase (silhouettes beside traced ones, flagged voxels explored) starts
    beside them instead of after a long outline's last cheap iterations."""
    from blobtree_ink.agents.session import DETAIL_AFTER
    s = one_seed_session(agents=100, explore_detail=True)
    s.step()
    assert 0 < len(s.traces) <= DETAIL_AFTER and s._detail is not None
    s.run()
    assert s.done
    (o,) = [o for o in s.outlines() if o.kind == "silhouette"]
    assert o.closed
    worst, covered = coverage(polyline_samples(o), circle(np.zeros(3), np.array([0, 0, 1.0]), K), 0.01 * K)
    assert covered == 1.0, (worst, covered)
