"""Changes of BlobTree node trees, debounced: a change schedules the tree's preview to
be rebuilt once changes have stopped for DELAY seconds (a timer; never on every step
of a slider drag or every frame of playback), and at the latest MAX_WAIT seconds after
the first change it has not shown, or WAIT_PER_REBUILD times as long as its last
rebuild took if that is longer (so the preview keeps up with playback and long drags,
and rebuilding takes at most a third of the time however slow it is). An artist's
edit is also counted: a running illustration stops when its tree's edit count moves.
A move (the animation written at a new frame, a followed object moving: :func:`moving`)
is not an edit. The state is module state keyed by tree name (not stored on Blender
data or on Python wrappers). The rebuild itself is blobtree_nodes.preview's, which hands it in when it
registers (:func:`on_due`)."""
import contextlib
import time

import bpy

from .idnames import TREE

DELAY = 0.35                     # seconds of quiet before a rebuild
MAX_WAIT = 1.0                   # seconds from a first change to its rebuild, at most, however many follow
WAIT_PER_REBUILD = 2.0           # ... or this many times the tree's last rebuild's seconds, if longer

_clock = time.monotonic         # the time changes are stamped with (tests replace it)
_pending = {}                    # tree name -> monotonic time the rebuild is due
_since = {}                      # tree name -> monotonic time of the first change the rebuild will show
_cost = {}                       # tree name -> seconds its last rebuild took
_edits = {}                      # tree name -> number of edits seen (a running illustration stops on change)
_rebuild = []                    # what a due tree goes to: preview.rebuild, set when it registers


def edits(tree):
    return _edits.get(tree.name, 0)


_held = []                       # trees whose edits are being gathered (see hold)
_moves = []                      # inside moving(): changes are moves, not edits


@contextlib.contextmanager
def hold():
    """Gather edits (e.g. the thousands an importer makes) and schedule each tree's
    preview once at the end, instead of once per property write."""
    _held.append(set())
    try:
        yield
    finally:
        names = _held.pop()
        for name in names:
            tree = bpy.data.node_groups.get(name)
            if tree is not None:
                schedule(tree)


@contextlib.contextmanager
def moving():
    """Changes made inside are moves (animation, followed objects), not edits."""
    _moves.append(True)
    try:
        yield
    finally:
        _moves.pop()


def schedule(tree, delay=DELAY, edit=True):
    if _held:
        _held[-1].add(tree.name)
        return
    if edit and not _moves:
        _edits[tree.name] = _edits.get(tree.name, 0) + 1
    now = _clock()
    if tree.name not in _pending:
        _since[tree.name] = now
    longest = max(MAX_WAIT, WAIT_PER_REBUILD * _cost.get(tree.name, 0.0))
    _pending[tree.name] = min(now + delay, _since[tree.name] + longest)
    if not bpy.app.timers.is_registered(_tick):
        bpy.app.timers.register(_tick, first_interval=delay)


def pending():
    return dict(_pending)


def _tick():
    now = _clock()
    run_due(now)
    if not _pending:
        return None
    return max(0.02, min(_pending.values()) - now)


def run_due(now=None):
    """Rebuild every preview whose quiet period is over; returns the trees rebuilt."""
    now = _clock() if now is None else now
    done = []
    for name, due in list(_pending.items()):
        if due > now:
            continue
        del _pending[name]
        _since.pop(name, None)
        tree = bpy.data.node_groups.get(name)
        if tree is not None and tree.bl_idname == TREE and _rebuild:
            t = _clock()
            if _rebuild[0](tree):
                done.append(name)
            _cost[name] = _clock() - t
    return done


def on_due(rebuild):
    """Hand due trees to ``rebuild(tree) -> bool`` (None: nobody)."""
    _rebuild[:] = [] if rebuild is None else [rebuild]


def forget():
    """Another file was loaded: its trees may have the old file's names."""
    _pending.clear()
    _since.clear()
    _cost.clear()
    _edits.clear()


def stop():
    if bpy.app.timers.is_registered(_tick):
        bpy.app.timers.unregister(_tick)
    _pending.clear()
    _since.clear()
    _cost.clear()
