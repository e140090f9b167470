"""Where a model sits in the scene: an imported model lands beside the others, and its
preview object places it (moving the preview moves the model and its ink)."""
import bpy
import numpy as np
from mathutils import Vector


def world_box(obj):
    c = np.array([obj.matrix_world @ Vector(v) for v in obj.bound_box])
    return c.min(0), c.max(0)


def test_an_imported_model_lands_beside_the_others(example):
    bpy.ops.blobtree_ink.import_json(filepath=example("pear"), preview=True)
    bpy.ops.blobtree_ink.import_json(filepath=example("jug"), preview=True)
    bpy.ops.blobtree_ink.import_json(filepath=example("torus"), preview=True)
    boxes = [world_box(bpy.data.node_groups[n].preview_object) for n in ("pear", "jug", "torus")]
    for (lo_a, hi_a), (lo_b, hi_b) in zip(boxes, boxes[1:]):
        assert lo_b[0] > hi_a[0]                       # side by side along x, not on top of each other
    assert bpy.context.view_layer.objects.active == bpy.data.node_groups["torus"].preview_object


def test_moving_the_preview_moves_the_model_and_its_ink(example):
    bpy.ops.blobtree_ink.import_json(filepath=example("sphere"), preview=True)
    tree = bpy.data.node_groups["sphere"]
    tree.ink.grid_resolution = 10
    tree.preview_object.location = (5.0, 1.0, -2.0)
    tree.preview_object.rotation_euler = (0.3, 0.0, 0.7)
    sc = bpy.context.scene
    cam = bpy.data.objects.new("Cam", bpy.data.cameras.new("Cam"))
    sc.collection.objects.link(cam)
    sc.camera = cam
    cam.location = (5.0, -4.0, -1.0)
    cam.rotation_euler = (Vector((5.0, 1.0, -2.0)) - cam.location).to_track_quat("-Z", "Y").to_euler()
    bpy.context.view_layer.update()
    assert bpy.ops.blobtree_ink.illustrate(tree_name="sphere", request="OUTLINES") == {"FINISHED"}
    ink = bpy.data.objects["sphere Ink"]
    assert ink.parent == tree.preview_object
    strokes = ink.data.layers["Silhouette"].frames[0].drawing.strokes
    assert len(strokes) == 1
    world = np.array([ink.matrix_world @ Vector(p.position) for p in strokes[0].points])
    r = 0.4543
    assert np.abs(np.linalg.norm(world - [5.0, 1.0, -2.0], axis=1) - r).max() < 1e-4   # on the moved sphere
    eye = np.array(cam.location)
    n = (world - [5.0, 1.0, -2.0]) / r
    assert np.abs(np.einsum("ij,ij->i", n, world - eye)).max() < 1e-3 * np.linalg.norm(eye)   # its silhouette
