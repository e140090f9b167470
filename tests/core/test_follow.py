"""Silhouettes followed from the last frame's when only the eye moved (agents.follow):
the followed points are this frame's silhouette points (truth from the exact field
alone), in the old order and spacing, never across a crease; a session going on from
the last frame follows them instead of tracing them again, keeps where its outlines
start, and looks for no crease the last frame found."""
import numpy as np

from blobtree_ink import model as M
from blobtree_ink.agents import Session, Settings
from blobtree_ink.agents import follow as FO
from blobtree_ink.agents.surface import Surface
from blobtree_ink.blackboard.board import KIND_ID
from blobtree_ink.blackboard.view import View
from test_continuation import EYE, doc, pair, point, session, turned
from truth import on_a_crease, on_the_surface, silhouette_residual

TURN = 0.04                     # radians the eye turns about the model from one frame to the next


def followed(model, eye, moved):
    """A session's silhouettes seen from ``eye``, followed to the eye ``moved``."""
    first = session(model, eye)
    sil = [o for o in first.outlines() if o.kind == "silhouette"]
    surface = Surface(first.ev, View(eye=moved))
    got, lost = FO.follow(surface, sil, first.h, first.step_len, first.tol, first.settings.crease_angle)
    return first, sil, got, lost


def test_followed_points_are_the_new_silhouette_in_the_old_order_and_spacing():
    ellipsoid = doc({"type": "transform", "scale": [1.4, 1.0, 0.8], "child": point(0.0)})
    moved = turned(EYE, TURN)
    first, sil, got, lost = followed(ellipsoid, EYE, moved)
    assert len(sil) == 1 and sil[0].closed and not lost
    assert len(got) == 1 and got[0].closed                              # followed whole: still one loop
    X, step = got[0].points, got[0].step
    assert on_the_surface(first.ev, X).all()
    assert np.abs(silhouette_residual(first.ev, X, moved)).max() < 1e-6
    assert np.abs(silhouette_residual(first.ev, X, EYE)).max() > 1e-3  # it did move: the old one is not it
    gaps = np.linalg.norm(np.roll(X, -1, axis=0) - X, axis=1)
    assert gaps.min() >= FO.SPACING[0] * step * 0.999 and gaps.max() <= sum(FO.SPACING) * step
    # the same start and the same way round: the first point near the old first, each
    # link heading the way the old outline went there
    old = sil[0].points
    assert np.linalg.norm(X[0] - old[0]) < FO.REACH * first.h
    along = np.roll(old, -1, axis=0) - old
    nearest = np.argmin(np.linalg.norm(X[:, None] - old[None], axis=2), axis=1)
    assert (np.einsum("ij,ij->i", np.roll(X, -1, axis=0) - X, along[nearest]) > 0).all()


def test_a_followed_silhouette_stops_at_a_crease():
    """Two spheres' union: each sphere's silhouette ends where it meets the crease; no
    followed run passes from one sphere to the other."""
    moved = turned(EYE, TURN)
    first, sil, got, lost = followed(pair(0.8), EYE, moved)
    assert got and sum(len(o.points) for o in got) > 0.8 * sum(len(o.points) for o in sil)
    spread = first.settings.crease_angle
    for o in got:
        X = o.points
        assert np.abs(silhouette_residual(first.ev, X, moved)).max() < 1e-6
        # no point of a followed run sits on the crease, and no link jumps across it
        assert not on_a_crease(first.ev, X).any()
        assert (np.einsum("ij,ij->i", o.normals[1:], o.normals[:-1]) > np.cos(0.5 * spread)).all()


def test_what_cannot_be_followed_is_given_back_to_seed():
    """An eye moved to the other side: the old silhouettes meet the new ones at a few
    points only. Every old point is followed (a new point within REACH cells) or comes
    back, old, in a part that seeds the tracer."""
    first, sil, got, lost = followed(pair(0.8), EYE, -EYE)
    old = np.concatenate([o.points for o in sil])
    new = np.concatenate([o.points for o in got]) if got else np.zeros((0, 3))
    back = np.concatenate([o.points for o in lost])
    assert len(new) < 0.2 * len(old) and len(back) > 0.8 * len(old)
    d_new = np.linalg.norm(old[:, None] - new[None], axis=2).min(axis=1) if len(new) else np.full(len(old), np.inf)
    d_back = np.linalg.norm(old[:, None] - back[None], axis=2).min(axis=1)
    assert ((d_new < FO.REACH * first.h) | (d_back == 0)).all()


def test_going_on_follows_the_silhouettes_rather_than_tracing_them():
    ev = M.Evaluator(pair(0.8))
    first = session(ev, EYE)
    moved = turned(EYE, TURN)
    going = session(ev, moved, first.continuation())
    scratch = session(M.Evaluator(pair(0.8)), moved)
    assert going.traces.serial < 0.25 * scratch.traces.serial, (going.traces.serial, scratch.traces.serial)
    # no crease seed: the field is the last frame's, and so are its creases (kept)
    f = going.bb.feat
    assert not (f["kind"] == KIND_ID["crease"]).any()
    creases = [o for o in going.outlines() if o.kind == "crease"]
    assert creases and sum(len(o.points) for o in creases) == sum(
        len(o.points) for o in first.outlines() if o.kind == "crease")
    sil = [o for o in going.outlines() if o.kind == "silhouette"]
    X = np.concatenate([o.points for o in sil])
    assert np.abs(silhouette_residual(ev, X, moved)).max() < 1e-6
    # where each silhouette starts stays put from frame to frame (a stroke's start)
    starts = [o.points[0] for o in first.outlines() if o.kind == "silhouette"]
    for o in sil:
        assert min(np.linalg.norm(o.points[0] - s) for s in starts) < 0.5 * first.h


def test_a_task_at_a_kept_outlines_end_traces_on_as_its_own():
    """A silhouette kept with a gap (as a last frame's part that could not be followed)
    is traced on from both ends of the gap by Traces.extend alone (no seed), as the
    outline's own: its own last points do not stop the tasks, they meet across the gap."""
    first = session(pair(0.8), EYE)
    whole = max((o for o in first.outlines() if o.kind == "silhouette"), key=lambda o: len(o.points))
    assert whole.closed
    cut = FO.Outline(whole.kind, whole.points[8:-8], whole.normals[8:-8], False, whole.step)
    s = Session(M.Evaluator(pair(0.8)), View(eye=EYE), Settings(resolution=20))     # no seed taken yet
    s.traces.add_traced([cut])
    s.traces.extend([cut], 0)
    for _ in range(100):
        if not len(s.traces):
            break
        s.traces.step()
    grown = [o for o in s.traces.done[1:] if len(o.points)]
    assert grown and not len(s.traces)
    X = np.concatenate([o.points for o in grown])
    assert np.abs(silhouette_residual(s.ev, X, EYE)).max() < 1e-6
    gap = np.concatenate([whole.points[:8], whole.points[-8:]])
    assert np.linalg.norm(gap[:, None] - X[None], axis=2).min(axis=1).max() < 0.5 * whole.step
    assert len(X) < 2 * len(gap) < len(whole.points) / 2         # the gap, not round the loop again


def test_a_session_stopped_short_leaves_its_creases_to_be_looked_for_again():
    """Only a last frame that ran to its end vouches for its creases: after one stopped
    by a budget, the polygon edges seed creases again where the field is the same."""
    ev = M.Evaluator(pair(0.8))
    short = Session(ev, View(eye=EYE), Settings(resolution=20), remember=True)
    short.request("OUTLINES")
    short.run(iterations=2)
    assert not short.done
    going = Session(ev, View(eye=turned(EYE, TURN)), Settings(resolution=20), previous=short.continuation())
    assert (going.bb.feat["kind"] == KIND_ID["crease"]).any()
    going.request("OUTLINES")
    going.run()
    assert any(o.kind == "crease" for o in going.outlines())
