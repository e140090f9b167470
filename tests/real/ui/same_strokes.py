"""Real-UI test script: for each of three styles, the strokes a modal run draws (the
operator invoked with an event loop, its pipeline on the worker thread) and the strokes
the same requests draw through `execute` (the background path) are saved for the test
to compare: one pipeline, the same strokes."""
import os
import sys

import bpy
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))))
sys.path.insert(0, os.path.join(REPO, "tests"))
import strokes_match as SM  # noqa: E402
from uistep import EXT, OUT, Steps, record, start_with_example  # noqa: E402

PRESETS = ("STIPPLED", "HATCHED", "SILHOUETTE_SHADING")


def save(name):
    drawing = SM.from_grease_pencil(bpy.data.objects["pear Ink"])
    np.savez(os.path.join(OUT, f"{name}.npz"), **SM.to_npz(drawing))
    return {k: len(v) for k, v in drawing.items()}


def run():
    win, view3d, region = yield from start_with_example("pear")
    ill = sys.modules[EXT + ".operators.illustrate"]
    counts = {}
    for preset in PRESETS:
        tree = bpy.data.node_groups["pear"]
        bpy.ops.blobtree_ink.apply_preset(tree_name="pear", preset=preset)
        tree.ink.grid_resolution, tree.ink.seed = 12, 2
        for request in ("OUTLINES", "PLACE_STROKES"):
            with bpy.context.temp_override(window=win, area=view3d, region=region):
                res = bpy.ops.blobtree_ink.illustrate("INVOKE_DEFAULT", tree_name="pear", request=request)
            assert res == {"RUNNING_MODAL"}, res
            for _ in range(600):
                if ill.last_run.get("state") != "running":
                    break
                yield 0.1
            assert ill.last_run.get("state") == "done", ill.last_run
        counts[f"modal-{preset}"] = save(f"modal-{preset}")
        for request in ("OUTLINES", "PLACE_STROKES"):
            with bpy.context.temp_override(window=win, area=view3d, region=region):
                assert bpy.ops.blobtree_ink.illustrate("EXEC_DEFAULT", tree_name="pear", request=request) == {"FINISHED"}
        counts[f"exec-{preset}"] = save(f"exec-{preset}")
        yield 0.2
    record(counts=counts, presets=list(PRESETS))


Steps(run())
