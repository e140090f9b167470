"""Bake: every frame of a range illustrated as that frame's Grease Pencil drawing, on
that frame's surface; re-baking replaces only its own frames and layers; bad ranges,
a tree broken at some frame and a deleted driving object are named, the frames before
them kept."""
import bpy
import numpy as np
import pytest
from moving_scene import moving_spheres


def mod(ext, name):
    from importlib import import_module
    return import_module(f"{ext.__name__}.{name}")


def drawing(name, frame):
    obj = bpy.data.objects[f"{name} Ink"]
    out = {}
    for layer in obj.data.layers:
        fr = [f for f in layer.frames if f.frame_number == frame]
        out[layer.name] = [np.array([p.position for p in s.points]) for s in fr[0].drawing.strokes] if fr else None
    return out


def test_a_bake_draws_each_frame_on_that_frames_surface(ext, example):
    comp = mod(ext, "blobtree_nodes.compile")
    M = mod(ext, "model")
    tree, empty = moving_spheres(example)
    sc = bpy.context.scene
    sc.frame_set(3)
    assert bpy.ops.blobtree_ink.bake(tree_name="two_spheres", frame_start=1, frame_end=4) == {"FINISHED"}
    assert sc.frame_current == 3                                   # where the artist was
    bake = mod(ext, "operators.bake").last_bake
    assert bake["state"] == "done" and bake["frames"] == [1, 2, 3, 4]
    layer = bpy.data.objects["two_spheres Ink"].data.layers["Silhouette"]
    assert sorted(f.frame_number for f in layer.frames) == [1, 2, 3, 4, 5]      # 5: the hold's end
    rights = []
    for frame in (1, 2, 3, 4):
        sc.frame_set(frame)
        ev = M.Evaluator(comp.compile_tree(tree))
        pts = np.concatenate(drawing("two_spheres", frame)["Silhouette"])
        assert np.abs(ev.field(pts) - ev.iso).max() < 1e-6         # on that frame's surface
        rights.append(pts[:, 0].max())
    assert rights == sorted(rights) and rights[-1] > rights[0] + 1.0   # following the empty


def test_a_bake_without_a_scene_camera_says_where_its_frames_are_seen_from(ext, example):
    """With no scene camera the frames are seen from a three-quarter view of the model:
    the bake says so (a warning with its result); with a camera it says nothing more."""
    tree, empty = moving_spheres(example)
    bake = mod(ext, "operators.bake").last_bake
    assert bpy.ops.blobtree_ink.bake(tree_name="two_spheres", frame_start=1, frame_end=2) == {"FINISHED"}
    assert bake["state"] == "done" and bake["note"] == ""
    with_camera = drawing("two_spheres", 2)["Silhouette"]
    bpy.context.scene.camera = None
    assert bpy.ops.blobtree_ink.bake(tree_name="two_spheres", frame_start=1, frame_end=2) == {"FINISHED"}
    assert bake["state"] == "done" and bake["note"] == ("the scene has no camera: each frame is seen from a "
                                                        "three-quarter view of the model")
    seen = drawing("two_spheres", 2)["Silhouette"]
    assert len(seen) and not all(a.shape == b.shape and np.allclose(a, b) for a, b in zip(seen, with_camera))


def test_baking_again_replaces_only_its_own_frames(ext, example):
    tree, empty = moving_spheres(example)
    assert bpy.ops.blobtree_ink.bake(tree_name="two_spheres", frame_start=1, frame_end=3) == {"FINISHED"}
    first = drawing("two_spheres", 1)["Silhouette"]
    empty.animation_data.action = None                             # the empty stops moving: frames differ
    empty.location = (2.0, 0.0, 0.0)
    assert bpy.ops.blobtree_ink.bake(tree_name="two_spheres", frame_start=2, frame_end=3) == {"FINISHED"}
    assert all(np.array_equal(x, y) for x, y in zip(drawing("two_spheres", 1)["Silhouette"], first))
    frames = mod(ext, "operators.frames")
    assert frames.drawn_frames(tree) == {1, 2, 3}


def test_the_frame_after_a_bake_shows_no_ink_until_the_next_drawing(ext, example):
    """Grease Pencil holds a layer's drawing until its next key: after a bake, each of
    its layers gets an empty drawing on the frame after the range, unless that frame has
    one; the empty one is no drawn frame (a render draws it) and a later bake there
    replaces it."""
    tree, empty = moving_spheres(example)
    frames = mod(ext, "operators.frames")
    obj_layers = lambda: bpy.data.objects["two_spheres Ink"].data.layers
    assert bpy.ops.blobtree_ink.bake(tree_name="two_spheres", frame_start=6, frame_end=7) == {"FINISHED"}
    inked = [layer for layer in obj_layers() if any(f.frame_number == 7 and len(f.drawing.strokes)
                                                   for f in layer.frames)]
    assert "Silhouette" in [layer.name for layer in inked]
    for layer in inked:                        # (a layer with nothing at 7 holds nothing)
        keys = {f.frame_number: len(f.drawing.strokes) for f in layer.frames}
        assert sorted(keys) == [6, 7, 8] and keys[8] == 0
    assert drawing("two_spheres", 7)["Silhouette"] and frames.drawn_frames(tree) == {6, 7}
    assert bpy.ops.blobtree_ink.bake(tree_name="two_spheres", frame_start=2, frame_end=3) == {"FINISHED"}
    for layer in inked:                        # 4 and 5 show nothing; 6 is still the bake's
        keys = {f.frame_number: len(f.drawing.strokes) for f in layer.frames}
        assert sorted(keys) == [2, 3, 4, 6, 7, 8] and keys[4] == 0
    assert bpy.ops.blobtree_ink.bake(tree_name="two_spheres", frame_start=4, frame_end=5) == {"FINISHED"}
    keys = {f.frame_number: len(f.drawing.strokes) for f in obj_layers()["Silhouette"].frames}
    assert sorted(keys) == [2, 3, 4, 5, 6, 7, 8] and keys[4] > 0 and keys[5] > 0    # no end before 6's drawing
    assert frames.drawn_frames(tree) == {2, 3, 4, 5, 6, 7}


def test_the_bake_range_is_the_scenes_or_the_trees_and_clear_removes_frames(ext, example):
    """Bake and Clear without a range (the sidebar's buttons, the Object menu) take the
    tree's bake range: the scene's Start and End, or the tree's own."""
    tree, empty = moving_spheres(example)
    frames = mod(ext, "operators.frames")
    sc = bpy.context.scene
    sc.frame_start, sc.frame_end = 2, 3
    assert bpy.ops.blobtree_ink.bake(tree_name="two_spheres") == {"FINISHED"}
    assert frames.drawn_frames(tree) == {2, 3}
    tree.ink.use_scene_range = False                               # the fields start from the range in effect
    assert (tree.ink.frame_start, tree.ink.frame_end) == (2, 3)
    tree.ink.frame_end = 7                                         # a range of its own is kept when
    tree.ink.use_scene_range = True                                # the scene's is used for a while
    tree.ink.use_scene_range = False
    assert (tree.ink.frame_start, tree.ink.frame_end) == (2, 7)
    tree.ink.frame_start = 9                                       # Start past End pushes End, as in the timeline
    assert (tree.ink.frame_start, tree.ink.frame_end) == (9, 9)
    tree.ink.frame_end = 5                                         # ... and End before Start pulls Start
    assert (tree.ink.frame_start, tree.ink.frame_end) == (5, 5)
    tree.ink.frame_end = 6
    assert bpy.ops.blobtree_ink.bake(tree_name="two_spheres") == {"FINISHED"}
    assert frames.drawn_frames(tree) == {2, 3, 5, 6}
    assert frames.spans(frames.drawn_frames(tree)) == "2-3, 5-6"
    assert bpy.ops.blobtree_ink.clear_frames(tree_name="two_spheres", frame_start=3, frame_end=5) == {"FINISHED"}
    assert frames.drawn_frames(tree) == {2, 6}
    obj = bpy.data.objects["two_spheres Ink"]
    keys = {f.frame_number: len(f.drawing.strokes) for f in obj.data.layers["Silhouette"].frames}
    assert sorted(keys) == [2, 3, 6, 7] and keys[2] and keys[6]         # 3 and 7: no ink, not 2 and 6 held
    assert keys[3] == keys[7] == 0
    assert bpy.ops.blobtree_ink.clear_frames(tree_name="two_spheres") == {"FINISHED"}     # the tree's range: 5-6
    assert frames.drawn_frames(tree) == {2}
    with pytest.raises(RuntimeError, match="the frame range 9-8 is empty"):
        bpy.ops.blobtree_ink.clear_frames(tree_name="two_spheres", frame_start=9, frame_end=8)
    assert frames.drawn_frames(tree) == {2}
    assert frames.spans({1, 2, 3, 5, 7, 8}) == "1-3, 5, 7-8" and frames.spans({4}) == "4"


@pytest.mark.parametrize("start, end, message", [(5, 2, "the frame range 5-2 is empty")])
def test_a_bad_range_is_named_and_nothing_is_drawn(ext, example, start, end, message):
    moving_spheres(example)
    with pytest.raises(RuntimeError, match=message):
        bpy.ops.blobtree_ink.bake(tree_name="two_spheres", frame_start=start, frame_end=end)
    assert "two_spheres Ink" not in bpy.data.objects


def test_a_tree_broken_at_a_frame_keeps_the_frames_before_it(ext, example):
    tree, empty = moving_spheres(example)
    a = [n for n in tree.nodes if getattr(n, "kind", "") == "point"][0]
    a.radius = 1.0
    a.keyframe_insert("radius", frame=1)
    a.keyframe_insert("radius", frame=2)
    a.radius = -1.0                                                # not a radius
    a.keyframe_insert("radius", frame=3)
    for fc in mod(ext, "blobtree_nodes.animation").channels(tree):
        for k in fc.keyframe_points:
            k.interpolation = "CONSTANT"
    with pytest.raises(RuntimeError, match="frame 3: .*Influence Radius must be > 0"):
        bpy.ops.blobtree_ink.bake(tree_name="two_spheres", frame_start=1, frame_end=4)
    assert mod(ext, "operators.frames").drawn_frames(tree) == {1, 2}


def _remove(empty):
    bpy.data.objects.remove(empty)


def _unlink(empty):                          # Delete in the viewport: the node's pointer keeps it in bpy.data
    for coll in list(empty.users_collection):
        coll.objects.unlink(empty)


@pytest.mark.parametrize("delete", [_remove, _unlink], ids=["removed", "deleted in the viewport"])
def test_a_deleted_driving_object_is_named(ext, example, delete):
    """A driving object removed, or deleted in the viewport (unlinked from the scene,
    kept in bpy.data by the node's pointer, its animation no longer evaluated), at frame
    3 of a bake: the bake names it and the node by its label, and keeps frames 1-2."""
    tree, empty = moving_spheres(example)
    next(n for n in tree.nodes if getattr(n, "center_object", None) is empty).label = "left lobe"
    state = {}

    def delete_at_frame_3(scene, *_):
        if scene.frame_current == 3 and not state:
            state["deleted"] = True
            delete(empty)
    bpy.app.handlers.frame_change_pre.append(delete_at_frame_3)
    try:
        with pytest.raises(RuntimeError, match="frame 3: the object 'Driver' that node 'left lobe' follows was "
                                               "deleted"):
            bpy.ops.blobtree_ink.bake(tree_name="two_spheres", frame_start=1, frame_end=4)
    finally:
        bpy.app.handlers.frame_change_pre.remove(delete_at_frame_3)
    assert mod(ext, "operators.frames").drawn_frames(tree) == {1, 2}


def test_an_animation_render_illustrates_each_frame_as_the_bake_does(ext, example, tmp_path):
    """Render Animation (what `blender -b file.blend -a` runs) illustrates every frame the
    ink has no drawing of before rendering it: the images differ from frame to frame, and
    each frame's drawing is the one a bake makes; a frame the artist drew is kept."""
    tree, empty = moving_spheres(example)
    sc = bpy.context.scene
    tree.ink.hatching, tree.ink.line_width = True, 6.0         # lines a few pixels wide at this small size
    sc.frame_set(1)
    assert bpy.ops.blobtree_ink.illustrate(tree_name="two_spheres", request="OUTLINES") == {"FINISHED"}
    mine = drawing("two_spheres", 1)
    sc.render.engine = "BLENDER_WORKBENCH"
    sc.render.resolution_x = sc.render.resolution_y = 128
    sc.frame_start, sc.frame_end = 1, 3
    sc.render.filepath = str(tmp_path / "f_")
    bpy.ops.render.render(animation=True)
    R = mod(ext, "operators.render_frames")
    assert [f for t, f in R.drawn if t == "two_spheres"][-2:] == [2, 3]
    assert drawing("two_spheres", 1)["Silhouette"] is not None
    assert all(np.array_equal(x, y) for x, y in zip(drawing("two_spheres", 1)["Silhouette"], mine["Silhouette"]))
    rendered = {f: drawing("two_spheres", f) for f in (2, 3)}
    assert rendered[2]["Hatching"] and rendered[3]["Hatching"]      # the look: outlines and the style's strokes
    images = []
    for f in (1, 2, 3):
        img = bpy.data.images.load(str(tmp_path / f"f_{f:04d}.png"))
        images.append(np.array(img.pixels[:]).reshape(128, 128, -1)[..., :3].mean(axis=2))
    assert np.abs(images[1] - images[2]).max() > 0.5 and np.abs(images[0] - images[1]).max() > 0.5
    # the same frames baked: the same drawings
    assert bpy.ops.blobtree_ink.bake(tree_name="two_spheres", frame_start=2, frame_end=3) == {"FINISHED"}
    for f in (2, 3):
        baked = drawing("two_spheres", f)
        for layer in ("Silhouette", "Hatching"):
            assert len(baked[layer]) == len(rendered[f][layer])
            assert all(np.allclose(x, y, atol=1e-6) for x, y in zip(baked[layer], rendered[f][layer]))
    assert mod(ext, "operators.frames").rendered_frames(tree) == set()    # baked now: kept by the next render


def test_a_render_uses_a_drawing_held_over_while_it_fits_the_frames_model_and_view(ext, example, tmp_path):
    """A still model drawn once at frame 1: a render of frame 6 uses that drawing as it
    is (no new drawing written); once the model, the camera (even a little), the style or
    the light changes, the render illustrates frame 6 for what it then is, once."""
    from aimed_camera import aimed_camera
    R = mod(ext, "operators.render_frames")
    bpy.ops.blobtree_ink.import_json(filepath=example("pear"), preview=False)
    tree, sc = bpy.data.node_groups["pear"], bpy.context.scene
    tree.ink.grid_resolution = 12
    cam = aimed_camera((0.0, -9.0, 2.0), (0.0, 0.0, 0.5))
    sc.render.engine = "BLENDER_WORKBENCH"
    sc.render.resolution_x = sc.render.resolution_y = 64
    sc.frame_set(1)
    assert bpy.ops.blobtree_ink.illustrate(tree_name="pear", preset="STIPPLED") == {"FINISHED"}

    def render(frame):
        sc.frame_set(frame)
        before = len(R.drawn)
        bpy.ops.render.render(write_still=False)
        return [f for t, f in R.drawn[before:] if t == "pear"]
    assert render(6) == [] and mod(ext, "operators.frames").drawn_frames(tree) == {1}
    [n for n in tree.nodes if n.label == "belly"][0].radius *= 1.1       # the model changes
    assert render(6) == [6] and render(6) == []                          # drawn once, then used
    cam.location.x += 0.01                                               # the camera moves a little
    bpy.context.view_layer.update()
    assert render(6) == [6] and render(6) == []
    tree.ink.contrast = 0.5                                              # the style changes
    assert render(6) == [6] and render(6) == []
    sun = bpy.data.objects.new("Sun", bpy.data.lights.new("Sun", "SUN"))
    sc.collection.objects.link(sun)                                      # the light changes
    bpy.context.view_layer.update()
    assert render(6) == [6] and render(6) == []
    sun.rotation_euler.x += 0.3
    bpy.context.view_layer.update()
    assert render(6) == [6]


def test_a_render_draws_a_tree_never_drawn_and_says_when_a_bake_it_keeps_is_out_of_date(ext, example, capsys):
    """F12 right after an import draws the model (its preview stays out of renders: the
    picture would be blank paper); a baked frame is rendered as it is, and once the
    model has changed the console says which layers no longer fit."""
    from aimed_camera import aimed_camera
    R = mod(ext, "operators.render_frames")
    FR = mod(ext, "operators.frames")
    bpy.ops.blobtree_ink.import_json(filepath=example("pear"), preview=True)
    tree, sc = bpy.data.node_groups["pear"], bpy.context.scene
    tree.ink.grid_resolution = 12
    aimed_camera((0.0, -9.0, 2.0), (0.0, 0.0, 0.5))
    sc.render.engine = "BLENDER_WORKBENCH"
    sc.render.resolution_x = sc.render.resolution_y = 64
    sc.frame_set(2)
    assert bpy.data.objects.get("pear Ink") is None
    bpy.ops.render.render(write_still=False)
    assert ("pear", 2) in R.drawn and FR.drawn_frames(tree) == {2}
    assert bpy.ops.blobtree_ink.bake(tree_name="pear", frame_start=3, frame_end=3) == {"FINISHED"}
    belly = [n for n in tree.nodes if n.label == "belly"][0]
    radius = belly.radius

    def render_3():
        sc.frame_set(3)
        capsys.readouterr()
        bpy.ops.render.render(write_still=False)
        return capsys.readouterr().out
    assert "BlobTree Ink: frame 3" not in render_3()                    # the bake fits: nothing said
    belly.radius = radius * 1.1
    said = render_3()
    assert ("pear", 3) not in R.drawn                                   # the bake's drawing, kept
    assert "frame 3 of 'pear' is rendered with the drawing it has: Silhouette drawn before the model changed" in said
    belly.radius = radius
    sc.camera.location.x += 2.0                                        # the camera moves away from the bake's
    bpy.context.view_layer.update()
    assert "Silhouette drawn for another viewpoint" in render_3()


def test_a_rendered_frame_compiles_each_tree_once_and_marks_only_its_own_errors(ext, example, monkeypatch, capsys):
    """A render's frame draws every tree, each hidden by the others: each tree is
    compiled once for all of them; a broken tree is named by the others' frames and
    marked on its own node by its own frame, as when it is drawn alone."""
    from aimed_camera import aimed_camera
    R, FR = mod(ext, "operators.render_frames"), mod(ext, "operators.frames")
    for _ in range(3):
        bpy.ops.blobtree_ink.import_json(filepath=example("sphere"), preview=True)
    trees = sorted((t for t in bpy.data.node_groups if t.name.startswith("sphere")), key=lambda t: t.name)
    for tree, x in zip(trees, (-1.5, 0.0, 1.5)):
        tree.preview_object.location = (x, -1.0 * abs(x), 0.0)
        tree.ink.grid_resolution = 10
    aimed_camera((0.0, -9.0, 0.0), (0.0, 0.0, 0.0))
    sc = bpy.context.scene
    sc.render.engine = "BLENDER_WORKBENCH"
    sc.render.resolution_x = sc.render.resolution_y = 64
    broken = trees[2]
    point = next(n for n in broken.nodes if getattr(n, "kind", "") == "point")
    point.radius = -1.0
    point.set_error("")
    compiled = []
    real = FR.compile_tree
    monkeypatch.setattr(FR, "compile_tree", lambda tree, *a, **k: compiled.append(tree.name) or real(tree, *a, **k))
    sc.frame_set(4)
    capsys.readouterr()
    bpy.ops.render.render(write_still=False)
    said = capsys.readouterr().out
    assert sorted(compiled) == sorted(t.name for t in trees)                  # once each, for the three frames
    assert {(t.name, 4) for t in trees[:2]} <= set(R.drawn) and (broken.name, 4) not in R.drawn
    assert f"'{broken.name}' hides no lines: its tree is broken" in said
    assert f"frame 4 of '{broken.name}' not illustrated" in said
    assert "must be > 0" in point.error and not any(n.error for t in trees[:2] for n in t.nodes
                                                    if hasattr(n, "error"))


def test_a_look_on_a_baked_frame_does_not_show_over_the_frames_after_it(ext, example):
    """A look drawn on one frame of a baked range draws that frame: the layers it adds
    end where the next baked frame begins (Grease Pencil would hold them over the later
    frames' own drawings), the later frames keep theirs, and the look says so."""
    frames = mod(ext, "operators.frames")
    tree, empty = moving_spheres(example)
    sc = bpy.context.scene
    assert bpy.ops.blobtree_ink.bake(tree_name="two_spheres", frame_start=1, frame_end=4) == {"FINISHED"}
    before = {f: drawing("two_spheres", f) for f in (2, 3, 4)}
    assert not any(d.get("Hatching") for d in before.values())          # the tree's look: outlines only
    sc.frame_set(1)
    assert bpy.ops.blobtree_ink.illustrate(tree_name="two_spheres", preset="HATCHED") == {"FINISHED"}
    obj = bpy.data.objects["two_spheres Ink"]
    hatching = obj.data.layers["Hatching"]
    shown = {f: len(mod(ext, "grease_pencil.views").shown_frame(hatching, f).drawing.strokes) for f in (1, 2, 3, 4)}
    assert shown[1] > 10 and shown[2] == shown[3] == shown[4] == 0
    for f in (2, 3, 4):                                                  # the later frames' own drawings, untouched
        now = drawing("two_spheres", f)
        for layer in ("Silhouette", "Crease"):
            got, had = now.get(layer), before[f].get(layer)
            assert (got is None) == (had is None) and all(np.array_equal(a, b) for a, b in zip(got or [], had or []))
    run = mod(ext, "operators.illustrate").last_run
    assert any("frames 2-4 keep their own drawings" in w for w in run["warnings"]), run["warnings"]
    assert frames.drawn_frames(tree) == {1, 2, 3, 4}


def test_a_look_holds_over_frames_with_only_the_artists_strokes(ext, example):
    """Only the extension's drawn layers end a look's hold: the artist's single strokes,
    or a layer of their own, keyed on a later frame, leave the look shown there."""
    writer, views = mod(ext, "grease_pencil.writer"), mod(ext, "grease_pencil.views")
    Stroke = mod(ext, "strokes.data").Stroke
    tree, empty = moving_spheres(example)
    bpy.context.scene.frame_set(1)
    assert bpy.ops.blobtree_ink.illustrate(tree_name="two_spheres", request="OUTLINES") == {"FINISHED"}
    obj = bpy.data.objects["two_spheres Ink"]
    mark = [Stroke(np.array([[0.0, 0.0, 0.0], [0.1, 0.0, 0.0]]), np.full(2, 0.01), np.ones(2))]
    writer.write_layer(obj, "Single Strokes", mark, 20)
    obj.data.layers.new("Notes")                                   # a layer of the artist's own
    writer.write_layer(obj, "Notes", mark, 30)
    assert bpy.ops.blobtree_ink.illustrate(tree_name="two_spheres", preset="HATCHED") == {"FINISHED"}
    for layer in ("Silhouette", "Hatching"):
        assert [f.frame_number for f in obj.data.layers[layer].frames] == [1]
        assert len(views.shown_frame(obj.data.layers[layer], 35).drawing.strokes) > 0
    assert not any("keep their own drawings" in w for w in mod(ext, "operators.illustrate").last_run["warnings"])
