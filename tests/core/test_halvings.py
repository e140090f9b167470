"""A silhouette trace step that fails is retried with its step halved (agents.traces):
with at most FEW tasks tracing, every halving is tried in the same batch and the task
goes on with the longest that holds, where it would get to after retrying in later
iterations; with more, one halving an iteration."""
import numpy as np

from blobtree_ink.agents import Session, Settings
from blobtree_ink.agents import traces as TS
from blobtree_ink.agents.tracer import trace_step
from blobtree_ink.blackboard.board import KIND_ID
from blobtree_ink.blackboard.view import View

SIL = KIND_ID["silhouette"]


def alone(s, r, h):
    """Task r's trace step with step h, computed for it alone."""
    tk = s.traces.table
    row = slice(r, r + 1)
    return trace_step(s.surface, tk.kind[row], tk.p[row], tk.t[row], tk.ref[row], np.array([h]), s.tol,
                      s.settings.crease_angle, tk.last_n[row], tk.pins[row], (tk.team_a[row], tk.team_b[row]),
                      np.array([TS.halvable(h, tk.base[r])]))


def halvings(s, r):
    """The steps task r would try after its step fails: halved while longer than
    SHORTEST of its full step, then once more."""
    tk = s.traces.table
    h, out = tk.h[r], [tk.h[r]]
    while TS.halvable(h, tk.base[r]):
        h *= 0.5
        out.append(h)
    return out


def a_failing_task(load_example, holds):
    """A heart session stopped where a silhouette task fails its step and (``holds``) one
    of its halvings holds, or none does: the session, the task, and the step that holds
    (None)."""
    s = Session(load_example("heart"), View(eye=np.array([4.0, -6.0, 3.0])), Settings(resolution=20))
    s.request("OUTLINES")
    while not s.done:
        tk = s.traces.table
        for r in np.flatnonzero(tk.kind[:len(tk)] == SIL):
            steps = halvings(s, r)
            if len(steps) < 2 or alone(s, r, steps[0]).ok[0]:
                continue
            good = [h for h in steps[1:] if alone(s, r, h).ok[0]]
            if bool(good) == holds:
                return s, r, (good[0] if good else None)
        s.step()
    raise AssertionError("no such task in the whole session")


def only(s, r):
    """Task r the session's only one (at most FEW)."""
    keep = np.zeros(len(s.traces.table), bool)
    keep[r] = True
    s.traces.table.keep(keep)


def test_a_few_tasks_try_every_halving_of_a_failed_step_at_once(load_example):
    s, r, h = a_failing_task(load_example, holds=True)
    want = alone(s, r, h)
    only(s, r)
    tk = s.traces.table
    st, retry = s.traces._trace_step()
    assert st.ok[0] and tk.h[0] == h and not retry[0]
    np.testing.assert_array_equal(st.X, want.X)
    np.testing.assert_array_equal(st.n, want.n)
    # the step that holds is the point the task keeps, and its step grows from there
    before = s.traces.paths.of(tk.serial)[0][0]
    s.traces.step()
    assert len(tk) == 1                                   # this task goes on (no outline is near)
    after = s.traces.paths.of(tk.serial)[0][0]
    assert len(after) == len(before) + 1 and tk.h[0] == min(tk.base[0], 1.5 * h)


def test_a_task_none_of_whose_halvings_holds_ends_at_once(load_example):
    s, r, _ = a_failing_task(load_example, holds=False)
    only(s, r)
    tk = s.traces.table
    st, retry = s.traces._trace_step()
    assert not st.ok[0] and not retry[0]
    s.traces.step()
    assert len(s.traces.table) == 0                       # lost: not retried in the next iteration


def test_many_tasks_halve_one_step_an_iteration(load_example, monkeypatch):
    monkeypatch.setattr(TS, "FEW", 0)
    s, r, h = a_failing_task(load_example, holds=True)
    only(s, r)
    tk = s.traces.table
    first = tk.h[0]
    st, retry = s.traces._trace_step()
    assert not st.ok[0] and retry[0] and tk.h[0] == first


def test_a_crease_beside_halving_silhouettes_is_retried_as_alone(load_example, monkeypatch):
    """In a batch with silhouettes trying their halvings, a crease task's step is still
    one a failure of which is retried with half the step (not bracketed at once), as in
    a step of its own: its row's retry flag is its own."""
    seen = []

    def spy(surface, kinds, *args):
        tk = s.traces.table
        if len(kinds) > len(tk) and (tk.kind[:len(tk)] == KIND_ID["crease"]).any():
            own = TS.halvable(tk.h, tk.base)[tk.kind[:len(tk)] == KIND_ID["crease"]]
            seen.append((args[-1][kinds == KIND_ID["crease"]], own))
        return trace_step(surface, kinds, *args)
    monkeypatch.setattr(TS, "trace_step", spy)
    s = Session(load_example("jug"), View(eye=np.array([4.0, -6.0, 3.0])), Settings(resolution=16))
    s.request("OUTLINES")
    s.run()
    assert seen and all(np.array_equal(got, own) for got, own in seen) and any(own.any() for _, own in seen)


def a_trace_near_its_seed(load_example, reach):
    """A heart session's only silhouette task, tracing forwards with four points or more,
    its seed moved just behind it (its next, short step lands within CLOSE steps of it), and
    ``reach``: how far from the seed it has been."""
    s = Session(load_example("heart"), View(eye=np.array([4.0, -6.0, 3.0])), Settings(resolution=20))
    s.request("OUTLINES")
    while not s.done:
        tk = s.traces.table
        rows = np.flatnonzero((tk.kind[:len(tk)] == SIL) & tk.fwd[:len(tk)] & (tk.nf[:len(tk)] >= 4))
        if len(rows):
            r = int(rows[0])
            only(s, r)
            tk = s.traces.table
            tk.h[0] = 0.25 * tk.base[0]                    # a step that holds (as it did) ...
            tk.start[0] = tk.p[0] - 0.1 * tk.base[0] * tk.t[0]     # ... lands within CLOSE steps of the seed
            tk.reach[0] = reach * tk.base[0]
            return s
        s.step()
    raise AssertionError("no such task in the whole session")


def test_a_trace_back_near_its_seed_closes_only_once_it_has_been_away(load_example):
    """A trace that comes back within CLOSE steps of its seed closes its outline only
    once it has been AWAY times as far from it: one crawling on halved steps near its
    seed (at a tight turn) goes on."""
    s = a_trace_near_its_seed(load_example, reach=0.3)
    serial = int(s.traces.table.serial[0])
    s.traces.step()
    assert len(s.traces.table) == 1 and int(s.traces.table.serial[0]) == serial      # still tracing
    s = a_trace_near_its_seed(load_example, reach=TS.AWAY * TS.CLOSE * 1.01)
    done = len(s.traces.done)
    s.traces.step()
    assert len(s.traces.table) == 0 and len(s.traces.done) == done + 1 and s.traces.done[-1].closed
