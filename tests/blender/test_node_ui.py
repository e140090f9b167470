"""What an artist sees of BlobTree nodes: numbered n-ary inputs."""
from importlib import import_module

import bpy

PKG = "bl_ext.user_default.blobtree_ink.blobtree_nodes"


def mod(name):
    return import_module(f"{PKG}.{name}")


def new_tree(name="T"):
    return bpy.data.node_groups.new(name, "BlobTreeInkNodeTree")


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
