"""Joined outlines' bridges filled with outline points (agents.bridges): a silhouette
traced at two scales, joined round, has exact silhouette points at the finer step
round the joins and across the gaps its pieces were stitched over, where those were
chords; a join of two fine pieces that holds no such line is cut again."""
import numpy as np

from blobtree_ink import model as M
from blobtree_ink.agents import Settings
from blobtree_ink.agents.bridges import LONG, filled
from blobtree_ink.agents.outline import Outline, stitch_scales
from blobtree_ink.agents.surface import Surface
from blobtree_ink.blackboard.view import View

R = 2.0 * np.sqrt(1.0 - 0.5 ** (1.0 / 3.0))   # a lone point of radius 2 meets iso 0.5 here (Wyvill kernel)
EYE = np.array([0.0, -6.0, 0.0])
Y = -R * R / 6.0                        # the silhouette seen from EYE: the circle y = Y ...
RHO = np.sqrt(R * R - Y * Y)            # ... of this radius
COARSE = 0.06
FINE = COARSE / 6


def arc(t0, t1, step):
    t = np.linspace(t0, t1, int(round(abs(t1 - t0) * RHO / step)) + 1)
    P = np.stack([RHO * np.cos(t), np.full_like(t, Y), RHO * np.sin(t)], axis=1)
    return P, P / R


def setting():
    ev = M.Evaluator(M.from_dict({"format": "blobtree-1", "iso": 0.5,
                                  "root": {"type": "point", "center": [0, 0, 0], "radius": 2.0}}))
    s = Settings()
    return ev, Surface(ev, View(eye=EYE)), s.tolerance * ev.scale, s.crease_angle


def pieces(kind="silhouette"):
    """The silhouette round in three pieces: two at the fine step, 8 fine steps apart
    (farther than their own stitching reaches), and a quarter at the coarse step, each
    stopped most of a coarse step short of the fine ones; the coarse piece was stitched
    across a gap of three of its steps in its middle."""
    gap = 0.7 * COARSE / RHO
    P, N = arc(1.5 * np.pi + gap, 2 * np.pi - gap, COARSE)
    keep = np.r_[0:10, 12:len(P)]
    return [Outline(kind, *arc(gap, np.pi, FINE), False, FINE),
            Outline(kind, *arc(np.pi + 8 * FINE / RHO, 1.5 * np.pi, FINE), False, FINE),
            Outline(kind, P[keep], N[keep], False, COARSE)]


def test_a_silhouette_joined_across_scales_is_filled_round_at_the_finer_step():
    ev, surface, tol, crease_angle = setting()
    chords = stitch_scales(pieces())
    assert len(chords) == 1 and chords[0].closed
    spacing = np.linalg.norm(np.diff(np.vstack([chords[0].points, chords[0].points[:1]]), axis=0), axis=1)
    assert spacing.max() > 4 * FINE                       # the joins and the coarse piece: chords
    out = stitch_scales(pieces(), fill=lambda o, b: filled(surface, o, b, tol, crease_angle))
    assert len(out) == 1 and out[0].closed and out[0].step == FINE
    P = out[0].points
    spacing = np.linalg.norm(np.diff(np.vstack([P, P[:1]]), axis=0), axis=1)
    coarse = {tuple(p) for p in pieces()[2].points}
    own = np.array([tuple(a) in coarse and tuple(b) in coarse for a, b in zip(P, np.roll(P, -1, axis=0))])
    assert spacing[~own].max() <= LONG * FINE             # the joins and the coarse piece's gap: filled
    assert spacing[own].max() <= LONG * COARSE and own.sum() > 5    # its own steps: kept
    assert spacing.min() > 0
    f, g = ev.field_grad(P)
    assert np.all(np.abs(f - ev.iso) / np.linalg.norm(g, axis=1) < 1e-6 * ev.scale)     # on the surface
    n = -g / np.linalg.norm(g, axis=1, keepdims=True)
    v = (EYE - P) / np.linalg.norm(EYE - P, axis=1, keepdims=True)
    assert np.abs(np.einsum("ij,ij->i", n, v)).max() < 1e-6                            # on the silhouette
    np.testing.assert_allclose(np.linalg.norm(out[0].normals - n, axis=1), 0.0, atol=1e-6)
    turn = np.unwrap(np.arctan2(P[:, 2], P[:, 0]))
    assert np.all(np.diff(turn) > 0)                        # in order round the circle


def test_a_join_of_fine_pieces_over_no_such_line_is_cut_again():
    """The same pieces called creases (a sphere has none): stitched alone they are joined
    round by chords; filled, the join of the two fine pieces finds no crease and is cut
    again (their own stitching did not reach across it), while the joins to the coarse
    piece, and its own gap, stay chords: one open outline of all the points, ending at
    the fine pieces' facing ends."""
    _, surface, tol, crease_angle = setting()
    plain = stitch_scales(pieces("crease"))
    assert len(plain) == 1 and plain[0].closed
    out = stitch_scales(pieces("crease"), fill=lambda o, b: filled(surface, o, b, tol, crease_angle))
    assert len(out) == 1 and not out[0].closed
    assert {tuple(p) for p in out[0].points} == {tuple(p) for p in plain[0].points}
    a, b = pieces("crease")[:2]
    ends = {tuple(out[0].points[0]), tuple(out[0].points[-1])}
    assert ends == {tuple(a.points[-1]), tuple(b.points[0])}
