"""An artist's first hour, in the background tiers (the real UI walks the same steps
with its keys and clicks in tests/real): trace outlines, click a stippled look, click
a hatched look (outlines and stipples stay), render on white paper in Workbench and in
EEVEE, and check the pixels of each layer's strokes: dark ink on white, no preview
mesh."""
import bpy
import numpy as np
import pytest
from aimed_camera import aimed_camera
from bpy_extras.object_utils import world_to_camera_view
from mathutils import Vector

EEVEE = "BLENDER_EEVEE_NEXT" if bpy.app.version < (5, 0, 0) else "BLENDER_EEVEE"


def layers_of(name):
    obj = bpy.data.objects[f"{name} Ink"]
    return {l.name: list(l.frames[0].drawing.strokes) if len(l.frames) else [] for l in obj.data.layers}


def points(strokes):
    return np.array([p.position for s in strokes for p in s.points])


def set_up(example, name="pear"):
    bpy.ops.blobtree_ink.import_json(filepath=example(name), preview=True)
    tree = bpy.data.node_groups[name]
    tree.ink.grid_resolution = 12
    aimed_camera((2.2, -3.2, 1.4), (0.0, 0.0, 0.1))
    return tree


def test_a_look_replaces_another_looks_strokes_and_presets_change_only_the_look(example):
    """A look is one drawing: it keeps the traced outlines (not traced again) and clears
    the strokes another look drew (said; Ctrl+Z brings them back)."""
    run = __import__("bl_ext.user_default.blobtree_ink.operators.illustrate", fromlist=["x"]).last_run
    tree = set_up(example)
    tree.ink.grid_resolution, tree.ink.agents, tree.ink.seed, tree.ink.lod = 12, 5000, 7, 0.3
    assert bpy.ops.blobtree_ink.illustrate(tree_name="pear", request="OUTLINES") == {"FINISHED"}
    outlines = layers_of("pear")
    assert outlines["Silhouette"] and outlines["Crease"]
    assert bpy.ops.blobtree_ink.illustrate(tree_name="pear", preset="STIPPLED") == {"FINISHED"}
    after = layers_of("pear")
    assert len(after["Stipples"]) > 50 and not after["Hatching"]
    assert np.array_equal(points(after["Silhouette"]), points(outlines["Silhouette"]))     # not traced again
    assert bpy.ops.blobtree_ink.illustrate(tree_name="pear", preset="HATCHED") == {"FINISHED"}
    hatched = layers_of("pear")
    assert len(hatched["Hatching"]) > 20 and hatched["Stipples"] == []                     # the stipples go
    assert run["warnings"][-1] == "Stipples cleared: not in this look (Ctrl+Z brings it back)"
    assert np.array_equal(points(hatched["Silhouette"]), points(outlines["Silhouette"]))
    # the looks set the style alone
    ink = tree.ink
    assert (ink.grid_resolution, ink.agents, ink.seed, ink.lod) == (12, 5000, 7, pytest.approx(0.3))
    assert ink.hatching and not ink.stipples
    # a single stroke adds to its own layer; the hatching stays
    bpy.context.scene.cursor.location = (0.0, -0.9, 0.0)
    for k in (1, 2):
        assert bpy.ops.blobtree_ink.illustrate(tree_name="pear", request="SINGLE_STROKE") == {"FINISHED"}
        assert len(layers_of("pear")["Single Strokes"]) == k
    assert len(layers_of("pear")["Hatching"]) == len(hatched["Hatching"])
    # the ink lives in the tree's collection, beside its preview
    ink_obj = bpy.data.objects["pear Ink"]
    assert ink_obj.users_collection[0] == tree.collection == tree.preview_object.users_collection[0]


def test_the_outlines_look_draws_outlines_and_place_strokes_without_strokes_says_so(example):
    set_up(example)
    assert bpy.ops.blobtree_ink.illustrate(tree_name="pear", preset="OUTLINES") == {"FINISHED"}
    layers = layers_of("pear")
    assert layers["Silhouette"] and not layers["Hatching"]
    assert bpy.ops.blobtree_ink.illustrate(tree_name="pear", request="PLACE_STROKES") == {"FINISHED"}
    layers = layers_of("pear")
    assert not layers["Hatching"] and not layers["Stipples"] and layers["Silhouette"]


def test_the_cursor_region_and_a_region_without_surface(example):
    from importlib import import_module
    tree = set_up(example)
    PL = import_module("bl_ext.user_default.blobtree_ink.pipeline")
    comp = import_module("bl_ext.user_default.blobtree_ink.blobtree_nodes.compile")
    M = import_module("bl_ext.user_default.blobtree_ink.model")
    _, radius = PL.bounds(M.Evaluator(comp.compile_tree(tree)))
    tree.ink.region, tree.ink.region_size, tree.ink.stipples = "CURSOR", 0.3, True
    centre = np.array([0.0, -0.6, 0.0])
    bpy.context.scene.cursor.location = centre
    assert bpy.ops.blobtree_ink.illustrate(tree_name="pear", request="PLACE_STROKES") == {"FINISHED"}
    pts = points(layers_of("pear")["Stipples"])
    assert len(pts) > 10 and np.linalg.norm(pts - centre, axis=1).max() <= 0.3 * radius + 1e-5
    before = len(layers_of("pear")["Stipples"])
    bpy.context.scene.cursor.location = (40.0, 0.0, 0.0)            # nothing of the model there
    assert bpy.ops.blobtree_ink.illustrate(tree_name="pear", request="PLACE_STROKES") == {"FINISHED"}
    assert len(layers_of("pear")["Stipples"]) == before            # nothing replaced


def test_place_strokes_in_a_second_region_keeps_the_first(example):
    """Regions build a drawing up: hatching placed around one point and then around
    another keeps both; placing it again around the first replaces that part only."""
    tree = set_up(example)
    tree.ink.region, tree.ink.region_size, tree.ink.hatching = "CURSOR", 0.25, True
    tree.ink.cross_hatching = False
    a, b = np.array([0.0, -0.6, -0.3]), np.array([0.5, -0.2, 0.2])

    def hatch_at(c):
        bpy.context.scene.cursor.location = c
        assert bpy.ops.blobtree_ink.illustrate(tree_name="pear", request="PLACE_STROKES") == {"FINISHED"}
        return layers_of("pear")["Hatching"]
    only_a = hatch_at(a)
    both = hatch_at(b)
    from importlib import import_module
    PL = import_module("bl_ext.user_default.blobtree_ink.pipeline")
    comp = import_module("bl_ext.user_default.blobtree_ink.blobtree_nodes.compile")
    M = import_module("bl_ext.user_default.blobtree_ink.model")
    r = 0.25 * PL.bounds(M.Evaluator(comp.compile_tree(tree)))[1] + 1e-5
    near = lambda strokes, c: sum(np.linalg.norm(points([s]) - c, axis=1).max() <= r for s in strokes)  # noqa: E731
    assert len(only_a) > 3 and len(both) > len(only_a)
    assert near(both, a) == near(only_a, a) > 0 and near(both, b) > 0
    again = hatch_at(a)
    assert len(again) == len(both)                                    # the same strokes, replaced


def test_paper_is_set_up_and_given_back(example):
    sc = bpy.context.scene
    old = bpy.data.worlds.new("Studio")
    sc.world = old
    sc.view_settings.view_transform = "AgX" if "AgX" in [i.identifier for i in
                                                        sc.view_settings.bl_rna.properties["view_transform"]
                                                        .enum_items] else "Filmic"
    was = sc.view_settings.view_transform
    for vl in sc.view_layers:
        vl.use_pass_z = False
    tree = set_up(example)
    assert tree.preview_object.hide_render                           # not in renders by default
    assert bpy.ops.blobtree_ink.illustrate(tree_name="pear", request="OUTLINES") == {"FINISHED"}
    assert sc.world.name == "BlobTree Ink Paper" and tuple(sc.world.color) == (1.0, 1.0, 1.0)
    assert sc.view_settings.view_transform == "Standard" and not sc.render.film_transparent
    assert all(vl.use_pass_z for vl in sc.view_layers)              # Grease Pencil renders without a warning
    assert tree.preview_object.data.materials[0].diffuse_color[:3] == (1.0, 1.0, 1.0)
    assert bpy.data.objects["pear Ink"].show_in_front                # over the rough preview in the viewport
    tree.ink.render_preview = True                                   # the mesh renders: its depth must not hide
    assert not tree.preview_object.hide_render and not any(vl.use_pass_z for vl in sc.view_layers)
    tree.ink.render_preview = False
    assert all(vl.use_pass_z for vl in sc.view_layers)
    tree.ink.paper = False                                           # the scene's own look comes back
    assert sc.world == old and sc.view_settings.view_transform == was
    assert not any(vl.use_pass_z for vl in sc.view_layers)
    assert not tree.preview_object.data.materials or tree.preview_object.data.materials[0] is None or \
        tree.ink.paper is False
    assert len(tree.preview_object.data.materials) == 0                # the preview's own look too
    tree.ink.paper = True                                            # ticked again: on paper at once
    assert sc.world.name == "BlobTree Ink Paper" and sc.view_settings.view_transform == "Standard"
    assert tree.preview_object.data.materials[0].diffuse_color[:3] == (1.0, 1.0, 1.0)
    tree.ink.paper = False
    assert sc.world == old and sc.view_settings.view_transform == was


@pytest.mark.parametrize("engine", ["BLENDER_WORKBENCH", EEVEE])
def test_a_render_shows_every_layer_as_ink_on_white_paper(example, tmp_path, engine):
    set_up(example)
    assert bpy.ops.blobtree_ink.illustrate(tree_name="pear", request="OUTLINES") == {"FINISHED"}
    assert bpy.ops.blobtree_ink.illustrate(tree_name="pear", preset="STIPPLED") == {"FINISHED"}
    bpy.data.node_groups["pear"].ink.hatching = True                    # stipples and hatching: one request
    assert bpy.ops.blobtree_ink.illustrate(tree_name="pear", request="PLACE_STROKES") == {"FINISHED"}
    sc = bpy.context.scene
    sc.render.engine = engine
    sc.render.resolution_x = sc.render.resolution_y = 400
    sc.render.filepath = str(tmp_path / "render.png")
    bpy.ops.render.render(write_still=True)
    img = bpy.data.images.load(str(tmp_path / "render.png"))
    w, h = img.size
    px = np.array(img.pixels[:]).reshape(h, w, img.channels)[..., :3].mean(axis=2)
    layers = layers_of("pear")
    near_ink = np.zeros((h, w), bool)
    for name in ("Silhouette", "Crease", "Stipples", "Hatching"):
        pts = points(layers[name])
        uv = np.array([world_to_camera_view(sc, sc.camera, Vector(p))[:2] for p in pts])
        x, y = (uv[:, 0] * w).astype(int), (uv[:, 1] * h).astype(int)
        ok = (x >= 1) & (x < w - 1) & (y >= 1) & (y < h - 1)
        x, y = x[ok], y[ok]
        # the darkest pixel of each point's 3x3 neighbourhood is ink
        dark = np.min([px[y + dy, x + dx] for dy in (-1, 0, 1) for dx in (-1, 0, 1)], axis=0)
        assert np.median(dark) < 0.55, f"{engine}: the {name} layer is not ink in the render"
        for dy in range(-3, 4):
            for dx in range(-3, 4):
                near_ink[np.clip(y + dy, 0, h - 1), np.clip(x + dx, 0, w - 1)] = True
    paper = px[~near_ink]
    assert np.median(paper) > 0.97 and np.quantile(paper, 0.05) > 0.9, f"{engine}: not white paper (or the mesh shows)"
