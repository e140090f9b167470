"""What an artist sees of BlobTree nodes: distinct, described labels; vectors with two
decimals, one component a row; numbered n-ary inputs."""
import math
from importlib import import_module
from types import SimpleNamespace

import bpy
import pytest

from recording_layout import Layout

PKG = "bl_ext.user_default.blobtree_ink.blobtree_nodes"


def mod(name):
    return import_module(f"{PKG}.{name}")


def new_tree(name="T"):
    return bpy.data.node_groups.new(name, "BlobTreeInkNodeTree")


def all_idnames():
    return [c.bl_idname for c in mod("nodes").classes]


def drawn(node):
    rec = Layout()
    node.draw_buttons(bpy.context, rec)
    return rec


@pytest.mark.parametrize("idname", all_idnames())
def test_every_drawn_property_has_its_own_name_and_a_tooltip(idname):
    node = new_tree().nodes.new(idname)
    named = drawn(node).prop_names()
    names = [name for _, name in named]
    assert len(set(names)) == len(names), names            # e.g. no two "Center"
    for p, name in named:
        rna = p["data"].bl_rna.properties[p["prop"]]
        assert name.strip(), p["prop"]
        assert len(rna.description) > len(name) and rna.description != name, (p["prop"], rna.description)
    assert len({s.name for s in node.inputs}) == len(node.inputs)


def test_object_pickers_and_vectors_are_told_apart():
    t = new_tree()
    point, segment, transform = (t.nodes.new(mod("nodes").idname(k)) for k in ("point", "segment", "transform"))
    def names(node):
        return [name for _, name in drawn(node).prop_names()]
    assert names(point) == ["Center: Follow Object", "Center", "Influence Radius", "Strength"]
    assert names(segment)[:4] == ["Start: Follow Object", "Start", "End: Follow Object", "End"]
    assert names(transform) == ["Follow Object", "Translate", "Rotate", "Scale"]
    assert {k: names(t.nodes.new(mod("nodes").idname(k))) for k in ("twist", "taper", "bend")} == {
        "twist": ["Twist Rate"], "taper": ["Taper Rate"], "bend": ["Curvature"]}
    # the pickers' own names (their tooltips' subject) tell them apart too
    assert [point.bl_rna.properties[k].name for k in ("center_object", "center")] == ["Center Follows", "Center"]
    # a followed vector shows no numbers (the object gives them)
    point.center_object = bpy.data.objects.new("Handle", None)
    assert names(point) == ["Center: Follow Object", "Influence Radius", "Strength"]


@pytest.mark.parametrize("idname", all_idnames())
def test_numbers_show_two_decimals_and_vectors_one_component_a_row(idname):
    node = new_tree().nodes.new(idname)
    for p in drawn(node).of("prop"):
        rna = p["data"].bl_rna.properties[p["prop"]]
        if rna.type == "FLOAT":
            if rna.unit == "NONE":
                assert rna.precision >= 2, (idname, p["prop"])
            else:                   # Blender's unit display counts the digits before the point too
                value = 12.34 if rna.unit == "LENGTH" else math.radians(12.34)
                shown = bpy.utils.units.to_string("METRIC", rna.unit, value, precision=rna.precision)
                assert shown.startswith("12.34"), (idname, p["prop"], shown)
            if rna.is_array:
                assert p["path"][-1] == "column", (idname, p["prop"])     # X, Y, Z stacked


def test_every_node_type_has_its_own_description():
    docs = [bpy.types.Node.bl_rna_get_subclass(i).description for i in all_idnames()]
    assert all(len(d) > 20 for d in docs), docs
    assert len(set(docs)) == len(docs)


def test_nary_inputs_are_numbered_as_links_come_and_go():
    t = new_tree()
    blend = t.nodes.new(mod("nodes").idname("blend"))
    pts = [t.nodes.new(mod("nodes").idname("point")) for _ in range(3)]
    assert [s.name for s in blend.inputs] == ["Field 1"]
    for p in pts:
        t.links.new(p.outputs[0], blend.inputs[-1])
    assert [s.name for s in blend.inputs] == ["Field 1", "Field 2", "Field 3", "Field 4"]
    t.links.remove(blend.inputs[1].links[0])                  # unlink the middle one
    blend.update()
    assert [s.name for s in blend.inputs] == ["Field 1", "Field 2", "Field 3"]
    assert [s.links[0].from_node for s in blend.inputs[:2]] == [pts[0], pts[2]]
    diff = t.nodes.new(mod("nodes").idname("difference"))
    assert [s.name for s in diff.inputs] == ["Base", "Subtract 1"]
    base = t.nodes.new(mod("nodes").idname("box"))
    t.links.new(base.outputs[0], diff.inputs[0])
    for p in pts:
        t.links.new(p.outputs[0], diff.inputs[-1])
    assert [s.name for s in diff.inputs] == ["Base", "Subtract 1", "Subtract 2", "Subtract 3", "Subtract 4"]
    t.links.remove(diff.inputs[2].links[0])                   # unlink Subtract 2
    diff.update()
    assert [s.name for s in diff.inputs] == ["Base", "Subtract 1", "Subtract 2", "Subtract 3"]
    assert [s.links[0].from_node for s in diff.inputs[:3]] == [base, pts[0], pts[2]]
    t.links.remove(diff.inputs[0].links[0])                   # the base stays, unlinked
    diff.update()
    assert [s.name for s in diff.inputs] == ["Base", "Subtract 1", "Subtract 2", "Subtract 3"]


def test_imported_operators_have_numbered_inputs(example):
    bpy.ops.blobtree_ink.import_json(filepath=example("heart"), preview=False)
    ops = [n for n in bpy.data.node_groups["heart"].nodes if getattr(n, "kind", "") in
           ("blend", "ricci", "union", "intersection", "difference")]
    assert ops
    for n in ops:
        fixed = ["Base"] if n.kind == "difference" else []
        label = "Subtract" if n.kind == "difference" else "Field"
        assert [s.name for s in n.inputs] == fixed + [f"{label} {i}" for i in range(1, len(n.inputs) - len(fixed) + 1)]
        assert not n.inputs[-1].is_linked and all(s.is_linked for s in n.inputs[len(fixed):-1])
