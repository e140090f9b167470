"""A hatching map's lines that meet end to end are one line (strokes.hatch_join): two
arcs of one track on a sphere, facing each other across a gap, become one smooth line
on the surface; lines side by side, too far aside, with another line across the gap, or
that would close a ring, stay apart."""
import numpy as np

from blobtree_ink import model as M
from blobtree_ink.strokes import hatch_join as HJ

EV = M.Evaluator(M.from_dict({"format": "blobtree-1", "root": {"type": "point", "center": [0, 0, 0],
                                                                 "radius": 1.0}}))
R = np.sqrt(1 - 0.5 ** (1 / 3))            # the sphere's radius: (1 - d^2)^3 = 0.5
SPACING = 0.1
STEP = 0.4 * SPACING


def arc(a, b, z=0.0, level=0, key=1):
    """A line of the map along the circle of height z (on the sphere) from angle a to b,
    about STEP apart."""
    rho = np.sqrt(R * R - z * z)
    t = np.linspace(a, b, max(int(abs(b - a) * rho / STEP), 2) + 1)
    P = np.c_[rho * np.cos(t), rho * np.sin(t), np.full(len(t), z)]
    return P, P / R, level, np.uint64(key)


def gap_angle(share):
    return share * SPACING / R


def test_two_arcs_of_one_track_facing_across_a_gap_are_one_smooth_line_on_the_surface():
    g = gap_angle(1.2)
    lines = [arc(0.0, 1.0, key=5), arc(1.0 + g, 1.5 + g, z=0.2 * SPACING, key=9)]   # a little to one side
    out = HJ.join(EV, lines, SPACING, STEP)
    assert len(out) == 1
    P, N, level, key = out[0]
    assert level == 0 and key == 5                          # the longer part's key
    assert len(P) > len(lines[0][0]) + len(lines[1][0])     # the gap bridged
    assert np.allclose(np.linalg.norm(P, axis=1), R, atol=1e-3)
    assert np.allclose(N, P / np.linalg.norm(P, axis=1, keepdims=True), atol=1e-2)
    T = np.diff(P, axis=0)
    T /= np.linalg.norm(T, axis=1, keepdims=True)
    turn = np.degrees(np.arccos(np.clip(np.einsum("ij,ij->i", T[1:], T[:-1]), -1, 1)))
    assert turn.max() < 10.0, turn.max()                    # eased over to the other's track, no step


def test_a_line_reversed_joins_head_to_head():
    g = gap_angle(1.0)
    lines = [arc(0.0, 1.0), arc(1.6 + g, 1.0 + g, key=2)]   # the second runs the other way
    out = HJ.join(EV, lines, SPACING, STEP)
    assert len(out) == 1
    P = out[0][0]
    assert np.allclose(P[0], lines[0][0][0]) and np.allclose(P[-1], lines[1][0][0])


def test_lines_that_do_not_meet_end_to_end_stay_apart():
    g = gap_angle(1.2)
    cases = {
        "side by side": [arc(0.0, 1.0), arc(0.0, 1.0, z=SPACING)],
        "too far aside": [arc(0.0, 1.0), arc(1.0 + g, 1.5 + g, z=0.5 * SPACING)],
        "too far apart": [arc(0.0, 1.0), arc(1.0 + gap_angle(2.5), 1.5 + gap_angle(2.5))],
        "levels apart": [arc(0.0, 1.0), arc(1.0 + g, 1.5 + g, level=1)],
        "another line across the gap": [arc(0.0, 1.0), arc(1.0 + g, 1.5 + g),
                                        (lambda t: (np.c_[np.full(9, R * np.cos(t)), np.full(9, R * np.sin(t)),
                                                          np.linspace(-0.2, 0.2, 9)], None, 1, 3))(1.0 + g / 2)],
    }
    for name, lines in cases.items():
        if lines[-1][1] is None:                               # (the crossing line: normals of its points)
            p = lines[-1][0]
            p = p / np.linalg.norm(p, axis=1, keepdims=True) * R
            lines[-1] = (p, p / R, 0, np.uint64(3))
        out = HJ.join(EV, lines, SPACING, STEP)
        assert len(out) == len(lines), name


def test_a_line_across_a_gap_shorter_than_a_step_keeps_the_ends_apart():
    g = gap_angle(1.2)
    t = 1.0 + g / 2
    p = np.c_[np.full(9, np.cos(t)), np.full(9, np.sin(t)), np.linspace(-0.2, 0.2, 9)]
    p = p / np.linalg.norm(p, axis=1, keepdims=True) * R
    across = (p, p / R, 0, np.uint64(3))
    lines = [arc(0.0, 1.0), arc(1.0 + g, 1.5 + g)]
    assert len(HJ.join(EV, lines, SPACING, 2.0 * SPACING)) == 1          # (no bridge points: the chord is tested)
    assert len(HJ.join(EV, lines + [across], SPACING, 2.0 * SPACING)) == 3


def test_a_ring_is_not_closed():
    g = gap_angle(1.0)
    half = np.pi - g
    lines = [arc(0.0, half), arc(half + g, 2 * np.pi - g, key=2)]    # a circle in two, a gap at each meeting
    out = HJ.join(EV, lines, SPACING, STEP)
    assert len(out) == 1                                    # joined once: an open line, its ends a gap apart
    P = out[0][0]
    assert np.linalg.norm(P[0] - P[-1]) > 0.5 * SPACING
