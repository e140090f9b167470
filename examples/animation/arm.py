"""An animated example: an arm of blended segments that bends and tapers, its Bend and
Taper rates keyed on their nodes.

    blender -b --factory-startup --python examples/animation/arm.py -- OUT.blend
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import common as C  # noqa: E402

SEGMENTS = [([-2.0, 0.0, 0.0], [-1.0, 0.0, 0.05]), ([-1.0, 0.0, 0.05], [0.0, 0.0, 0.0]),
            ([0.0, 0.0, 0.0], [1.0, 0.0, -0.05]), ([1.0, 0.0, -0.05], [2.0, 0.0, 0.0])]
MODEL = {"format": "blobtree-1", "name": "arm", "root": {
    "type": "bend", "name": "bend", "rate": 0.0, "child": {
        "type": "taper", "name": "taper", "rate": 0.0, "child": {"type": "blend", "children": [
            {"type": "segment", "a": a, "b": b, "radius": 1.0} for a, b in SEGMENTS] + [
            {"type": "point", "name": "hand", "center": [2.1, 0.0, 0.0], "radius": 1.2}]}}}}


def build(path):
    C.empty_scene()
    C.extension()
    tree = C.import_model(MODEL)
    start, end = C.FRAMES
    C.key(C.node(tree, "bend"), "rate", [(start, 0.0), (end, 0.45)])
    C.key(C.node(tree, "taper"), "rate", [(start, 0.0), (end, -0.12)])
    C.stage(eye=(0.0, -9.0, 2.5), target=(0.0, 0.0, 0.6))
    C.save(path, tree)


if __name__ == "__main__":
    build(C.out_path("arm.blend"))
