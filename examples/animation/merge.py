"""An animated example: two blobs that meet, merge and part again (the outlines change
their topology). The second blob's Center is keyed on its node.

    blender -b --factory-startup --python examples/animation/merge.py -- OUT.blend
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import common as C  # noqa: E402

MODEL = {"format": "blobtree-1", "name": "merge", "root": {"type": "blend", "children": [
    {"type": "point", "name": "still", "center": [0.0, 0.0, 0.0], "radius": 1.0},
    {"type": "point", "name": "moving", "center": [1.8, 0.0, 0.0], "radius": 0.9}]}}


def build(path):
    C.empty_scene()
    C.extension()
    tree = C.import_model(MODEL)
    start, end = C.FRAMES
    mid = (start + end) // 2
    C.key(C.node(tree, "moving"), "center", [(start, (1.8, 0.0, 0.0)), (mid, (0.5, 0.0, 0.15)),
                                             (end, (1.8, 0.0, 0.3))])
    C.stage(eye=(1.0, -6.5, 2.0), target=(0.9, 0.0, 0.1))
    C.save(path, tree)


if __name__ == "__main__":
    build(C.out_path("merge.blend"))
