"""Models that move: keyframed and driven node values, and objects the nodes follow
(with their parents and constraints), at the scene's frame; the preview follows."""
import bpy

import numpy as np
import pytest
from moving_scene import moving_spheres


def mod(ext, name):
    from importlib import import_module
    return import_module(f"{ext.__name__}.{name}")


def two_spheres(example):
    bpy.ops.blobtree_ink.import_json(filepath=example("two_spheres"), preview=True)
    tree = bpy.data.node_groups["two_spheres"]
    a, b = [n for n in tree.nodes if getattr(n, "kind", "") == "point"]
    return tree, a, b


def test_keyframed_node_values_take_effect_at_each_frame(ext, example):
    """A Point's radius and the tree's iso, keyed at frames 1 and 11 (Blender's smooth
    interpolation: halfway at frame 6), compile to those values at each frame."""
    comp = mod(ext, "blobtree_nodes.compile")
    tree, a, b = two_spheres(example)
    sc = bpy.context.scene
    a.radius, tree.iso = 1.0, 0.5
    a.keyframe_insert("radius", frame=1)
    tree.keyframe_insert("iso", frame=1)
    a.radius, tree.iso = 2.0, 0.3
    a.keyframe_insert("radius", frame=11)
    tree.keyframe_insert("iso", frame=11)
    for frame, radius, iso in ((1, 1.0, 0.5), (6, 1.5, 0.4), (11, 2.0, 0.3), (3, None, None)):
        sc.frame_set(frame)
        model = comp.compile_tree(tree)
        got = model.root.children[0].radius
        if radius is None:                                      # between: strictly between the keys
            assert 1.0 < got < 1.5 and 0.4 < model.iso < 0.5
        else:
            assert got == pytest.approx(radius, abs=1e-6) and model.iso == pytest.approx(iso, abs=1e-6)
    assert a.radius == pytest.approx(model.root.children[0].radius)   # the node shows the frame's value


def test_a_driven_value_follows_its_driver(ext, example):
    comp = mod(ext, "blobtree_nodes.compile")
    tree, a, b = two_spheres(example)
    sc = bpy.context.scene
    ctl = bpy.data.objects.new("Control", None)
    sc.collection.objects.link(ctl)
    fc = a.driver_add("radius")
    var = fc.driver.variables.new()
    var.name, var.type = "z", "TRANSFORMS"
    var.targets[0].id = ctl
    var.targets[0].transform_type = "LOC_Z"
    fc.driver.expression = "0.5 + z * 0.25 + frame * 0"
    ctl.location.z = 2.0
    sc.frame_set(3)
    assert comp.compile_tree(tree).root.children[0].radius == pytest.approx(1.0)
    ctl.location.z = 4.0
    ctl.keyframe_insert("location", index=2, frame=5)
    sc.frame_set(5)
    assert comp.compile_tree(tree).root.children[0].radius == pytest.approx(1.5)
    fc.driver.expression = "__import__('os').getcwd()"            # no builtins: a named error, nothing run
    anim = mod(ext, "blobtree_nodes.animation")
    with pytest.raises(anim.DriverError, match="cannot evaluate"):
        anim.apply(tree, 5, bpy.context.evaluated_depsgraph_get())


def test_the_preview_follows_a_driving_empty_across_a_frame_change(ext, example):
    changes = mod(ext, "blobtree_nodes.changes")
    tree, a, b = two_spheres(example)
    sc = bpy.context.scene
    empty = bpy.data.objects.new("Driver", None)
    sc.collection.objects.link(empty)
    b.center_object = empty
    empty.location = (0.0, 0.0, 0.0)
    empty.keyframe_insert("location", frame=1)
    empty.location = (3.0, 0.0, 0.0)
    empty.keyframe_insert("location", frame=21)
    sc.frame_set(1)
    changes.run_due(float("inf"))
    edits = changes.edits(tree)
    xs1 = np.array([v.co.x for v in tree.preview_object.data.vertices])
    sc.frame_set(21)
    assert tree.name in changes.pending()                        # a move schedules the preview ...
    assert changes.edits(tree) == edits                          # ... and is not an edit
    changes.run_due(float("inf"))
    xs21 = np.array([v.co.x for v in tree.preview_object.data.vertices])
    assert xs21.max() > xs1.max() + 2.5                          # the sphere moved with the empty
    empty.location.y = 1.0                                        # dragging it (no frame change)
    bpy.context.view_layer.update()
    assert tree.name in changes.pending()


def test_the_preview_keeps_up_with_playback(ext, example, monkeypatch):
    """Every frame of playback is a change and pushes the quiet period back, but a
    rebuild comes due at most MAX_WAIT after the first change it has not shown (the
    changes' clock is a fake one: frames an eighth of a second apart)."""
    changes = mod(ext, "blobtree_nodes.changes")
    tree, empty = moving_spheres(example)                        # the Empty keyed x = 0 at frame 1, 2 at frame 5
    empty.location = (6.0, 0.0, 0.0)
    empty.keyframe_insert("location", frame=21)                  # ... and on to 6 at frame 21: it moves every frame
    sc = bpy.context.scene
    sc.frame_set(1)
    changes.run_due(float("inf"))
    x1 = max(v.co.x for v in tree.preview_object.data.vertices)
    now = [100.0]
    monkeypatch.setattr(changes, "_clock", lambda: now[0])
    sc.frame_set(2)                                              # playback's first frame
    assert changes.pending()[tree.name] == 100.0 + changes.DELAY
    for f in range(3, 21):                                       # the next frames come faster than the quiet period
        now[0] += 0.125
        sc.frame_set(f)
        assert changes.run_due() == ([tree.name] if now[0] >= 100.0 + changes.MAX_WAIT else [])
        if tree.name not in changes.pending():
            break
    assert now[0] == 100.0 + changes.MAX_WAIT                    # rebuilt once the longest wait was up
    x = max(v.co.x for v in tree.preview_object.data.vertices)
    assert x == pytest.approx(x1 + empty.matrix_world.translation.x, abs=0.1)     # the preview shows that frame
    now[0] += 0.125
    sc.frame_set(f + 1)                                          # the next change starts a new wait
    assert changes.pending()[tree.name] == pytest.approx(now[0] + changes.DELAY)


def test_a_slow_preview_waits_longer_during_playback(ext, example, monkeypatch):
    """A rebuild that takes long (seconds of the changes' fake clock) makes the longest
    wait WAIT_PER_REBUILD times its length: rebuilding takes at most a third of the time."""
    changes = mod(ext, "blobtree_nodes.changes")
    tree, empty = moving_spheres(example)
    now = [100.0]
    monkeypatch.setattr(changes, "_clock", lambda: now[0])
    rebuild = changes._rebuild[0]

    def slow(t):                                                 # the rebuild takes 0.75 s
        now[0] += 0.75
        return rebuild(t)
    monkeypatch.setattr(changes, "_rebuild", [slow])
    bpy.context.scene.frame_set(2)
    changes.run_due(float("inf"))                                # one rebuild, 0.75 s long
    start = now[0]
    for f in range(3, 5):
        now[0] += 0.125
        bpy.context.scene.frame_set(f)
    assert changes.pending()[tree.name] == now[0] + changes.DELAY    # a short wait: as ever
    for f in range(5, 30):                                       # playback goes on
        now[0] += 0.125
        bpy.context.scene.frame_set(f)
    assert changes.pending()[tree.name] == start + 0.125 + changes.WAIT_PER_REBUILD * 0.75


def test_exporting_writes_the_model_as_it_is_at_the_current_frame(ext, example, tmp_path):
    """A keyed radius and a centre that follows a keyed Empty: the JSON exported at a
    frame holds that frame's values."""
    import json
    tree, a, b = two_spheres(example)
    sc = bpy.context.scene
    a.radius = 1.0
    a.keyframe_insert("radius", frame=1)
    a.radius = 3.0
    a.keyframe_insert("radius", frame=21)
    empty = bpy.data.objects.new("Driver", None)
    sc.collection.objects.link(empty)
    b.center_object = empty
    empty.location = (0.0, 0.0, 0.0)
    empty.keyframe_insert("location", frame=1)
    empty.location = (4.0, 0.0, 0.0)
    empty.keyframe_insert("location", frame=21)
    for frame in (1, 11, 21):
        sc.frame_set(frame)
        out = tmp_path / f"at_{frame}.json"
        assert bpy.ops.blobtree_ink.export_json(filepath=str(out), tree_name=tree.name) == {"FINISHED"}
        root = json.loads(out.read_text())["root"]
        radius, centre = root["children"][0]["radius"], root["children"][1]["center"]
        want_r = {1: 1.0, 11: 2.0, 21: 3.0}[frame]
        want_x = {1: 0.0, 11: 2.0, 21: 4.0}[frame]
        assert radius == pytest.approx(want_r, abs=1e-5) and centre[0] == pytest.approx(want_x, abs=1e-5), frame


def test_the_sidebar_switches_the_preview_off_and_on(ext, example):
    """The 3D sidebar draws the tree's Live Preview toggle (with its resolution, inactive
    while it is off): switched off, the preview mesh goes and the ink is seen alone;
    switched on, it comes back."""
    from types import SimpleNamespace

    from recording_layout import Layout
    changes = mod(ext, "blobtree_nodes.changes")
    tree, a, b = two_spheres(example)
    changes.run_due(float("inf"))
    assert tree.preview_object is not None
    panel = mod(ext, "operators.panels").VIEW3D_PT_blobtree_ink
    rec = Layout()
    panel.draw(SimpleNamespace(layout=rec), bpy.context)
    drawn = {(i["data"], i["prop"]): i for i in rec.of("prop")}
    assert (tree, "show_preview") in drawn and (tree, "preview_resolution") in drawn
    tree.show_preview = False                                    # the artist's click
    changes.run_due(float("inf"))
    assert tree.preview_object is None and not [o for o in bpy.data.objects if o.name.startswith("two_spheres Preview")]
    tree.show_preview = True
    changes.run_due(float("inf"))
    assert tree.preview_object is not None and len(tree.preview_object.data.vertices) > 100


def test_the_sidebar_keeps_a_tree_whose_preview_is_off_and_reaches_it(ext, example):
    """Switching a tree's preview off (its object goes) leaves the 3D sidebar on that tree,
    not on another; Other BlobTrees reaches a tree without preview or ink (nothing to
    select), and requests without a tree name work on the tree the sidebar shows."""
    from types import SimpleNamespace

    from recording_layout import Layout
    changes = mod(ext, "blobtree_nodes.changes")
    panel = mod(ext, "operators.panels").VIEW3D_PT_blobtree_ink

    def shown():
        rec = Layout()
        panel.draw(SimpleNamespace(layout=rec), bpy.context)
        others = [i["props"].tree_name for i in rec.of("operator") if i["idname"] == "blobtree_ink.activate_tree"]
        return rec.of("label")[0]["text"], others

    bpy.ops.blobtree_ink.import_json(filepath=example("pear"), preview=True)
    tree, a, b = two_spheres(example)
    changes.run_due(float("inf"))
    assert bpy.context.view_layer.objects.active == tree.preview_object
    assert shown() == ("two_spheres", ["pear"])
    tree.show_preview = False                                    # the artist's click in the sidebar
    changes.run_due(float("inf"))
    assert bpy.context.view_layer.objects.active is None and shown() == ("two_spheres", ["pear"])
    assert bpy.ops.blobtree_ink.activate_tree(tree_name="pear") == {"FINISHED"}
    pear = bpy.data.node_groups["pear"]
    assert bpy.context.view_layer.objects.active == pear.preview_object and shown() == ("pear", ["two_spheres"])
    assert bpy.ops.blobtree_ink.activate_tree(tree_name="two_spheres") == {"FINISHED"}    # no preview, no ink
    assert bpy.context.view_layer.objects.active is None and not pear.preview_object.select_get()
    assert shown() == ("two_spheres", ["pear"])
    tree.ink.grid_resolution = 12
    assert bpy.ops.blobtree_ink.illustrate(request="OUTLINES") == {"FINISHED"}          # no tree named
    assert bpy.data.objects.get("two_spheres Ink") is not None and bpy.data.objects.get("pear Ink") is None


def test_a_followed_object_deleted_in_the_viewport_is_named_on_its_node(ext, example):
    """Delete in the viewport unlinks the Empty from the scene while the node's pointer
    keeps it: the tree does not compile, the node says which object is gone and why, and
    the preview keeps its last good shape; linked again, all is well."""
    changes = mod(ext, "blobtree_nodes.changes")
    comp = mod(ext, "blobtree_nodes.compile")
    tree, empty = moving_spheres(example)
    follower = next(n for n in tree.nodes if getattr(n, "center_object", None) is empty)
    changes.run_due(float("inf"))
    shape = [tuple(v.co) for v in tree.preview_object.data.vertices]
    empty.select_set(True)                                       # a selection updates the scene ...
    bpy.context.view_layer.update()
    assert tree.name not in changes.pending()                    # ... and rebuilds nothing
    bpy.context.scene.collection.objects.unlink(empty)
    bpy.context.view_layer.update()                              # the delete reaches the depsgraph
    assert tree.name in changes.pending()                        # ... which schedules the tree
    changes.run_due(float("inf"))
    assert "'Driver' it follows was deleted" in follower.error   # the node says so
    assert [tuple(v.co) for v in tree.preview_object.data.vertices] == shape
    with pytest.raises(comp.TreeError, match="the object 'Driver' it follows was deleted"):
        comp.compile_tree(tree)
    bpy.context.scene.collection.objects.link(empty)             # back (an undo)
    bpy.context.view_layer.update()
    assert tree.name in changes.pending()
    changes.run_due(float("inf"))
    assert follower.error == "" and comp.tree_model_or_none(tree) is not None
