"""Animated examples frame by frame: time per frame, coherence of the strokes, and what
an artist would do instead.

    ~/.cache/blobtree-ink/venv-bpy-5.0.1/bin/python bench/animation.py [--examples rigid,merge,arm]
                                                                      [--frames 1-12] [--lineart-res 64]
    tools/blender -b --factory-startup --python bench/animation.py -- [same options]

Builds each example of examples/animation in memory and illustrates its frames in
order, each through the tree's look (outlines and hatching) as a render or a bake does.
For each example it prints:

- seconds per frame: the outlines (compiling the tree at the frame, the rough
  polygonisation, the agents) and the whole frame, from scratch and going on from the
  last frame (pipeline.continuation), frames after the first; and how far the outlines
  going on from the last frame are from the scratch ones (1 px at 1024 px);
- coherence of the hatching from one frame to the next: the share of the strokes' marks
  that survive, births and deaths per frame, and the drift of surviving strokes relative
  to the surface's own motion, in pixels of a 1024-pixel-wide camera image: a stroke's
  start (its mark) and its points on average, against where the part it lies on carried
  the previous frame's points (each primitive's warps and transforms at both frames);
- the alternative: a dense mesh of the field per frame (polygonised at --lineart-res)
  and Blender's Line Art on it, seconds per frame.
"""
import argparse
import os
import sys
import tempfile
import time

if "bpy" not in sys.modules:
    os.environ["BLENDER_USER_RESOURCES"] = tempfile.mkdtemp(prefix="bti-bench-")
import bpy  # noqa: E402
import numpy as np  # noqa: E402
from bpy_extras.object_utils import world_to_camera_view  # noqa: E402
from mathutils import Matrix, Vector  # noqa: E402

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(REPO, "examples", "animation"))
import common  # noqa: E402

WIDTH = 1024                       # the camera image's width for drifts, in pixels


def args():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else sys.argv[1:]
    ap = argparse.ArgumentParser()
    ap.add_argument("--examples", default="rigid,merge,arm")
    ap.add_argument("--frames", default="1-12")
    ap.add_argument("--lineart-res", type=int, default=64)
    a = ap.parse_args(argv)
    first, last = (int(x) for x in a.frames.split("-"))
    return a.examples.split(","), range(first, last + 1), a.lineart_res


def projector(scene, place):
    """Model points to pixels of a WIDTH-wide camera image at the scene's current frame."""
    cam = scene.camera
    h = WIDTH * scene.render.resolution_y / scene.render.resolution_x
    M = np.array(place)

    def px(P):
        W = np.asarray(P, float) @ M[:3, :3].T + M[:3, 3]
        uv = np.array([world_to_camera_view(scene, cam, Vector(w))[:2] for w in W]).reshape(-1, 2)
        return uv * [WIDTH, h]
    return px


def frame(ext, tree, scene, f, previous=None):
    """One frame, from scratch or going on from ``previous`` (the last frame's
    continuation): seconds of its outlines and of the whole frame, its hatching strokes by
    mark (primitive, mark, points), its outlines in pixels, its primitives, its projector
    and its continuation."""
    FR, PL = ext.operators.frames, ext.pipeline
    scene.frame_set(f)
    t0 = time.perf_counter()
    job, place = FR.frame_job(tree, scene)
    fresh = previous is False                                # from scratch
    ill = PL.Illustration(job, previous=None if fresh else previous, remember=not fresh)
    while ill.stage in ("init", "sampling", "outlines"):
        ill.step()
    t_outlines = time.perf_counter() - t0
    res = ill.run()
    t_full = time.perf_counter() - t0
    marks = ill.marks("hatching")
    at = {k: (i, p) for k, i, p in zip(marks.keys.tolist(), marks.prim.tolist(), marks.points)}
    strokes = {}
    for s in res.strokes.layers["Hatching"]:
        if s.mark in at:                                     # the hatching's own (not a cross-hatching's)
            strokes.setdefault(s.mark, []).append(s.points)  # a stroke split where it goes out of sight
    strokes = {k: (at[k][0], at[k][1], v) for k, v in strokes.items()}
    px = projector(scene, place)
    lines = [px(o.points) for o in ill.sampling.outlines]
    return dict(outlines=t_outlines, full=t_full, strokes=strokes, placed=ext.model.owners.owners(ill.ev).placed,
                px=px, lines=lines, next=ill.continuation())


def same_outlines(a, b):
    """The share of b's outline points within a pixel of a's outlines, and of a's of b's."""
    def share(x, y):
        P = np.concatenate(x) if x else np.zeros((0, 2))
        return float(np.mean([_to_polylines(p, y) < 1.0 for p in P])) if len(P) else 1.0
    return min(share(a["lines"], b["lines"]), share(b["lines"], a["lines"]))


ext_skins = None            # model.skins of the extension (set in main)


def coherence(a, b):
    """Survival, births, deaths and drifts from frame a to frame b: of a surviving mark,
    and of its stroke's points from the polyline its previous stroke was carried to."""
    ka, kb = set(a["strokes"]), set(b["strokes"])
    both = sorted(ka & kb)
    marks, paths = [], []
    for k in both:
        i, ma, pa = a["strokes"][k]
        _, mb, pb = b["strokes"][k]
        carry = _carrier(a["placed"][i], b["placed"][i], ext_skins)
        marks.append(np.linalg.norm(b["px"](carry(ma[None])) - b["px"](mb[None])))
        now = np.concatenate([b["px"](p) for p in pb])
        paths.append(np.mean([_to_polylines(q, [b["px"](carry(p)) for p in pa]) for q in now]))
    return dict(survival=len(both) / max(len(ka), 1), births=len(kb - ka), deaths=len(ka - kb),
                mark_drift=float(np.mean(marks)) if marks else float("nan"),
                path_drift=float(np.mean(paths)) if paths else float("nan"),
                path_median=float(np.median(paths)) if paths else float("nan"))


def _carrier(a, b, skins):
    """Model points of frame a to frame b as a primitive carries them: into its own
    coordinates, moved with its centre (a keyed Center), out through its warps then."""
    move = skins.Shape(b.node, 0.5).centre - skins.Shape(a.node, 0.5).centre
    return lambda P: b.to_model(a.to_local(P) + move)


def _to_polylines(q, lines):
    """The distance from a point to the nearest of some polylines (pixels)."""
    best = np.inf
    for L in lines:
        if len(L) == 1:
            best = min(best, float(np.linalg.norm(q - L[0])))
            continue
        a, b = L[:-1], L[1:]
        ab = b - a
        t = np.clip(np.einsum("ij,ij->i", q - a, ab) / np.maximum(np.einsum("ij,ij->i", ab, ab), 1e-300), 0, 1)
        best = min(best, float(np.linalg.norm(a + t[:, None] * ab - q, axis=1).min()))
    return best


def lineart_seconds(ext, tree, scene, frames, res):
    """A dense mesh of the field per frame and a Line Art modifier on it: seconds per frame."""
    poly = ext.blackboard.polygonise
    comp, M = ext.blobtree_nodes.compile, ext.model
    mesh = bpy.data.meshes.new("dense")
    obj = bpy.data.objects.new("dense", mesh)
    scene.collection.objects.link(obj)
    gp = ext.grease_pencil.compat.grease_pencil_data().new("lineart")
    art = bpy.data.objects.new("lineart", gp)
    scene.collection.objects.link(art)
    gp.layers.new("Lines")
    mat = bpy.data.materials.new("lines")
    bpy.data.materials.create_gpencil_data(mat)
    gp.materials.append(mat)
    mod = art.modifiers.new("Line Art", "LINEART")
    mod.source_type = "OBJECT"
    mod.source_object = obj
    mod.target_layer = "Lines"
    mod.target_material = mat
    seconds = []
    for f in frames:
        scene.frame_set(f)
        t0 = time.perf_counter()
        m = poly.polygonise(M.Evaluator(comp.compile_tree(tree)), res)
        mesh.clear_geometry()
        mesh.from_pydata(m.vertices.tolist(), [], m.quads.tolist())
        mesh.update()
        dg = bpy.context.evaluated_depsgraph_get()
        dg.update()
        lines = sum(len(l.frames[0].drawing.strokes) if len(l.frames) else 0
                    for l in art.evaluated_get(dg).data.layers)
        seconds.append(time.perf_counter() - t0)
    bpy.data.objects.remove(art)
    bpy.data.objects.remove(obj)
    return float(np.mean(seconds)), lines


def main():
    global ext_skins
    names, frames, res = args()
    ext = common.extension()
    ext_skins = ext.model.skins
    print(f"Blender {bpy.app.version_string}; frames {frames.start}-{frames.stop - 1}; camera image {WIDTH} px wide")
    for name in names:
        example = __import__(name)
        example.build(os.path.join(tempfile.mkdtemp(), f"{name}.blend"))
        tree, scene = bpy.data.node_groups[name], bpy.context.scene
        scratch, got, previous = [], [], None
        for f in frames:                                     # interleaved: the machine's drift hits both alike
            scratch.append(frame(ext, tree, scene, f, previous=False))
            got.append(frame(ext, tree, scene, f, previous))
            previous = got[-1]["next"]
        pairs = [coherence(a, b) for a, b in zip(got, got[1:])]
        mean = {k: float(np.nanmean([p[k] for p in pairs])) for k in pairs[0]}
        worst = min(p["survival"] for p in pairs)
        later = slice(1, None)                               # the first frame has nothing to go on from
        s_out, i_out = np.mean([g["outlines"] for g in scratch[later]]), np.mean([g["outlines"] for g in got[later]])
        s_all, i_all = np.mean([g["full"] for g in scratch[later]]), np.mean([g["full"] for g in got[later]])
        same = min(same_outlines(a, b) for a, b in zip(scratch, got))
        print(f"\n{name}: {len(got)} frames, {np.mean([len(g['strokes']) for g in got]):.0f} hatching marks a frame")
        print(f"  outlines: {s_out:.3f} s/frame from scratch, {i_out:.3f} going on from the last frame "
              f"(x{i_out / s_out:.2f}); whole frame {s_all:.3f} and {i_all:.3f} s/frame (x{i_all / s_all:.2f})")
        print(f"  the outlines going on from the last frame are the scratch ones: at least {100 * same:.1f} % of "
              f"either's points within 1 px of the other's, every frame")
        print(f"  coherence: {100 * mean['survival']:.1f} % of marks survive a frame (worst {100 * worst:.1f} %), "
              f"{mean['births']:.1f} births and {mean['deaths']:.1f} deaths a frame")
        print(f"  drift against the surface's motion: marks {mean['mark_drift']:.3f} px, "
              f"strokes {mean['path_drift']:.3f} px (mean; a stroke's median {mean['path_median']:.3f} px)")
        la, lines = lineart_seconds(ext, tree, scene, frames, res)
        print(f"  instead: a dense mesh (grid {res}) and Line Art, {la:.3f} s/frame ({lines} lines)")


if __name__ == "__main__":
    main()
