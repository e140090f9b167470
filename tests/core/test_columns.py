"""Agents stored as arrays (agents.columns): task columns appended in batches and
kept by selection, and the pooled points of tracing tasks in step order."""
import numpy as np
import pytest

from blobtree_ink.agents.columns import Columns, Paths

from test_both_ways import one_seed_session


def test_columns_append_broadcast_and_keep_in_order():
    c = Columns(a=((), np.int64), v=((3,), float), pins=((2, 0), np.int32))
    assert len(c) == 0 and not c
    c.append(2, a=[4, 5], v=[[1, 2, 3], [4, 5, 6]], pins=np.zeros((2, 2, 0)))
    c.append(3, a=7, v=np.arange(9.0).reshape(3, 3), pins=-2)       # one value broadcast to every row
    assert c.a.tolist() == [4, 5, 7, 7, 7] and c.v.shape == (5, 3) and c.pins.shape == (5, 2, 0)
    assert c.a.dtype == np.int64 and c.pins.dtype == np.int32
    c.keep(np.array([False, True, False, True, True]))
    assert c.a.tolist() == [5, 7, 7] and c.v[0].tolist() == [4, 5, 6] and c.v[2].tolist() == [6, 7, 8]
    c.keep([2, 0])
    assert c.a.tolist() == [7, 5] and c.v.tolist() == [[6, 7, 8], [4, 5, 6]]
    with pytest.raises(ValueError, match="exactly the columns"):
        c.append(1, a=1, v=[0, 0, 0])
    with pytest.raises(ValueError, match="exactly the columns"):
        c.append(1, a=1, v=[0, 0, 0], pins=0, extra=3)


def test_paths_give_each_tasks_points_in_step_order():
    """Points come in batches of several tasks, forwards (0, 1, ...) and backwards
    (-1, -2, ...) from the seed; a task's outline runs from its last backward point to
    its last forward one, in the order the tasks are asked for."""
    p = Paths()
    p.add([10, 11], 0, [[0, 0, 0], [5, 0, 0]], [[0, 0, 1], [0, 0, 2]])
    p.add([11, 10, 12], [-1, 1, 0], [[4, 0, 0], [1, 0, 0], [9, 9, 9]], np.ones((3, 3)))
    p.add(10, -1, [[-1, 0, 0]], [[0, 1, 0]])
    p.add([10, 11], [-2, 1], [[-2, 0, 0], [6, 0, 0]], np.zeros((2, 3)))
    out = p.of([11, 13, 10])
    assert [len(x) for x, _ in out] == [3, 0, 4]
    assert out[0][0][:, 0].tolist() == [4, 5, 6] and out[2][0][:, 0].tolist() == [-2, -1, 0, 1]
    assert out[0][1][1].tolist() == [0, 0, 2] and out[2][1][1].tolist() == [0, 1, 0]
    assert out[1][0].shape == (0, 3)
    gone = p.of([10], remove=True)
    assert gone[0][0][:, 0].tolist() == [-2, -1, 0, 1]
    assert sorted(p.task.tolist()) == [11, 11, 11, 12] and p.of([10])[0][0].shape == (0, 3)
    assert p.of([]) == []


def test_a_sessions_tracing_tasks_are_rows_of_arrays():
    """A seed with two free agents starts two tasks, one each way, as two rows: each
    with its own agent, the same outline id, paired; after a step both rows hold a new
    point on the surface, kept in the pool, and the session's outlines so far are the
    two halves."""
    s = one_seed_session(agents=2)
    s.step()
    tk = s.traces.table
    assert len(tk) == 2 and len(s.pool) == 0 and s.pool.busy == 2
    assert tk.fwd.tolist() == [True, False] and tk.paired.all() and tk.id[0] == tk.id[1]
    assert sorted(tk.agents[:, 0].tolist()) == [0, 1] and (tk.agents[:, 1] == -1).all()
    assert tk.nf.tolist() == [2, 0] and tk.nb.tolist() == [0, 1]
    f, _ = s.ev.field_grad(tk.p)
    assert np.all(np.abs(f - s.ev.iso) < 1e-9)
    pts = s.traces.paths.of(tk.serial)
    assert [len(x) for x, _ in pts] == [2, 1]
    assert np.array_equal(pts[0][0][-1], tk.p[0]) and np.array_equal(pts[1][0][-1], tk.p[1])
    assert np.array_equal(pts[0][0][0], tk.start[0])           # the seed, on the forward half
    (o,) = s.outlines(include_active=True)                       # the halves stitched
    assert len(o.points) == 3 and not o.closed


def test_paths_grow_past_their_storage_and_keep_every_point():
    """A long trace adds points one step at a time, far past the pool's first storage:
    none is lost or reordered, and removing one task keeps the others' points."""
    p = Paths()
    for i in range(300):
        p.add([1, 2], [i, -i - 1], [[i, 0, 0], [0, i, 0]], [[0, 0, i], [0, 0, -i]])
    p.add(3, np.arange(5), np.ones((5, 3)), np.ones((5, 3)))     # one batch for one task
    assert len(p) == 605
    (a, an), (b, bn) = p.of([1, 2], remove=True)
    assert a[:, 0].tolist() == list(range(300)) and an[:, 2].tolist() == list(range(300))
    assert b[:, 1].tolist() == list(range(299, -1, -1))
    assert len(p) == 5 and p.task.tolist() == [3] * 5 and p.arc.tolist() == [0, 1, 2, 3, 4]
    p.add(4, 0, [[7, 7, 7]], [[0, 0, 1]])
    (c, _), = p.of([3])
    assert c.shape == (5, 3) and p.of([4])[0][0].tolist() == [[7, 7, 7]]


def test_the_total_length_of_outlines_is_the_sum_of_their_lengths():
    from blobtree_ink.agents.outline import Outline, total_length
    rng = np.random.default_rng(4)
    outs = [Outline("silhouette", rng.normal(size=(k, 3)), np.zeros((k, 3)), closed=bool(k % 2)) for k in (1, 2, 5, 8)]
    assert total_length(outs) == pytest.approx(sum(o.length for o in outs), rel=1e-12)
    assert total_length([]) == 0.0 and total_length(outs[:1]) == 0.0
