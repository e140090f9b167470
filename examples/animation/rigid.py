"""An animated example: the heart turning and moving as one piece. Its object (the
model's preview, which places the model and carries its ink) is the child of an Empty,
keyed to turn by 50 degrees (about two a frame) and move across over the frames: the
model itself does not change, only where it is seen from.

    blender -b --factory-startup --python examples/animation/rigid.py -- OUT.blend
"""
import os
import sys

import bpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import common as C  # noqa: E402


def build(path):
    C.empty_scene()
    C.extension()
    tree = C.import_model(dict(C.example("heart"), name="rigid"))
    empty = bpy.data.objects.new("Motion", None)
    bpy.context.scene.collection.objects.link(empty)
    tree.preview_object.parent = empty
    start, end = C.FRAMES
    C.key(empty, "location", [(start, (-0.4, 0.0, 0.0)), (end, (0.4, 0.2, 0.1))])
    C.key(empty, "rotation_euler", [(start, C.degrees(0, 0, -25)), (end, C.degrees(0, 0, 25))])
    C.stage(eye=(5.0, -9.0, 4.0), target=(0.0, 0.0, 0.0))
    C.save(path, tree)


if __name__ == "__main__":
    build(C.out_path("rigid.blend"))
