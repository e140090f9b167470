"""The worker-thread runner the modal operator drives: the same result as stepping in
the caller, results published while it runs, the initialisation on the worker, stop
keeps what was made (with the outlines' hidden lines removed), cancel and errors reach
the caller, join is bounded, the switch interval always comes back. The worker is held
between steps by the runner's test hook, never raced against a clock."""
import dataclasses
import sys
import threading

import numpy as np
import pytest

from blobtree_ink import pipeline as PL
from blobtree_ink.pipeline import runner as RN
from helpers import job_for, same_strokes


@pytest.fixture(autouse=True)
def released():
    yield
    RN.HOLD.release()


def test_the_threaded_run_equals_the_plain_run(load_example):
    plain = PL.Illustration(job_for(load_example, "torus", "hatched")).run()
    RN.HOLD.arm(3)                                               # held after its third step
    r = RN.Runner(PL.Illustration(job_for(load_example, "torus", "hatched"))).start()
    assert RN.HOLD.reached.wait(120)
    mid = r.latest()                                             # figures come while it runs
    assert not mid.done and 0 < mid.progress.fraction < 1
    RN.HOLD.release()
    r.join(120)
    r.check()
    got = r.latest()
    assert got.done and not got.stopped and got.progress.fraction == 1.0
    assert got.progress.fraction > mid.progress.fraction
    same_strokes(plain.strokes, got.strokes)
    assert got.strokes.count("Hatching") > 10 and got.strokes.count("Silhouette") > 0


def test_the_initialisation_runs_on_the_worker(load_example):
    ill = PL.Illustration(job_for(load_example, "heart", "outlines"))
    assert ill.session is None and ill.stage == "init"          # nothing computed in the caller
    RN.HOLD.arm(1)
    r = RN.Runner(ill).start()
    assert RN.HOLD.reached.wait(120)
    assert ill.session is not None and ill.stage == "sampling"
    assert r.latest().progress.stage == "sampling" and 0 < r.latest().progress.fraction < 0.5
    RN.HOLD.release()
    r.join(120)
    assert r.latest().done


def test_the_hook_holds_the_worker_it_was_armed_for(load_example):
    """Armed for the second worker started (a bake starts one per frame), the hook lets
    the first run to its end and holds the second."""
    RN.HOLD.arm(1, run=2)
    first = RN.Runner(PL.Illustration(job_for(load_example, "sphere", "outlines", res=8))).start()
    first.join(120)
    assert first.latest().done and not RN.HOLD.reached.is_set()
    second = RN.Runner(PL.Illustration(job_for(load_example, "sphere", "outlines", res=8))).start()
    assert RN.HOLD.reached.wait(120)
    assert second.latest().progress.stage == "sampling"
    RN.HOLD.release()
    second.join(120)
    assert second.latest().done


def test_stop_keeps_the_outlines_found_so_far_with_their_hidden_lines_removed(load_example):
    full = PL.Illustration(job_for(load_example, "heart", "hatched")).run()
    RN.HOLD.arm(3)                                  # init and two system iterations
    ill = PL.Illustration(job_for(load_example, "heart", "hatched"))
    r = RN.Runner(ill).start()
    assert RN.HOLD.reached.wait(120)
    held = r.latest()
    assert held.progress.stage == "sampling" and held.progress.iterations == 2
    r.stop()
    r.join()
    r.check()
    got = r.latest()
    assert got.stopped and not got.done and got.progress.iterations == 2
    assert got.strokes.count("Silhouette") > 0 and got.strokes.count("Hatching") == 0   # no layer after a stop
    assert ill.outline_set is not None                  # the outline stage ran on what was traced
    # the visible outlines only: no more points than the raw ones held, and fewer than a full run's
    pts = lambda s, layer: sum(len(x.points) for x in s.layers[layer])      # noqa: E731
    assert pts(got.strokes, "Silhouette") <= pts(held.strokes, "Silhouette")
    assert pts(got.strokes, "Silhouette") < pts(full.strokes, "Silhouette")


def test_stop_during_a_layer_keeps_the_layers_before_it(load_example):
    ill = PL.Illustration(job_for(load_example, "pear", "hatched"))
    k = ill.stages.index("cross-hatching")
    while ill.stage != "cross-hatching":            # the steps in the caller up to that layer
        ill.step()
    hatched = ill.result().strokes.count("Hatching")
    ill.stop()
    assert not ill.step()
    got = ill.result()
    assert got.stopped and got.strokes.count("Hatching") == hatched > 0 and 0 < k


def test_stop_in_the_middle_of_a_layer_keeps_its_finished_parts(load_example, monkeypatch):
    """A stroke layer is drawn in parts (chunks of its hatching map's lines), one per
    step: a stop keeps the parts drawn so far, and the full run draws the same parts and
    more."""
    from blobtree_ink.pipeline import layers as LY
    monkeypatch.setattr(LY, "CHUNK_LINES", 20)
    full = PL.Illustration(job_for(load_example, "pear", "hatched", requests=[PL.Request("PLACE_STROKES")])).run()
    ill = PL.Illustration(job_for(load_example, "pear", "hatched", requests=[PL.Request("PLACE_STROKES")]))
    while not (ill.stage == "hatching" and ill._part == 3):
        assert ill.step()
    made = ill.result()
    assert 0.2 < made.progress.fraction < 0.9
    ill.stop()
    assert not ill.step()
    got = ill.result()
    part, whole = got.strokes.layers["Hatching"], full.strokes.layers["Hatching"]
    assert 0 < len(part) < len(whole) and got.stopped and got.owned == ("Hatching",)
    for x, y in zip(part, whole):                 # the same strokes as the full run's first ones
        assert np.array_equal(x.points, y.points)


def test_cancel_ends_without_more_work(load_example):
    RN.HOLD.arm(2)
    ill = PL.Illustration(job_for(load_example, "heart", "outlines"))
    r = RN.Runner(ill).start()
    assert RN.HOLD.reached.wait(120)
    r.cancel()
    r.join()
    assert r.steps == 2 and ill.outline_set is None and r.latest().progress.stage == "sampling"


def test_an_error_on_the_worker_reaches_the_caller(load_example):
    ill = PL.Illustration(job_for(load_example, "torus", "outlines"))

    def broken():
        raise FloatingPointError("field blew up")
    ill.step = broken
    before = sys.getswitchinterval()
    r = RN.Runner(ill).start()
    r.join()
    assert sys.getswitchinterval() == before
    with pytest.raises(RN.RunnerError, match="the illustration failed: FloatingPointError.*field blew up"):
        r.check()


def test_join_is_bounded_and_says_why(load_example):
    ill = PL.Illustration(job_for(load_example, "torus", "outlines"))
    gate, entered = threading.Event(), threading.Event()

    def stuck():
        entered.set()
        gate.wait(60)
        return False
    ill.step = stuck
    r = RN.Runner(ill).start()
    assert entered.wait(30)
    r.cancel()
    with pytest.raises(RN.RunnerError, match=r"did not end within 0.1 s .*'init' stage"):
        r.join(0.1)
    gate.set()
    r.join()
    assert r.finished


def test_the_switch_interval_is_short_only_while_a_worker_runs(load_example):
    before = sys.getswitchinterval()
    RN.HOLD.arm(1)
    r = RN.Runner(PL.Illustration(job_for(load_example, "torus", "outlines"))).start()
    assert RN.HOLD.reached.wait(60)
    during = sys.getswitchinterval()
    r.cancel()
    r.join()
    assert during <= RN.SWITCH_INTERVAL < before and sys.getswitchinterval() == before


def test_the_progress_figure_counts_each_stage_by_its_share(load_example):
    """Stage by stage, the fraction is the share of the stages done (init 0.15, sampling
    0.5, the visible outlines 0.1 of an outlines job), and within the sampling it grows."""
    ill = PL.Illustration(job_for(load_example, "heart", "outlines"))
    total = 0.15 + 0.5 + 0.1
    ill.step()
    assert ill.stage == "sampling" and ill.progress().fraction == pytest.approx(0.15 / total)
    within = []
    while ill.stage == "sampling":
        ill.step()
        within.append(ill.progress().fraction)
    assert within[-1] == pytest.approx(0.65 / total) and 0.15 / total < within[0] < within[-1]
    ill.step()
    assert ill.finished and ill.progress().fraction == pytest.approx(1.0)


def test_the_hook_holds_a_worker_in_the_middle_of_a_layer(load_example, monkeypatch):
    from blobtree_ink.pipeline import layers as LY
    monkeypatch.setattr(LY, "CHUNK_LINES", 20)
    RN.HOLD.arm(at=("hatching", 2))
    ill = PL.Illustration(job_for(load_example, "pear", "hatched", requests=[PL.Request("PLACE_STROKES")]))
    r = RN.Runner(ill).start()
    assert RN.HOLD.reached.wait(120)
    assert ill.position() == ("hatching", 2) and r.latest().strokes.count("Hatching") > 0
    r.stop()
    r.join()
    got = r.latest()
    assert got.stopped and got.owned == ("Hatching",) and ill.position()[0] == "done"


def test_a_light_inside_the_model_reaches_the_caller_in_its_own_words(load_example):
    job = job_for(load_example, "torus", "outlines")
    ill = PL.Illustration(dataclasses.replace(job, light=None, light_at=(1.0, 0.0, 0.0)))       # in the ring
    r = RN.Runner(ill).start()
    r.join()
    with pytest.raises(RN.RunnerError, match=r"the illustration failed: the light at \(1, 0, 0\) is inside the model"):
        r.check()
