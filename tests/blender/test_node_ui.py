"""What an artist sees of BlobTree nodes: distinct, described labels; vectors with two
decimals, one component a row; numbered n-ary inputs; errors whole on the node, in the
sidebar and in a tooltip; the Add menu's searchable submenus."""
import math
from importlib import import_module
from types import SimpleNamespace

import blf
import bpy
import pytest

from recording_layout import Layout

PKG = "bl_ext.user_default.blobtree_ink.blobtree_nodes"
SHOW_ERROR = "blobtree_ink.show_node_error"


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


LONG_ERROR = ("the link from 'A node with an unusually long name that no node is wide enough for' is invalid "
              "(a cycle or an incompatible socket)")


def error_lines(rec):
    return [i["text"] for i in rec.of("label") if "box" in i["path"] and i["text"]]


def text_width(text):
    blf.size(0, bpy.context.preferences.ui_styles[0].widget.points)
    return blf.dimensions(0, text)[0]


@pytest.mark.parametrize("width", [140, 190, 400])
def test_the_error_on_a_node_is_whole_and_fits_the_nodes_width(width):
    wrap = mod("wrap")
    node = new_tree().nodes.new(mod("nodes").idname("blend"))
    node.width = width
    node.set_error(LONG_ERROR)
    lines = error_lines(drawn(node))
    assert "".join(lines).replace(" ", "") == LONG_ERROR.replace(" ", "")    # nothing cut off
    assert all(text_width(line) <= wrap.node_text_width(bpy.context, width) for line in lines), lines
    short = "needs at least 1 linked input"
    node.set_error(short)
    assert " ".join(error_lines(drawn(node))) == short


def test_a_narrower_node_wraps_into_more_lines():
    node = new_tree().nodes.new(mod("nodes").idname("blend"))
    node.set_error(LONG_ERROR)
    counts = []
    for width in (400, 190, 140):
        node.width = width
        counts.append(len(error_lines(drawn(node))))
    assert counts[0] < counts[1] < counts[2]


def test_the_error_icons_tooltip_is_the_whole_error_and_a_click_selects_the_node():
    t = new_tree()
    node, other = (t.nodes.new(mod("nodes").idname("blend")) for _ in range(2))
    node.set_error(LONG_ERROR)
    (icon,) = [i for i in drawn(node).of("operator") if i["idname"] == SHOW_ERROR]
    assert icon["icon"] == "ERROR"
    op = mod("show_node_error").BLOBTREE_INK_OT_show_node_error
    assert op.description(bpy.context, icon["props"]) == f"{node.name}: {LONG_ERROR}"
    other.select = True
    assert bpy.ops.blobtree_ink.show_node_error(tree_name=t.name, node_name=node.name) == {"FINISHED"}
    assert t.nodes.active == node and node.select and not other.select
    node.set_error("")
    assert op.description(bpy.context, icon["props"]) is None      # then the operator's own docstring


def sidebar(tree, active, width=300):
    context = SimpleNamespace(space_data=SimpleNamespace(tree_type=tree.bl_idname, edit_tree=tree),
                              active_node=active, region=SimpleNamespace(width=width),
                              preferences=bpy.context.preferences)
    panel = mod("panels").NODE_PT_blobtree_ink_errors
    assert panel.poll(context)
    rec = Layout()
    panel.draw(SimpleNamespace(layout=rec), context)
    return rec


def test_the_sidebar_shows_the_active_nodes_whole_error_and_lists_the_others():
    wrap = mod("wrap")
    t = new_tree()
    blend, out, point = (t.nodes.new(mod("nodes").idname(k) if k != "output" else "BlobTreeInkOutputNode")
                         for k in ("blend", "output", "point"))
    t.links.new(blend.outputs[0], out.inputs[0])
    assert mod("compile").tree_model_or_none(t) is None
    assert blend.error == "needs at least 1 linked input"
    out.set_error(LONG_ERROR)
    rec = sidebar(t, out, width=260)
    lines = error_lines(rec)
    assert "".join(lines).replace(" ", "") == LONG_ERROR.replace(" ", "") and len(lines) > 2
    assert all(text_width(line) <= wrap.region_text_width(bpy.context, 260) for line in lines)
    (others,) = [i for i in rec.of("operator") if i["text"] == blend.name]
    assert others["idname"] == SHOW_ERROR and others["props"].node_name == blend.name and others["props"].frame
    # a node without an error: the others are still listed
    rec = sidebar(t, point)
    assert not error_lines(rec) and {i["text"] for i in rec.of("operator")} == {blend.name, out.name}
    for n in (blend, out):
        n.set_error("")
    assert [i["text"] for i in sidebar(t, point).of("label")] == ["No node has an error"]
    other_tree = SimpleNamespace(space_data=SimpleNamespace(tree_type="ShaderNodeTree", edit_tree=t))
    assert not mod("panels").NODE_PT_blobtree_ink_errors.poll(other_tree)


def test_the_blobtree_ink_tab_names_the_broken_nodes_at_its_top():
    """The BlobTree Ink tab (3D viewport and node editor), where an artist looks first,
    starts with the tree's node errors: each node a button that selects and frames it,
    its whole error below it; once mended, nothing of it is left."""
    panels = import_module("bl_ext.user_default.blobtree_ink.operators.panels")
    t = new_tree()
    blend, out = t.nodes.new(mod("nodes").idname("blend")), t.nodes.new("BlobTreeInkOutputNode")
    blend.label = "Body"
    t.links.new(blend.outputs[0], out.inputs[0])
    assert mod("compile").tree_model_or_none(t) is None and blend.error
    space = SimpleNamespace(type="NODE_EDITOR", tree_type=t.bl_idname, node_tree=t, edit_tree=t)
    for panel, context in (
            (panels.NODE_PT_blobtree_ink, SimpleNamespace(space_data=space)),
            (panels.VIEW3D_PT_blobtree_ink, SimpleNamespace(space_data=space, active_object=None))):
        def draw():
            rec = Layout()
            ctx = SimpleNamespace(region=SimpleNamespace(width=300), preferences=bpy.context.preferences,
                                  scene=bpy.context.scene, **vars(context))
            panel.draw(SimpleNamespace(layout=rec), ctx)
            return rec
        rec = draw()
        alert = [i for i in rec.of("label") if i["alert"] and i["icon"] == "ERROR"]
        assert alert and alert[0]["text"].startswith("1 node with an error")
        assert rec.items.index(alert[0]) < min(rec.items.index(i) for i in rec.of("prop"))   # above the settings
        (button,) = [i for i in rec.of("operator") if i["idname"] == SHOW_ERROR and i["text"] == "Body"]
        assert button["props"].node_name == blend.name and button["props"].frame
        assert "".join(error_lines(rec)).replace(" ", "") == blend.error.replace(" ", "")
        blend.set_error("")
        assert not [i for i in draw().items if i.get("alert")]
        blend.set_error("needs at least 1 linked input")


def test_the_blobtree_ink_tab_says_a_new_tree_needs_a_model_output():
    """A new tree has no node: the tab says what it needs; with a Model Output it does not."""
    panels = import_module("bl_ext.user_default.blobtree_ink.operators.panels")
    t = new_tree()
    space = SimpleNamespace(type="NODE_EDITOR", tree_type=t.bl_idname, node_tree=t, edit_tree=t)
    ctx = SimpleNamespace(space_data=space, region=SimpleNamespace(width=300), preferences=bpy.context.preferences,
                          scene=bpy.context.scene)

    def alerts():
        rec = Layout()
        panels.NODE_PT_blobtree_ink.draw(SimpleNamespace(layout=rec), ctx)
        return " ".join(i["text"] for i in rec.of("label") if i["alert"])
    assert alerts().replace(" ", "") == panels.NO_OUTPUT.replace(" ", "") and "Model Output" in alerts()
    t.nodes.new("BlobTreeInkOutputNode")
    assert "no Model Output" not in alerts()


def test_the_add_menu_is_searchable_and_lists_every_node_type():
    menu = mod("menu")
    assert menu.draw_in_node_add_menu in bpy.types.NODE_MT_add._dyn_ui_initialize()
    assert "SEARCH_ON_KEY_PRESS" in bpy.types.NODE_MT_add.bl_options
    add = getattr(bpy.types, "NODE_MT_blobtree_ink_add")
    assert "SEARCH_ON_KEY_PRESS" in add.bl_options
    blobtree = SimpleNamespace(space_data=SimpleNamespace(tree_type="BlobTreeInkNodeTree"))
    shader = SimpleNamespace(space_data=SimpleNamespace(tree_type="ShaderNodeTree"))
    rec = Layout()
    menu.draw_in_node_add_menu(SimpleNamespace(layout=rec), blobtree)
    assert [i["menu"] for i in rec.of("menu_contents")] == ["NODE_MT_blobtree_ink_add"]
    rec = Layout()
    menu.draw_in_node_add_menu(SimpleNamespace(layout=rec), shader)
    assert rec.items == []
    rec = Layout()
    add.draw(SimpleNamespace(layout=rec), blobtree)
    sub_names = [i["menu"] for i in rec.of("menu")]
    labels = [getattr(bpy.types, m).bl_label for m in sub_names]
    assert labels == ["Primitives", "Operators", "Warps", "Output"]
    listed = []
    for m in sub_names:
        sub = getattr(bpy.types, m)
        assert sub.poll(blobtree) and not sub.poll(shader)
        rec = Layout()
        sub.draw(SimpleNamespace(layout=rec, node_idnames=sub.node_idnames), blobtree)
        for item in rec.of("operator"):
            assert item["idname"] == "node.add_node" and item["props"].use_transform
            assert item["text"] == bpy.types.Node.bl_rna_get_subclass(item["props"].type).name
            listed.append(item["props"].type)
    assert sorted(listed) == sorted(all_idnames()) and len(listed) == 15
    import nodeitems_utils
    assert not nodeitems_utils.has_node_categories(blobtree)          # no second, legacy Add menu


def test_the_group_tab_shows_no_sockets_colour_or_width_of_a_group():
    """A model has no sockets of its own and is no node group: Blender's Group tab shows
    its name and description only (no Group Sockets panel, colour tag or node width),
    while a shader node group keeps them."""
    panel = bpy.types.NODE_PT_node_tree_properties

    def props(tree):
        rec = Layout()
        panel.draw(SimpleNamespace(layout=rec), SimpleNamespace(space_data=SimpleNamespace(edit_tree=tree)))
        return [i["prop"] for i in rec.of("prop")]
    tree = new_tree()
    assert tree.bl_use_group_interface is False
    assert props(tree) == ["name", "description"]
    shader = bpy.data.node_groups.new("G", "ShaderNodeTree")
    assert shader.bl_use_group_interface and "color_tag" in props(shader)
