"""A scene the Blender tiers animate: the two spheres example, the second following an
Empty keyed from x=0 (frame 1) to x=2 (frame 5), seen by a camera (needs bpy)."""
import bpy
from mathutils import Vector


def moving_spheres(example):
    """The tree (grid 10) and its driving Empty, at frame 1."""
    bpy.ops.blobtree_ink.import_json(filepath=example("two_spheres"), preview=True)
    tree = bpy.data.node_groups["two_spheres"]
    tree.ink.grid_resolution = 10
    a, b = [n for n in tree.nodes if getattr(n, "kind", "") == "point"]
    sc = bpy.context.scene
    empty = bpy.data.objects.new("Driver", None)
    sc.collection.objects.link(empty)
    b.center_object = empty
    for frame, x in ((1, 0.0), (5, 2.0)):
        empty.location = (x, 0.0, 0.0)
        empty.keyframe_insert("location", frame=frame)
    cam = bpy.data.objects.new("Cam", bpy.data.cameras.new("Cam"))
    sc.collection.objects.link(cam)
    sc.camera = cam
    cam.location = (0.8, -7.0, 0.5)
    cam.rotation_euler = (Vector((0.8, 0.0, 0.0)) - cam.location).to_track_quat("-Z", "Y").to_euler()
    sc.frame_set(1)
    return tree, empty
