"""An animated example: the heart turning and moving as one piece. Its model sits in a
Transform node that follows an Empty, keyed to turn a quarter round and move across
over the frames.

    blender -b --factory-startup --python examples/animation/rigid.py -- OUT.blend
"""
import json
import os
import sys

import bpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import common as C  # noqa: E402


def build(path):
    C.empty_scene()
    C.extension()
    heart = json.load(open(os.path.join(C.REPO, "examples", "heart.json")))
    heart["name"] = "rigid"
    heart["root"] = {"type": "transform", "name": "motion", "child": heart["root"]}
    tree = C.import_model(heart)
    empty = bpy.data.objects.new("Motion", None)
    bpy.context.scene.collection.objects.link(empty)
    C.node(tree, "motion").source_object = empty
    start, end = C.FRAMES
    C.key(empty, "location", [(start, (-0.6, 0.0, 0.0)), (end, (0.6, 0.3, 0.2))])
    C.key(empty, "rotation_euler", [(start, C.degrees(0, 0, -45)), (end, C.degrees(0, 0, 45))])
    C.stage(eye=(5.0, -9.0, 4.0), target=(0.0, 0.0, 0.0))
    C.save(path, tree)


if __name__ == "__main__":
    build(C.out_path("rigid.blend"))
