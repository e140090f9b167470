"""The blobtree-ink command line (pure subcommands) on every example and on bad input."""
import io

import numpy as np
import pytest
from conftest import ALL_MODELS, example_path

from blobtree_ink import model as M
from blobtree_ink.cli import main


def run(*args):
    out = io.StringIO()
    code = main(list(args), out=out)
    return code, out.getvalue()


@pytest.mark.parametrize("name", ALL_MODELS)
def test_info_on_every_example(name):
    code, text = run("info", example_path(name))
    assert code == 0
    m = M.load(example_path(name))
    assert f"nodes: {M.count_nodes(m)}\n" in text and f"name: {m.name}\n" in text
    line = [ln for ln in text.splitlines() if ln.startswith("surface bounds: (")][0]
    lo, hi = [np.array([float(x) for x in part.strip(" ()").split(",")]) for part in
              line[len("surface bounds: "):].split("..")]
    assert np.all(hi > lo)
    # the surface really lies inside the reported bounds: the field is below iso just outside
    ev = M.Evaluator(m)
    g = np.random.default_rng(0).uniform(lo, hi, size=(20000, 3))
    assert (ev.field(g) >= m.iso).any()
    span = hi - lo
    outside = np.random.default_rng(1).uniform(lo - span, hi + span, size=(20000, 3))
    outside = outside[np.any((outside < lo) | (outside > hi), axis=1)]
    assert not (ev.field(outside) >= m.iso).any()


@pytest.mark.parametrize("name", ALL_MODELS)
def test_eval_on_every_example(name, tmp_path):
    m = M.load(example_path(name))
    ev = M.Evaluator(m)
    P = np.random.default_rng(2).uniform(*ev.bounds, size=(500, 3))
    np.save(tmp_path / "p.npy", P)
    assert run("eval", example_path(name), "--points", str(tmp_path / "p.npy"), "--out", str(tmp_path / "f.npy"))[0] == 0
    np.testing.assert_array_equal(np.load(tmp_path / "f.npy"), ev.field(P))
    assert run("eval", example_path(name), "--points", str(tmp_path / "p.npy"), "--out", str(tmp_path / "g.npy"),
               "--gradient")[0] == 0
    fg = np.load(tmp_path / "g.npy")
    f, g = ev.field_grad(P)
    assert fg.shape == (500, 4)
    np.testing.assert_array_equal(fg[:, 0], f)
    np.testing.assert_array_equal(fg[:, 1:], g)


def test_eval_rejects_bad_points(tmp_path, capsys):
    sphere = example_path("sphere")
    np.save(tmp_path / "flat.npy", np.zeros((4, 2)))
    np.save(tmp_path / "nan.npy", np.array([[0, 0, 0], [np.nan, 0, 0]]))
    np.save(tmp_path / "obj.npy", np.array([["a", "b", "c"]]))
    (tmp_path / "junk.npy").write_bytes(b"not numpy")
    cases = {"flat.npy": "must hold an (N,3) array, got shape (4, 2)", "nan.npy": "row 1 is not finite",
             "obj.npy": "must hold numbers", "junk.npy": "not a readable .npy array",
             "missing.npy": "no such file"}
    for fname, msg in cases.items():
        out = tmp_path / "out.npy"
        code, _ = run("eval", sphere, "--points", str(tmp_path / fname), "--out", str(out))
        err = capsys.readouterr().err
        assert code == 1 and msg in err, (fname, err)
        assert not out.exists()
    code, _ = run("eval", sphere, "--points", str(tmp_path / "nan.npy"), "--out", str(tmp_path / "no" / "x.npy"))
    assert code == 1


def test_usage_errors_exit_2(capsys):
    assert run()[0] == 2
    assert run("frobnicate")[0] == 2
    assert run("eval", example_path("sphere"))[0] == 2    # --points and --out missing
    assert "usage: blobtree-ink" in capsys.readouterr().err


def test_existing_output_survives_a_failed_run(tmp_path):
    out = tmp_path / "f.npy"
    np.save(out, np.arange(3.0))
    np.save(tmp_path / "bad.npy", np.zeros((2, 5)))
    assert run("eval", example_path("sphere"), "--points", str(tmp_path / "bad.npy"), "--out", str(out))[0] == 1
    np.testing.assert_array_equal(np.load(out), np.arange(3.0))
