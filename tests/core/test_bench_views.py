"""The measures of bench/outlines.py --views on synthetic pictures: gaps in the covered
ground truth, dangling outline ends and precision."""
import os
import sys

import numpy as np

from blobtree_ink.agents.outline import Outline

sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))),
                                "bench"))
import outlinemeasure as O  # noqa: E402


class Flat:
    """A camera whose pixels are the points' x and y."""

    def pixels(self, P):
        return np.asarray(P, float)[:, :2]


def line(*points, closed=False):
    P = np.array(points, float)
    return Outline("silhouette", P, np.zeros_like(P), closed)


def row(x0, x1, y=100):
    img = np.zeros((O.PX, O.PX), bool)
    img[y, x0:x1] = True
    return img


def test_a_missed_run_of_five_pixels_is_a_gap_and_one_of_two_is_not():
    truth = row(100, 200)
    five = row(100, 200) & ~row(140, 147)           # within 1 px of 139 and 147: 141-145 missed
    two = row(100, 200) & ~row(140, 144)            # 141-142 missed
    assert (truth & ~O.dilate(five)).sum() == 5 and (truth & ~O.dilate(two)).sum() == 2
    assert O.gaps(truth, five) == 1
    assert O.gaps(truth, two) == 0
    assert O.gaps(truth, five & two & ~row(170, 177)) == 2
    assert O.gaps(truth, truth) == 0


def test_a_diagonal_run_is_one_gap():
    truth = np.zeros((O.PX, O.PX), bool)
    truth[np.arange(300, 320), np.arange(300, 320)] = True
    assert O.gaps(truth, np.zeros_like(truth)) == 1


def test_ends_meeting_another_outline_or_the_border_do_not_dangle():
    bar = line((1, 100), (1022, 100))                                # both ends at the border
    stem = line((500, 100), (500, 300), (500, 1023))                 # from the bar to the border
    assert O.dangling_ends(Flat(), [bar, stem]) == 0
    half = line((1, 400), (300, 400))
    other = line((300, 400), (600, 400), (1022, 400))                # end to end with half
    assert O.dangling_ends(Flat(), [half, other]) == 0


def test_a_free_end_dangles():
    bar = line((1, 100), (1022, 100))
    stem = line((500, 100), (500, 300))                              # its lower end is free
    assert O.dangling_ends(Flat(), [bar, stem]) == 1
    assert O.dangling_ends(Flat(), [line((200, 200), (300, 200))]) == 2


def test_an_end_near_its_own_outline_far_along_it_does_not_dangle():
    hook = line((1, 500), (400, 500), (400, 520), (300, 520), (300, 502))   # back beside its own start
    assert O.dangling_ends(Flat(), [hook]) == 0
    short = line((1, 600), (300, 600), (303, 601))                    # its own points only, within 6 px
    assert O.dangling_ends(Flat(), [short]) == 1


def test_a_closed_outline_has_no_ends():
    square = line((200, 200), (300, 200), (300, 300), (200, 300), closed=True)
    assert O.dangling_ends(Flat(), [square]) == 0
    traced = O.raster(Flat(), O.drawn([square]))
    assert traced[250, 200] and traced[200, 250]                     # its closing side is drawn


def test_precision_is_the_share_of_traced_pixels_near_the_truth():
    truth = row(100, 200)
    traced = row(100, 200, y=101) | row(300, 350)                    # 100 beside the truth, 50 far
    assert np.isclose(O.precision(truth, traced), 100 / 150)
    assert O.precision(truth, row(100, 200, y=102)) == 0.0
    assert O.coverage(truth, row(100, 150, y=101)) == 51 / 100


def test_an_edge_has_one_key_whichever_way_round():
    a = np.array([[0.0, 1.0, 2.0], [1.0, 0.0, 0.0], [1.0, 1.0, 1.0]])
    b = np.array([[0.0, 1.0, 3.0], [0.0, 5.0, 0.0], [1.0, 1.0, 1.0]])
    assert O.edge_keys(a, b) == O.edge_keys(b, a)
    assert len(set(O.edge_keys(a, b))) == 3


def test_the_turning_mode_compares_going_on_frames_with_scratch_ones():
    """bench/outlines.py --turning: a sphere seen by a turning eye, going on from the
    last frame and from scratch: the same outline, all of its ground truth; a bad
    frame count or turn is a usage error."""
    import subprocess
    script = os.path.join(os.path.dirname(O.__file__), "outlines.py")
    run = subprocess.run([sys.executable, script, "--turning", "3", "--turn", "5", "--models", "sphere",
                          "--gt-res", "64"], capture_output=True, text=True, timeout=300)
    assert run.returncode == 0, run.stderr
    rows = [line.split() for line in run.stdout.splitlines() if line.startswith("sphere")]
    assert [r[1] for r in rows[:2]] == ["1", "2"] and len(rows) == 3          # frames 1, 2 and the worst
    for r in rows:
        assert [float(x) for x in r[-6:-2]] == [1.0] * 4, r
    for bad in (["--turning", "1"], ["--turning", "3", "--turn", "nan"]):
        run = subprocess.run([sys.executable, script, *bad], capture_output=True, text=True, timeout=60)
        assert run.returncode == 2 and "--turning needs" in run.stderr
