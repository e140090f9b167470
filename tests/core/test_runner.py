"""The worker-thread runner the modal operator uses: same result as stepping in the
caller, snapshots while it runs, stop keeps what was made, errors reach the caller."""
import time

import numpy as np
import pytest

from blobtree_ink import model as M
from blobtree_ink.agents import Session, Settings
from blobtree_ink.agents.runner import Runner
from blobtree_ink.blackboard.view import View


def session(load_example, name="torus", res=16):
    ev = M.Evaluator(load_example(name))
    return Session(ev, View(eye=np.array([1.0, -4.0, 2.5])), Settings(resolution=res, seed=3))


def wait(runner, cond, limit=120.0):
    t0 = time.monotonic()
    while not cond() and time.monotonic() - t0 < limit:
        time.sleep(0.005)
    assert cond(), "the runner did not get there in time"


def test_the_threaded_run_equals_the_plain_run(load_example):
    plain = session(load_example)
    plain.request("OUTLINES")
    plain.run()
    s = session(load_example)
    s.request("OUTLINES")
    seen = []
    r = Runner(s, finalize=lambda: "finished strokes").start()
    wait(r, lambda: seen.append(r.snapshot().version) or r.finished)
    r.check()
    snap = r.snapshot()
    assert snap.final == "finished strokes" and snap.progress["tasks_left"] == 0
    assert snap.progress["iterations"] == plain.iteration
    assert len(set(seen)) > 2 and seen == sorted(seen)          # snapshots came while it ran
    a, b = plain.outlines(), snap.outlines
    assert len(a) == len(b) and all(np.array_equal(x.points, y.points) for x, y in zip(a, b))


def test_stop_keeps_the_latest_snapshot_and_skips_finalize(load_example):
    s = session(load_example, "heart", 20)
    s.request("OUTLINES")
    r = Runner(s, finalize=lambda: pytest.fail("finalize after a stop")).start()
    wait(r, lambda: r.snapshot().version >= 2)
    assert r.stop(wait=30.0)
    snap = r.snapshot()
    assert snap.final is None and snap.progress["tasks_left"] > 0
    assert snap.outlines and snap.progress["iterations"] == snap.version
    # the figures are those of the snapshot's own outlines (stitched once, shared)
    assert snap.progress["outlines"] == len(snap.outlines) > 0
    assert snap.progress["outline_length"] == sum(o.length for o in snap.outlines) > 0
    assert s.progress() == s.progress(s.outlines())
    r.check()


def test_an_error_on_the_worker_reaches_the_caller(load_example):
    s = session(load_example)
    s.request("OUTLINES")

    def broken():
        raise FloatingPointError("field blew up")
    s.step = broken
    r = Runner(s).start()
    wait(r, lambda: r.finished)
    with pytest.raises(RuntimeError, match="the agents failed: FloatingPointError.*field blew up"):
        r.check()


def test_the_switch_interval_is_short_only_while_a_worker_runs(load_example):
    import sys
    before = sys.getswitchinterval()
    s = session(load_example)
    s.request("OUTLINES")
    r = Runner(s).start()
    during = sys.getswitchinterval()
    wait(r, lambda: r.finished)
    assert during <= 2e-4 < before and sys.getswitchinterval() == before
