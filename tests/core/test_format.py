"""blobtree-1 loading, saving and validation: every rule has a test with its message."""
import json

import pytest
from conftest import ALL_MODELS, example_path

from blobtree_ink import model as M
from blobtree_ink.model import format as F
from blobtree_ink.model import nodes as N


def doc(root, **top):
    d = {"format": "blobtree-1", "name": "t", "root": root}
    d.update(top)
    return d


PT = {"type": "point", "center": [0, 0, 0], "radius": 1}


def err(d):
    with pytest.raises(M.ModelError) as e:
        M.from_dict(d) if not isinstance(d, str) else M.loads(d)
    return str(e.value)


@pytest.mark.parametrize("name", ALL_MODELS)
def test_round_trip_every_example(name):
    text = open(example_path(name)).read()
    m = M.loads(text)
    again = M.loads(M.dumps(m))
    assert again == m
    assert M.to_dict(again) == json.loads(text)


def test_defaults_and_optional_keys():
    m = M.from_dict(doc({"type": "transform", "child": PT}))
    assert m.iso == 0.5 and m.name == "t"
    t = m.root
    assert t.translate == (0, 0, 0) and t.rotate == (0, 0, 0) and t.scale == (1, 1, 1)
    assert t.child.strength == 1.0
    assert M.to_dict(m)["root"] == {"type": "transform", "child": {"type": "point", "center": [0, 0, 0],
                                                                     "radius": 1}}
    m2 = M.from_dict(doc(dict(PT, strength=2.5, name="ball"), iso=0.3))
    assert m2.iso == 0.3 and m2.root.strength == 2.5 and m2.root.name == "ball"
    assert M.from_dict(M.to_dict(m2)) == m2


@pytest.mark.parametrize("root, message", [
    ({"type": "point", "center": [0, 0, 0], "radius": -1}, "root.radius: must be > 0, got -1"),
    ({"type": "point", "center": [0, 0, 0], "radius": 0}, "root.radius: must be > 0, got 0"),
    ({"type": "point", "center": [0, 0], "radius": 1}, "root.center: must be a list of 3 numbers, got a list of 2"),
    ({"type": "point", "center": [0, "x", 0], "radius": 1}, "root.center[1]: must be a number, got the string 'x'"),
    ({"type": "point", "center": [0, True, 0], "radius": 1}, "root.center[1]: must be a number, got a boolean"),
    ({"type": "point", "center": [0, 0, 0]}, "root.radius: missing (a point node needs it)"),
    ({"type": "point", "center": [0, 0, 0], "radius": 1, "colour": 3}, "root: unknown key 'colour' for a point node"),
    ({"type": "point", "center": [0, 0, 0], "radius": 1, "name": 5}, "root.name: must be a string, got 5"),
    ({"type": "point", "center": [0, 0, 0], "radius": 1, "strength": "1"}, "root.strength: must be a number"),
    ({"type": "sphere"}, "root.type: must be one of point, segment"),
    ({"center": [0, 0, 0]}, "root.type: must be one of"),
    ([1, 2], "root: must be a node object, got a list of 2"),
    ({"type": "segment", "a": [0, 0, 0], "radius": 1}, "root.b: missing"),
    ({"type": "circle", "center": [0, 0, 0], "normal": [0, 0, 0], "circle_radius": 1, "radius": 1},
     "root.normal: must not be the zero vector"),
    ({"type": "circle", "center": [0, 0, 0], "normal": [0, 0, 1], "circle_radius": -2, "radius": 1},
     "root.circle_radius: must be > 0, got -2"),
    ({"type": "disc", "center": [0, 0, 0], "normal": [0, 0, 1], "disc_radius": 0, "radius": 1},
     "root.disc_radius: must be > 0, got 0"),
    ({"type": "box", "center": [0, 0, 0], "half_size": [1, -1, 1], "radius": 1}, "root.half_size[1]: must be >= 0, got -1"),
    ({"type": "blend", "children": []}, "root.children: must be a list of at least 1 node, got a list of 0"),
    ({"type": "union", "children": PT}, "root.children: must be a list of at least 1 node, got an object"),
    ({"type": "difference", "children": [PT]}, "root.children: must be a list of at least 2 nodes, got a list of 1"),
    ({"type": "ricci", "children": [PT], "n": 0.5}, "root.n: must be >= 1, got 0.5"),
    ({"type": "ricci", "children": [PT]}, "root.n: missing"),
    ({"type": "blend", "children": [PT, {"type": "point", "center": [0, 0, 0], "radius": -1}]},
     "root.children[1].radius: must be > 0, got -1"),
    ({"type": "blend", "children": [PT, 7]}, "root.children[1]: must be a node object, got 7"),
    ({"type": "transform", "child": PT, "scale": [1, 0, 1]}, "root.scale[1]: must not be 0"),
    ({"type": "transform", "child": PT, "rotate": [0, 0]}, "root.rotate: must be a list of 3 numbers"),
    ({"type": "transform"}, "root.child: missing"),
    ({"type": "twist", "child": PT}, "root.rate: missing"),
    ({"type": "bend", "child": {"type": "taper", "rate": 1, "child": {"type": "point", "center": [0, 0, 0],
                                                                    "radius": 1e30}}, "rate": 1},
     "root.child.child.radius: magnitude must be at most 1e+09"),
])
def test_validation_messages(root, message):
    assert message in err(doc(root))


def test_document_rules():
    assert "document: must be a JSON object" in err([1])
    assert "document.format: missing" in err({"name": "x", "root": PT})
    assert 'document.format: must be "blobtree-1", got the string \'blobtree-2\'' in err(
        {"format": "blobtree-2", "root": PT})
    assert "document: unknown key 'version'" in err(doc(PT, version=2))
    assert "document.root: missing" in err({"format": "blobtree-1"})
    assert "document.iso: must be > 0, got 0" in err(doc(PT, iso=0))
    assert "document.name: must be a non-empty string" in err(doc(PT, name=""))


def test_non_finite_and_broken_json():
    assert "must be finite" in err(doc(dict(PT, radius=float("nan"))))
    assert "root.center[2]: must be a finite number, got the literal NaN" in err(
        '{"format": "blobtree-1", "root": {"type": "point", "center": [0, 0, NaN], "radius": 1}}')
    assert "root.children[1].radius: must be a finite number, got the literal -Infinity" in err(
        '{"format": "blobtree-1", "root": {"type": "union", "children": [{"type": "point", "center": [0, 0, 0], '
        '"radius": 1}, {"type": "point", "center": [1, 0, 0], "radius": -Infinity}]}}')
    assert "document.format: must be \"blobtree-1\", got the literal NaN" in err('{"format": NaN}')
    assert "root.radius: must be finite, got inf" in err(
        '{"format": "blobtree-1", "root": {"type": "point", "center": [0,0,0], "radius": 1e999}}')
    assert "not valid JSON" in err('{"format": "blobtree-1", "root": ')
    assert "not a usable JSON number" in err('{"format": "blobtree-1", "root": {"type": "point", '
                                             '"center": [0,0,0], "radius": ' + "9" * 5000 + "}}")
    with pytest.raises(M.ModelError, match="not UTF-8"):
        M.loads(b'{"format": "\xff"}')


def test_hostile_deep_nesting_is_rejected_quickly():
    text = '{"format": "blobtree-1", "root": ' + '{"type": "transform", "child": ' * 100_000 + \
        json.dumps(PT) + "}" * 100_000 + "}"
    msg = err(text)
    assert "nesting" in msg and "256" in msg


def test_hostile_million_nodes_rejected():
    text = '{"format": "blobtree-1", "root": {"type": "blend", "children": [' + \
        ",".join([json.dumps(PT)] * 1_000_000) + "]}}"
    assert f"model has more than {F.MAX_NODES} nodes" in err(text)


def test_save_is_atomic(tmp_path, monkeypatch):
    good = tmp_path / "m.json"
    M.save(M.from_dict(doc(PT)), good)
    before = good.read_text()
    # a failing save leaves the old file intact
    with pytest.raises(TypeError, match="not a BlobTree node"):
        M.save(N.Model(root="not a node"), good)
    assert good.read_text() == before
    import os

    def boom(a, b):
        raise OSError("disk full")
    monkeypatch.setattr(os, "replace", boom)
    with pytest.raises(OSError, match="disk full"):
        M.save(M.from_dict(doc(dict(PT, radius=2))), good)
    assert good.read_text() == before
    assert not [p for p in tmp_path.iterdir() if p.name.startswith(".blobtree-")]


def test_load_names_the_file(tmp_path):
    p = tmp_path / "broken.json"
    p.write_text(json.dumps(doc(dict(PT, radius=-3))))
    with pytest.raises(M.ModelError) as e:
        M.load(str(p))
    assert str(e.value) == f"{p}: root.radius: must be > 0, got -3"
    with pytest.raises(M.ModelError, match="cannot read"):
        M.load(str(tmp_path / "missing.json"))


def test_node_counts_of_paper_models(load_example):
    assert M.count_nodes(load_example("shell")) == 1497
    assert abs(M.count_nodes(load_example("train")) - 723) <= 5
    assert M.count_nodes(load_example("heart")) == 76


def test_lengths_whose_squares_underflow_are_rejected():
    """A radius, scale factor or normal so small that its square underflows (or its
    inverse overflows) is refused with its path, not left to divide by zero later."""
    assert "root.radius: must be at least 1e-09, got 1e-200" in err(doc(dict(PT, radius=1e-200)))
    assert "root.children[1].radius: must be at least 1e-09" in err(doc(
        {"type": "blend", "children": [PT, dict(PT, radius=1e-160)]}))
    assert "root.scale[0]: must be at least 1e-09 in size, got -1e-200" in err(doc(
        {"type": "transform", "scale": [-1e-200, 1, 1], "child": PT}))
    assert "root.normal: must be at least 1e-09 long" in err(doc(
        {"type": "circle", "center": [0, 0, 0], "normal": [1e-300, 0, 0], "circle_radius": 1, "radius": 0.5}))
    assert "root.rate: must be 0 or at least 1e-09 in size" in err(doc({"type": "bend", "rate": 5e-324, "child": PT}))
    assert M.from_dict(doc({"type": "bend", "rate": 0, "child": PT})).root.rate == 0
    assert M.from_dict(doc(dict(PT, radius=1e-9))).root.radius == 1e-9      # the limit itself loads


def test_a_fingerprint_tells_models_apart_by_their_surface_not_their_names():
    """model.fingerprint: one key for models that draw alike (names of the model and
    its nodes aside), another after any change of a value."""
    from blobtree_ink.model import fingerprint
    doc = {"format": "blobtree-1", "name": "a", "root": {"type": "blend", "name": "body", "children": [
        {"type": "point", "center": [0, 0, 0], "radius": 1.0},
        {"type": "segment", "a": [0, 0, 0], "b": [1, 0, 0], "radius": 0.5}]}}
    key = fingerprint(M.from_dict(doc))
    assert len(key) == 16 and key == fingerprint(M.from_dict(doc))
    renamed = dict(doc, name="b", root=dict(doc["root"], name="torso"))
    assert fingerprint(M.from_dict(renamed)) == key
    moved = json.loads(json.dumps(doc))
    moved["root"]["children"][1]["b"] = [1, 0, 1e-9]
    assert fingerprint(M.from_dict(moved)) != key
    assert fingerprint(M.from_dict(dict(doc, iso=0.4))) != key
