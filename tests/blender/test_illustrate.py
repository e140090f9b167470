"""The Illustrate operator in background mode (execute runs the stepper to the end)."""
import bpy
import numpy as np
import pytest
from ink_layers import ink


def test_trace_outlines_writes_the_strokes(example):
    bpy.ops.blobtree_ink.import_json(filepath=example("pear"), preview=False)
    tree = bpy.data.node_groups["pear"]
    tree.ink.grid_resolution = 12
    assert bpy.ops.blobtree_ink.illustrate(tree_name="pear", request="OUTLINES") == {"FINISHED"}
    layers = ink("pear")
    assert len(layers["Silhouette"]) >= 1 and len(layers["Crease"]) >= 1
    # INVOKE_DEFAULT in background runs execute; running again keeps one object
    assert bpy.ops.blobtree_ink.illustrate("INVOKE_DEFAULT", tree_name="pear") == {"FINISHED"}
    assert len([o for o in bpy.data.objects if o.type == "GREASEPENCIL"]) == 1
    from importlib import import_module
    run = import_module("bl_ext.user_default.blobtree_ink.operators.illustrate").last_run
    assert run["state"] == "done" and run["fraction"] == 1.0 and run["stage"] == "done" and run["iterations"] > 0


def test_place_strokes_stay_in_the_selected_objects_bounds_else_cover_the_model(example):
    bpy.ops.blobtree_ink.import_json(filepath=example("pear"), preview=False)
    tree = bpy.data.node_groups["pear"]
    tree.ink.grid_resolution = 12
    tree.ink.hatching = True
    tree.ink.stipples = True
    marker = bpy.data.objects.new("Region", bpy.data.meshes.new("Region"))
    bpy.context.scene.collection.objects.link(marker)
    marker.data.from_pydata([(-1, -1, -1), (1, 1, 1)], [], [])
    marker.location, marker.scale = (-0.6, -0.5, -0.2), (0.4, 0.4, 0.4)
    bpy.context.view_layer.update()
    marker.select_set(True)
    assert bpy.ops.blobtree_ink.illustrate(tree_name="pear", request="PLACE_STROKES") == {"FINISHED"}
    layers = ink("pear")
    placed = layers["Hatching"] + layers["Stipples"]
    assert placed
    pts = np.array([p.position for s in placed for p in s.points])
    assert np.all(np.abs(pts - marker.location) <= 0.4 + 1e-5)       # inside the marker's box
    marker.select_set(False)                                          # no selection: the whole model
    assert bpy.ops.blobtree_ink.illustrate(tree_name="pear", request="PLACE_STROKES") == {"FINISHED"}
    layers = ink("pear")
    pts = np.array([p.position for s in layers["Hatching"] + layers["Stipples"] for p in s.points])
    assert np.ptp(pts[:, 2]) > 1.0 and len(layers["Hatching"]) > len([s for s in placed if len(s.points) > 1])


def test_single_stroke_from_the_cursor(example):
    bpy.ops.blobtree_ink.import_json(filepath=example("sphere"), preview=False)
    r = 0.4543
    bpy.context.scene.cursor.location = (0.0, -r, 0.0)
    bpy.data.node_groups["sphere"].ink.grid_resolution = 10
    assert bpy.ops.blobtree_ink.illustrate(tree_name="sphere", request="SINGLE_STROKE") == {"FINISHED"}
    strokes = ink("sphere")["Single Strokes"]
    assert len(strokes) == 1 and len(strokes[0].points) > 5
    pts = np.array([p.position for p in strokes[0].points])
    assert np.abs(np.linalg.norm(pts, axis=1) - r).max() < 1e-3


def test_a_broken_tree_is_reported_and_nothing_is_drawn(example):
    bpy.ops.blobtree_ink.import_json(filepath=example("pear"), preview=False)
    tree = bpy.data.node_groups["pear"]
    belly = [n for n in tree.nodes if n.label == "belly"][0]
    belly.radius = 0.0
    with pytest.raises(RuntimeError, match="Radius must be > 0"):
        bpy.ops.blobtree_ink.illustrate(tree_name="pear")
    assert not [o for o in bpy.data.objects if o.type == "GREASEPENCIL"]
    with pytest.raises(RuntimeError, match="no BlobTree node tree named 'nope'"):
        bpy.ops.blobtree_ink.illustrate(tree_name="nope")


def test_presets_set_the_tree_settings(example):
    bpy.ops.blobtree_ink.import_json(filepath=example("sphere"), preview=False)
    tree = bpy.data.node_groups["sphere"]
    assert bpy.ops.blobtree_ink.apply_preset(tree_name="sphere", preset="STIPPLED") == {"FINISHED"}
    assert tree.ink.stipples and not tree.ink.hatching
    assert bpy.ops.blobtree_ink.apply_preset(tree_name="sphere", preset="HATCHED") == {"FINISHED"}
    assert tree.ink.hatching and not tree.ink.stipples and tree.ink.grid_resolution == 20


def test_every_preset_maps_to_its_style_and_back(ext, example):
    from importlib import import_module
    ST = import_module(f"{ext.__name__}.strokes.style")
    settings = import_module(f"{ext.__name__}.blobtree_nodes.settings")
    bpy.ops.blobtree_ink.import_json(filepath=example("sphere"), preview=False)
    tree = bpy.data.node_groups["sphere"]
    for name, style in ST.STYLES.items():
        key = name.upper().replace("-", "_")
        assert bpy.ops.blobtree_ink.apply_preset(tree_name="sphere", preset=key) == {"FINISHED"}
        got = settings.style_of(tree.ink)
        for f in settings.STYLE_PROPS:
            want, have = getattr(style, f), getattr(got, f)
            want, have = (tuple(want), tuple(have)) if f == "hatch_axis" else (want, have)
            assert have == pytest.approx(want, rel=1e-6) if not isinstance(want, str) else have == want, (name, f)
        assert got.resolved_weights() == pytest.approx(style.resolved_weights(), rel=1e-6)
    tree.ink.weights = "CUSTOM"
    tree.ink.w_cohesion = 2.5
    assert settings.style_of(tree.ink).resolved_weights()["cohesion"] == 2.5
    tree.ink.shade_lower, tree.ink.shade_upper = 0.9, 0.1
    with pytest.raises(RuntimeError, match=r"shade_lower \(0.9\) must be below shade_upper \(0.1\)"):
        bpy.ops.blobtree_ink.illustrate(tree_name="sphere")
    assert not [o for o in bpy.data.objects if o.type == "GREASEPENCIL"]


def test_a_flow_field_saved_before_the_diagonal_field_reads_as_it_was_saved(example):
    """The flow fields keep the numbers files saved them with (the diagonal field is
    numbered after them): a value stored as 0..5 reads as the field it was then."""
    bpy.ops.blobtree_ink.import_json(filepath=example("sphere"), preview=False)
    ink = bpy.data.node_groups["sphere"].ink
    assert ink.cross_field == "DIAGONAL"                                  # the default of a new tree
    for number, field in enumerate(("DIR1", "DIR2", "CONTOUR", "AXIS", "LEVEL", "STRAIGHT")):
        ink["hatch_field"] = ink["cross_field"] = number                  # as a saved file holds them
        assert (ink.hatch_field, ink.cross_field) == (field, field)


def test_place_strokes_uses_the_tree_style_and_the_scene_sun(example):
    bpy.ops.blobtree_ink.import_json(filepath=example("sphere"), preview=False)
    tree = bpy.data.node_groups["sphere"]
    tree.ink.grid_resolution = 12
    tree.ink.hatching, tree.ink.chains, tree.ink.short = True, True, True
    tree.ink.cross_hatching = False
    sun = bpy.data.objects.new("Sun", bpy.data.lights.new("Sun", "SUN"))
    bpy.context.scene.collection.objects.link(sun)
    sun.rotation_euler = (0.0, np.pi / 2, 0.0)        # its +Z axis (towards the light) is +x
    cam = bpy.data.objects.new("Cam", bpy.data.cameras.new("Cam"))
    bpy.context.scene.collection.objects.link(cam)
    bpy.context.scene.camera = cam
    cam.location = (0.0, -4.0, 0.0)
    assert bpy.ops.blobtree_ink.illustrate(tree_name="sphere", request="PLACE_STROKES") == {"FINISHED"}
    layers = ink("sphere")
    assert layers["Hatching"] and layers["Chains"] and layers["Short Strokes"]
    pts = np.array([p.position for s in layers["Hatching"] + layers["Short Strokes"] for p in s.points])
    # the ink (n.L under the highlight threshold, Shade Upper 0.7) is on the side away from the sun (-x)
    assert pts[:, 0].max() < 0.71 * 0.4543 and pts[:, 0].min() < -0.4
    radii = np.array([p.radius for s in layers["Hatching"] for p in s.points])
    assert radii.min() < 0.8 * radii.max()          # width follows the light


def test_ink_layers_clears_one_layer_at_this_frame(example):
    """Ink Layers has a clear button per layer, greyed out where the layer is empty: it
    removes that layer's strokes at this frame (one undo step); the other layers stay.
    The sidebar's "Last run" then says the ink changed since the run."""
    from recording_layout import Layout
    panels = __import__("bl_ext.user_default.blobtree_ink.operators.panels", fromlist=["x"])
    bpy.ops.blobtree_ink.import_json(filepath=example("pear"), preview=False)
    tree = bpy.data.node_groups["pear"]
    tree.ink.grid_resolution = 12
    assert bpy.ops.blobtree_ink.illustrate(tree_name="pear", preset="STIPPLED") == {"FINISHED"}
    before = ink("pear")
    assert len(before["Stipples"]) > 50 and before["Silhouette"]
    rec = Layout()
    panels._draw_layers(rec, tree)
    clears = {i["props"].layer: i for i in rec.of("operator") if i["idname"] == "blobtree_ink.clear_layer"}
    assert set(clears) == {layer.name for layer in bpy.data.objects["pear Ink"].data.layers}
    assert clears["Stipples"]["props"].object_name == "pear Ink"
    enabled = {k for k, i in clears.items() if i["enabled"]}
    assert enabled == {k for k, v in before.items() if v} and "Stipples" in enabled and "Hatching" not in enabled
    run = Layout()
    panels._draw_last_run(run, bpy.context, tree)
    shown = [i["text"] for i in run.of("label")]
    assert shown[0] == "Last run: done" and shown[1].startswith("Strokes: ")
    assert bpy.ops.blobtree_ink.clear_layer(object_name="pear Ink", layer="Stipples") == {"FINISHED"}
    after = ink("pear")
    assert after["Stipples"] == [] and len(after["Silhouette"]) == len(before["Silhouette"])
    # the sidebar's figures are the run's, no longer the ink's: it says so, not the old count
    run = Layout()
    panels._draw_last_run(run, bpy.context, tree)
    assert [i["text"] for i in run.of("label")] == ["Last run: done", "Undone or edited since"]
    assert bpy.ops.blobtree_ink.illustrate(tree_name="pear", preset="STIPPLED") == {"FINISHED"}
    run = Layout()
    panels._draw_last_run(run, bpy.context, tree)
    shown = [i["text"] for i in run.of("label")]
    assert shown[0] == "Last run: done" and shown[1].startswith("Strokes: ") and "frame" not in shown[1]
    bpy.context.scene.frame_set(7)                             # on another frame: the count says where it was drawn
    run = Layout()
    panels._draw_last_run(run, bpy.context, tree)
    assert [i["text"] for i in run.of("label")][1].endswith(" (drawn on frame 1)")
    bpy.context.scene.frame_set(1)
    figures = panels.last_run
    kept = dict(figures)
    figures["state"] = "undone"                                 # a run an undo took back drew nothing
    run = Layout()
    panels._draw_last_run(run, bpy.context, tree)
    assert [i["text"] for i in run.of("label")] == ["Last run: undone", "Nothing drawn"]
    figures.clear()
    figures.update(kept)
    with pytest.raises(RuntimeError, match="no ink layer 'Nope' on 'pear Ink'"):
        bpy.ops.blobtree_ink.clear_layer(object_name="pear Ink", layer="Nope")


def test_a_run_from_the_camera_says_so_in_a_viewport_that_looks_from_elsewhere(ext):
    """Drawn for the scene camera (From Camera) while the viewport looks from elsewhere,
    the ink lies off the view's outlines: the report says how to see it as drawn."""
    from types import SimpleNamespace
    hint = __import__(f"{ext.__name__}.operators.illustrate", fromlist=["x"]).camera_hint
    view = lambda p: SimpleNamespace(space_data=SimpleNamespace(region_3d=SimpleNamespace(view_perspective=p)))
    assert hint(view("PERSP"), True) == "; drawn as the scene camera sees it (Numpad 0 looks through it)"
    assert hint(view("CAMERA"), True) == hint(view("PERSP"), False) == ""
    assert hint(SimpleNamespace(space_data=None), True) == ""                  # not from a 3D viewport


def test_a_running_illustration_stops_only_for_a_change_of_the_model(ext, example):
    """A run stops when the tree's model changes, not for every counted edit of the tree
    (a Live Preview switched, a node moved, a setting of the run): the tree's document is
    compared with the one the run started from."""
    comp = __import__(f"{ext.__name__}.blobtree_nodes.compile", fromlist=["x"])
    bpy.ops.blobtree_ink.import_json(filepath=example("pear"), preview=True)
    tree = bpy.data.node_groups["pear"]
    doc = comp.tree_document(tree)[0]
    tree.show_preview = False
    tree.ink.grid_resolution = 48
    tree.nodes[0].location.x += 100.0
    assert comp.same_model(tree, doc)
    node = next(n for n in tree.nodes if hasattr(n, "radius"))
    r0 = node.radius
    node.radius = r0 + 0.1
    assert not comp.same_model(tree, doc)
    node.radius = r0
    assert comp.same_model(tree, doc)
    for link in list(tree.links):
        tree.links.remove(link)
    assert not comp.same_model(tree, doc)                         # a broken tree is a change


def test_a_tree_error_in_the_sidebar_moves_no_request_or_look_button(ext, example):
    """The sidebar's requests and looks come first, and a tree's error below them: an
    error that appears while the artist reaches for a look leaves the look where it was
    (the settings below move instead). In a node, the error comes below its values."""
    from types import SimpleNamespace

    from recording_layout import Layout
    panels = __import__(f"{ext.__name__}.operators.panels", fromlist=["x"])
    preview = __import__(f"{ext.__name__}.blobtree_nodes.preview", fromlist=["x"])
    bpy.ops.blobtree_ink.import_json(filepath=example("pear"), preview=True)
    tree = bpy.data.node_groups["pear"]
    context = SimpleNamespace(space_data=None, active_object=tree.preview_object, region=SimpleNamespace(width=300),
                              preferences=bpy.context.preferences, scene=bpy.context.scene)

    def sidebar():
        rec = Layout()
        panels.VIEW3D_PT_blobtree_ink.draw(SimpleNamespace(layout=rec), context)
        return [(i["kind"], i.get("idname"), i.get("text")) for i in rec.items if i["kind"] in ("label", "operator")]
    fine = sidebar()
    belly = [n for n in tree.nodes if n.label == "belly"][0]
    node_context = SimpleNamespace(region=SimpleNamespace(width=300), preferences=bpy.context.preferences)

    def node():
        rec = Layout()
        belly.draw_buttons(node_context, rec)
        return [(i["kind"], i.get("prop") or i.get("text")) for i in rec.items if i["kind"] in ("prop", "label")]
    values = node()
    belly.radius = 0.0
    assert not preview.rebuild(tree) and belly.error            # the node's error is marked
    broken = sidebar()
    looks = [k for k, (kind, idname, _) in enumerate(fine) if idname == "blobtree_ink.illustrate"]
    assert len(looks) == 4 + len(panels.PRESETS)
    assert broken[:looks[-1] + 1] == fine[:looks[-1] + 1]       # every request and look, as before
    error = next(k for k, (kind, _, text) in enumerate(broken) if kind == "label" and "with an error" in str(text))
    assert error > looks[-1]
    # in the node: its values where they were, then the error
    shown = node()
    assert shown[:len(values)] == values and len(shown) > len(values)
    assert {kind for kind, _ in shown[len(values):]} == {"label"}


@pytest.mark.parametrize("preset", ["STIPPLED", "HATCHED"])
def test_the_same_look_twice_draws_the_same_strokes_and_says_so(example, preset):
    """A look run again on the same view and settings (its outlines kept the second time)
    draws the same strokes, bit for bit, and "Last run" says the same count: the
    drawing's, the outlines it kept too."""
    from importlib import import_module
    run = import_module("bl_ext.user_default.blobtree_ink.operators.illustrate").last_run
    bpy.ops.blobtree_ink.import_json(filepath=example("heart"), preview=False)
    tree = bpy.data.node_groups["heart"]
    tree.ink.grid_resolution = 12
    drawings, counts = [], []
    for _ in range(2):
        assert bpy.ops.blobtree_ink.illustrate(tree_name="heart", preset=preset) == {"FINISHED"}
        layers = ink("heart")
        drawings.append({k: [np.array([p.position for p in s.points]) for s in v] for k, v in layers.items() if v})
        counts.append(run["strokes"])
    a, b = drawings
    assert {k: len(v) for k, v in a.items()} == {k: len(v) for k, v in b.items()}
    assert all(np.array_equal(x, y) for k in a for x, y in zip(a[k], b[k]))
    assert counts[0] == counts[1] == sum(len(v) for v in a.values()) > 100


def test_a_camera_inside_the_model_is_said(ext, example):
    """The warning is the run's last report (the status bar's), not that the model is
    partly outside the camera's view, which follows from it."""
    bpy.ops.blobtree_ink.import_json(filepath=example("sphere"), preview=True)
    tree = bpy.data.node_groups["sphere"]
    tree.ink.grid_resolution = 12
    cam = bpy.data.objects.new("Cam", bpy.data.cameras.new("Cam"))
    bpy.context.scene.collection.objects.link(cam)
    bpy.context.scene.camera = cam
    cam.location = (0.05, 0.0, 0.0)                    # inside the ball
    assert bpy.ops.blobtree_ink.illustrate(tree_name="sphere", request="OUTLINES") == {"FINISHED"}
    from importlib import import_module
    run = import_module(f"{ext.__name__}.operators.illustrate").last_run
    assert run["warnings"][-1].startswith("the eye at (0.05, 0, 0) is inside the model"), run["warnings"]
    assert not any("camera's view" in w for w in run["warnings"]), run["warnings"]
    assert not ink("sphere")["Silhouette"]
    cam.location = (0.0, -4.0, 0.0)                    # outside, looking down past it: the model is out of view
    assert bpy.ops.blobtree_ink.illustrate(tree_name="sphere", request="OUTLINES") == {"FINISHED"}
    assert any("outside the scene camera's view" in w for w in run["warnings"]), run["warnings"]
