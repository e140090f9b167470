"""Ink that no longer fits: each layer remembers the eye, the model and the models in
front of it it was drawn for; the sidebar says when the ink is out of date, a request
names the layers it leaves, and a look draws them again."""
from types import SimpleNamespace

import bpy
import numpy as np
from ink_layers import ink
from recording_layout import Layout


def stale_note(ext, tree):
    """What the sidebar's out-of-date note says of ``tree`` (its lines joined), or ''."""
    panels = __import__(f"{ext.__name__}.operators.panels", fromlist=["x"])
    context = SimpleNamespace(scene=bpy.context.scene, region=SimpleNamespace(width=300),
                              preferences=bpy.context.preferences)
    bpy.context.view_layer.update()
    rec = Layout()
    panels._draw_stale(rec, context, tree)
    return " ".join(i["text"] for i in rec.of("label")).replace("  ", " ")


def test_layers_drawn_for_another_viewpoint_are_named_and_a_look_redraws_its_outlines(ext, example):
    """Each layer remembers the eye it was drawn for. A request that leaves layers drawn
    for another viewpoint says which and what redraws them; a look draws its outlines
    again when they were drawn for another viewpoint, and clears what it leaves that
    was (one drawing, one viewpoint)."""
    from aimed_camera import aimed_camera
    run = __import__(f"{ext.__name__}.operators.illustrate", fromlist=["x"]).last_run
    views = __import__(f"{ext.__name__}.grease_pencil.views", fromlist=["x"])
    bpy.ops.blobtree_ink.import_json(filepath=example("pear"), preview=False)
    tree = bpy.data.node_groups["pear"]
    tree.ink.grid_resolution = 12
    cam = aimed_camera((4.0, -6.0, 2.0), (0, 0, 0))
    assert bpy.ops.blobtree_ink.illustrate(tree_name="pear", request="OUTLINES") == {"FINISHED"}
    obj = bpy.data.objects["pear Ink"]
    first = list(obj[views.KEY]["Silhouette@1"])
    assert np.allclose(first[:3], cam.location, atol=1e-4)                    # the eye, in the model's frame
    silhouette = [tuple(p.position) for p in ink("pear")["Silhouette"][0].points]
    # the same camera: strokes fit the outlines, nothing to say
    tree.ink.hatching = True
    assert bpy.ops.blobtree_ink.illustrate(tree_name="pear", request="PLACE_STROKES") == {"FINISHED"}
    assert run["warnings"] == []
    # a camera a few degrees round: a request for the strokes names the outline layers
    aimed_camera((4.6, -5.6, 2.0), (0, 0, 0))
    assert bpy.ops.blobtree_ink.illustrate(tree_name="pear", request="PLACE_STROKES") == {"FINISHED"}
    assert run["warnings"] == ["Silhouette, Crease drawn for another viewpoint: Trace Feature Outlines draws them "
                               "for this one"]
    assert [tuple(p.position) for p in ink("pear")["Silhouette"][0].points] == silhouette     # left as drawn
    # tracing the outlines again makes the drawing one viewpoint's
    assert bpy.ops.blobtree_ink.illustrate(tree_name="pear", request="OUTLINES") == {"FINISHED"}
    assert run["warnings"] == []
    # from a third viewpoint, a request for the outlines names the strokes
    aimed_camera((-4.0, -6.0, 3.0), (0, 0, 0))
    assert bpy.ops.blobtree_ink.illustrate(tree_name="pear", request="OUTLINES") == {"FINISHED"}
    assert run["warnings"] == ["Hatching drawn for another viewpoint: Place Strokes draws it for this one"]
    # a look from a fourth draws its outlines too: nothing is left from elsewhere
    aimed_camera((-4.0, -6.2, 3.4), (0, 0, 0))
    assert bpy.ops.blobtree_ink.illustrate(tree_name="pear", preset="HATCHED") == {"FINISHED"}
    assert run["warnings"] == []
    assert np.allclose(list(obj[views.KEY]["Silhouette@1"])[:3], (-4.0, -6.2, 3.4), atol=1e-4)
    assert np.allclose(list(obj[views.KEY]["Hatching@1"])[:3], (-4.0, -6.2, 3.4), atol=1e-4)
    # the same look from the same viewpoint traces nothing again
    assert bpy.ops.blobtree_ink.illustrate(tree_name="pear", preset="HATCHED") == {"FINISHED"}
    assert run["warnings"] == [] and run["iterations"] == 0
    # a layer the style no longer draws is named as such, and does not make every look trace again
    assert bpy.ops.blobtree_ink.illustrate(tree_name="pear", preset="STIPPLED") == {"FINISHED"}
    assert run["iterations"] == 0 and len(ink("pear")["Stipples"]) > 0
    aimed_camera((-4.4, -5.8, 3.4), (0, 0, 0))
    assert bpy.ops.blobtree_ink.illustrate(tree_name="pear", preset="HATCHED") == {"FINISHED"}
    assert run["warnings"] == ["Stipples cleared: not in this look (Ctrl+Z brings it back)"]   # (drawn elsewhere too)
    assert run["iterations"] > 0 and ink("pear")["Stipples"] == [] and len(ink("pear")["Hatching"]) > 0
    assert bpy.ops.blobtree_ink.illustrate(tree_name="pear", preset="HATCHED") == {"FINISHED"}
    assert run["warnings"] == [] and run["iterations"] == 0
    # a request names a layer its style no longer draws, and leaves it
    assert bpy.ops.blobtree_ink.illustrate(tree_name="pear", preset="STIPPLED") == {"FINISHED"}
    aimed_camera((-4.4, -5.6, 3.8), (0, 0, 0))
    tree.ink.hatching, tree.ink.stipples = True, False
    assert bpy.ops.blobtree_ink.illustrate(tree_name="pear", request="PLACE_STROKES") == {"FINISHED"}
    assert run["warnings"] == ["Silhouette, Crease drawn for another viewpoint: Trace Feature Outlines draws them "
                               "for this one; Stipples drawn for another viewpoint: switched off, Ink Layers "
                               "clears it"]
    assert len(ink("pear")["Stipples"]) > 0


def test_a_layer_redrawn_in_a_region_for_another_viewpoint_is_mixed(ext, example):
    """Strokes redrawn only in a region for another eye leave the rest as they were:
    the drawing holds both viewpoints, and no eye is its own any more."""
    views = __import__(f"{ext.__name__}.grease_pencil.views", fromlist=["x"])
    bpy.ops.blobtree_ink.import_json(filepath=example("pear"), preview=False)
    tree = bpy.data.node_groups["pear"]
    tree.ink.grid_resolution = 12
    tree.ink.hatching = True
    assert bpy.ops.blobtree_ink.illustrate(tree_name="pear", request="PLACE_STROKES") == {"FINISHED"}
    obj = bpy.data.objects["pear Ink"]
    eye, centre = np.array(obj[views.KEY]["Hatching@1"][:3]), np.zeros(3)
    assert views.unfit(obj, ["Hatching"], 1, eye, centre) == {}
    assert views.unfit(obj, ["Hatching"], 7, eye, centre) == {}          # frame 1's drawing, held
    assert views.unfit(obj, ["Hatching"], 7, -eye, centre) == {"Hatching": views.VIEWPOINT}
    views.record(obj, ["Hatching"], 1, eye, centre, region="a region")                # the same eye: still its own
    assert views.unfit(obj, ["Hatching"], 1, eye, centre) == {}
    views.record(obj, ["Hatching"], 1, -eye, centre, region="a region")
    assert obj[views.KEY]["Hatching@1"] == views.MIXED
    assert views.unfit(obj, ["Hatching"], 1, eye, centre) == {"Hatching": views.VIEWPOINT}
    assert views.unfit(obj, ["Hatching"], 1, -eye, centre) == {"Hatching": views.VIEWPOINT}
    views.record(obj, ["Hatching"], 1, -eye, centre)                                  # redrawn whole
    assert views.unfit(obj, ["Hatching"], 1, -eye, centre) == {}


def test_ink_drawn_before_a_model_in_front_moved_is_said(ext, example):
    """The ink remembers the models that stood between its model and the eye: once one
    of them moves or changes, or another comes between, the sidebar says the ink is out
    of date; a model moved about beside the view hides nothing and is not news."""
    import json

    from aimed_camera import aimed_camera
    panels = __import__(f"{ext.__name__}.operators.panels", fromlist=["x"])
    preview = __import__(f"{ext.__name__}.blobtree_nodes.preview", fromlist=["x"])
    views = __import__(f"{ext.__name__}.grease_pencil.views", fromlist=["x"])
    run = __import__(f"{ext.__name__}.operators.illustrate", fromlist=["x"]).last_run
    for _ in range(3):
        bpy.ops.blobtree_ink.import_json(filepath=example("sphere"), preview=True)
    back, front, aside = sorted((t for t in bpy.data.node_groups if t.name.startswith("sphere")), key=lambda t: t.name)
    back.preview_object.location = (0.0, 0.0, 0.0)
    front.preview_object.location = (0.3, -2.5, 0.0)
    aside.preview_object.location = (6.0, 0.0, 0.0)
    aimed_camera((0.0, -8.0, 0.0), (0.0, 0.0, 0.0))
    for t in (back, front, aside):
        t.ink.grid_resolution = 10
        preview.rebuild(t)

    def stale():
        return stale_note(ext, back)
    assert bpy.ops.blobtree_ink.illustrate(tree_name=back.name, request="OUTLINES") == {"FINISHED"}
    kept = json.loads(bpy.data.objects[f"{back.name} Ink"][views.HIDERS]["Silhouette@1"])
    assert sorted(kept) == [front.name, aside.name]
    assert kept[front.name][1] and not kept[aside.name][1]
    assert stale() == ""
    aside.preview_object.location.z += 1.0                    # beside the view: hides nothing, then or now
    assert stale() == ""
    front.preview_object.location.x += 0.4                    # the model in front moves
    assert stale() == panels.STALE_HIDDEN.replace("  ", " ")
    assert bpy.ops.blobtree_ink.illustrate(tree_name=back.name, request="OUTLINES") == {"FINISHED"}
    assert stale() == ""
    node = next(n for n in front.nodes if getattr(n, "kind", "") == "point")
    node.radius *= 1.2                                        # ... or changes
    preview.rebuild(front)
    assert stale() == panels.STALE_HIDDEN.replace("  ", " ")
    assert bpy.ops.blobtree_ink.illustrate(tree_name=back.name, request="OUTLINES") == {"FINISHED"}
    aside.preview_object.location = (0.0, -3.0, 0.5)          # another comes between
    assert stale() == panels.STALE_HIDDEN.replace("  ", " ")
    aside.preview_object.location = (6.0, 0.0, 0.0)
    assert stale() == ""
    front.ink.render_frames, front.preview_object.hide_render = False, True    # the one in front renders no more
    assert stale() == panels.STALE_HIDDEN.replace("  ", " ")
    # a look draws the outlines again, though the model and the eye are the ones they were drawn for
    front.ink.render_frames, front.preview_object.hide_render = True, False
    assert bpy.ops.blobtree_ink.illustrate(tree_name=back.name, preset="HATCHED") == {"FINISHED"}
    assert stale() == ""
    front.preview_object.location.x -= 0.4
    assert stale() == panels.STALE_HIDDEN.replace("  ", " ")
    assert bpy.ops.blobtree_ink.illustrate(tree_name=back.name, preset="HATCHED") == {"FINISHED"}
    assert run["iterations"] > 0 and stale() == ""
    front.preview_object.location.x += 0.4                    # a request leaves the outlines, and says why
    bpy.ops.object.select_all(action="DESELECT")              # (its region: the whole model)
    assert bpy.ops.blobtree_ink.illustrate(tree_name=back.name, request="PLACE_STROKES") == {"FINISHED"}
    assert run["warnings"] == ["Silhouette drawn before the models in front of it moved or changed: Trace Feature "
                               "Outlines draws it again"]
    # a model in front whose tree breaks hides nothing: news once, then its preview (the model before) is not
    assert bpy.ops.blobtree_ink.illustrate(tree_name=back.name, preset="HATCHED") == {"FINISHED"}
    node.radius = -1.0
    preview.rebuild(front)                                    # (a timer's, in the UI: the node shows its error)
    assert stale() == panels.STALE_HIDDEN.replace("  ", " ")
    assert bpy.ops.blobtree_ink.illustrate(tree_name=back.name, preset="HATCHED") == {"FINISHED"}
    assert stale() == ""
    node.radius = 1.0
    preview.rebuild(front)
    # names of any length are kept; a model squashed flat is no trouble for the sidebar
    aside.model_name = "a model with a name longer than Blender's own names may be, " * 3
    assert bpy.ops.blobtree_ink.illustrate(tree_name=back.name, preset="HATCHED") == {"FINISHED"}
    assert aside.model_name in bpy.data.objects[f"{back.name} Ink"][views.HIDERS]["Silhouette@1"]
    assert stale() == ""
    aside.preview_object.scale = (0.0, 0.0, 0.0)
    back.preview_object.scale = (0.0, 1.0, 1.0)
    assert stale() in ("", panels.STALE_HIDDEN.replace("  ", " "))


def test_ink_drawn_before_the_model_changed_is_said_and_a_look_redraws_it(ext, example):
    """Each layer remembers the model it was drawn for (model.fingerprint): after an
    edit the sidebar says the ink is out of date; a Look traces the outlines again and
    clears the layers it does not draw; a request names those it leaves."""
    views = __import__(f"{ext.__name__}.grease_pencil.views", fromlist=["x"])
    panels = __import__(f"{ext.__name__}.operators.panels", fromlist=["x"])
    preview = __import__(f"{ext.__name__}.blobtree_nodes.preview", fromlist=["x"])
    run = __import__(f"{ext.__name__}.operators.illustrate", fromlist=["x"]).last_run
    bpy.ops.blobtree_ink.import_json(filepath=example("pear"), preview=True)
    tree = bpy.data.node_groups["pear"]
    tree.ink.grid_resolution = 12

    def stale():
        return stale_note(ext, tree)
    assert bpy.ops.blobtree_ink.illustrate(tree_name="pear", preset="STIPPLED") == {"FINISHED"}
    obj = bpy.data.objects["pear Ink"]
    before = obj[views.MODELS]["Silhouette@1"]
    assert obj[views.MODELS]["Stipples@1"] == before == preview.shown_model(tree) and stale() == ""
    belly = [n for n in tree.nodes if n.label == "belly"][0]
    belly.radius *= 1.15                                      # the artist makes the pear fatter
    preview.rebuild(tree)                                     # (in the UI, a timer does so after the edit)
    assert preview.shown_model(tree) != before
    assert stale().replace("  ", " ") == panels.STALE.replace("  ", " ")
    # a request leaves the outlines and says so
    tree.ink.stipples, tree.ink.hatching = False, True
    assert bpy.ops.blobtree_ink.illustrate(tree_name="pear", request="PLACE_STROKES") == {"FINISHED"}
    assert run["warnings"] == ["Silhouette, Crease drawn before the model changed: Trace Feature Outlines draws them "
                               "again; Stipples drawn before the model changed: switched off, Ink Layers clears it"]
    # a look traces them again, and clears the stipples it does not draw (Ctrl+Z brings them back)
    assert bpy.ops.blobtree_ink.illustrate(tree_name="pear", preset="HATCHED") == {"FINISHED"}
    assert run["iterations"] > 0 and ink("pear")["Stipples"] == [] and ink("pear")["Silhouette"]
    assert run["warnings"] == ["Stipples cleared: not in this look (Ctrl+Z brings it back)"]   # (and stale)
    now = obj[views.MODELS]
    assert now["Silhouette@1"] == now["Hatching@1"] == preview.shown_model(tree) and stale() == ""
    # the artist's single strokes are their own: drawn before an edit, they say nothing
    assert bpy.ops.blobtree_ink.clear_layer(object_name="pear Ink", layer="Hatching") == {"FINISHED"}
    for name in ("Silhouette", "Crease"):
        bpy.ops.blobtree_ink.clear_layer(object_name="pear Ink", layer=name)
    bpy.context.scene.cursor.location = (0.0, -0.9, 0.3)                 # by the pear's belly
    assert bpy.ops.blobtree_ink.illustrate(tree_name="pear", request="SINGLE_STROKE") == {"FINISHED"}
    belly.radius *= 1.05
    preview.rebuild(tree)
    assert ink("pear")["Single Strokes"] and stale() == ""
    belly.radius /= 1.05
    preview.rebuild(tree)
    assert bpy.ops.blobtree_ink.illustrate(tree_name="pear", preset="HATCHED") == {"FINISHED"}
    # the outlines now fit the fatter pear: every silhouette point lies on its surface
    model = __import__(f"{ext.__name__}.blobtree_nodes.compile", fromlist=["x"]).compile_tree(tree)
    ev = __import__(f"{ext.__name__}.model", fromlist=["x"]).Evaluator(model)
    P = np.concatenate([np.array([p.position for p in s.points]) for s in ink("pear")["Silhouette"]])
    assert np.abs(ev.field(P) - ev.iso).max() < 1e-3


def test_ink_drawn_from_the_camera_before_the_camera_or_the_model_moved_is_said(ext, example):
    """Drawn from the scene camera, the ink holds for that camera where the model stood:
    the sidebar says so once the camera or the model has moved (a look draws it again);
    a move that sees the model alike, or ink drawn from a viewport, is not news."""
    from aimed_camera import aimed_camera
    panels = __import__(f"{ext.__name__}.operators.panels", fromlist=["x"])
    bpy.ops.blobtree_ink.import_json(filepath=example("sphere"), preview=True)
    tree = bpy.data.node_groups["sphere"]
    tree.ink.grid_resolution = 10
    cam = aimed_camera((0.0, -8.0, 0.0), (0.0, 0.0, 0.0))

    def stale():
        return stale_note(ext, tree)
    note = panels.STALE_VIEW.replace("  ", " ")
    assert bpy.ops.blobtree_ink.illustrate(tree_name="sphere", request="OUTLINES") == {"FINISHED"}
    assert stale() == ""
    cam.location = (3.0, -7.5, 1.0)                          # the camera moved round the model
    assert stale() == note
    assert bpy.ops.blobtree_ink.illustrate(tree_name="sphere", request="OUTLINES") == {"FINISHED"}
    assert stale() == ""
    tree.preview_object.rotation_euler.z += 0.5               # the model turned
    assert stale() == note
    assert bpy.ops.blobtree_ink.illustrate(tree_name="sphere", preset="HATCHED") == {"FINISHED"}
    assert stale() == ""
    tree.preview_object.location.z += 1e-4                    # a move that sees it alike
    assert stale() == ""
    tree.ink.use_camera = False                                # the ink is then the viewport's affair
    cam.location = (-3.0, -7.5, 1.0)
    assert stale() == ""
