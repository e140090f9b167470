"""Suggestive contours on the exact surface against Freestyle's on a dense mesh of the
same model, from the same camera: the README's side-by-side pictures and the seconds
each takes.

    ~/.cache/blobtree-ink/venv-bpy-5.0.1/bin/python bench/vs_freestyle.py [--model heart] [--size 600]
                                                                      [--dense 128] [--docs]

Ours: the command line's render of the model's silhouettes and suggestive contours
(`--style outlines --lines silhouette,suggestive`), which writes PNG, .blend and SVG.
Freestyle: in that .blend, the ink hidden, a mesh of the field polygonised at --dense
(smooth shaded, white), Freestyle's silhouettes, borders and suggestive contours (face
smoothness on), rendered by Cycles on the CPU at one sample. With --docs the two
pictures go to docs/suggestive_ours.png and docs/suggestive_freestyle.png.
"""
import argparse
import os
import shutil
import sys
import tempfile
import time

if "bpy" not in sys.modules:
    os.environ["BLENDER_USER_RESOURCES"] = tempfile.mkdtemp(prefix="bti-bench-")
import bpy  # noqa: E402

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(REPO, "examples", "animation"))
import common  # noqa: E402


def args():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else sys.argv[1:]
    ap = argparse.ArgumentParser()
    ap.add_argument("--model", default="heart")
    ap.add_argument("--size", type=int, default=600)
    ap.add_argument("--dense", type=int, default=128)
    ap.add_argument("--docs", action="store_true")
    return ap.parse_args(argv)


def ours(ext, path, out, size):
    t0 = time.perf_counter()
    code = ext.cli.main(["render", path, "--out", out, "--size", str(size), "--style", "outlines",
                         "--lines", "silhouette,suggestive"])
    if code != 0:
        raise SystemExit(f"the command line's render failed ({code})")
    return time.perf_counter() - t0


def freestyle(ext, path, blend, png, dense):
    """Freestyle's lines on a dense mesh in the command line's scene: seconds of the mesh
    and of the render."""
    bpy.ops.wm.open_mainfile(filepath=blend)
    scene = bpy.context.scene
    ink = next(o for o in scene.objects if o.type == "GREASEPENCIL")
    ink.hide_render = True
    t0 = time.perf_counter()
    ev = ext.model.Evaluator(ext.model.load(path))
    m = ext.blackboard.polygonise.polygonise(ev, dense)
    mesh = bpy.data.meshes.new("dense")
    mesh.from_pydata(m.vertices.tolist(), [], m.quads.tolist())
    mesh.shade_smooth()
    obj = bpy.data.objects.new("dense", mesh)
    obj.matrix_world = ink.matrix_world.copy()
    scene.collection.objects.link(obj)
    t_mesh = time.perf_counter() - t0
    white = bpy.data.materials.new("white")
    white.use_nodes = True
    nodes = white.node_tree.nodes
    nodes.clear()
    emit = nodes.new("ShaderNodeEmission")
    emit.inputs[0].default_value = (1, 1, 1, 1)
    white.node_tree.links.new(emit.outputs[0], nodes.new("ShaderNodeOutputMaterial").inputs[0])
    mesh.materials.append(white)
    world = bpy.data.worlds.new("paper")
    world.use_nodes = True
    world.node_tree.nodes["Background"].inputs[0].default_value = (1, 1, 1, 1)
    scene.world = world
    scene.render.engine = "CYCLES"
    scene.cycles.device = "CPU"
    scene.cycles.samples = 1
    scene.render.film_transparent = False
    scene.view_settings.view_transform = "Standard"
    scene.render.use_freestyle = True
    fs = scene.view_layers[0].freestyle_settings
    fs.use_smoothness = True
    ls = fs.linesets[0] if len(fs.linesets) else fs.linesets.new("lines")
    ls.linestyle = ls.linestyle or bpy.data.linestyles.new("lines")
    ls.linestyle.thickness = 1.5
    ls.select_by_edge_types = True
    ls.select_silhouette = ls.select_border = ls.select_suggestive_contour = True
    ls.select_crease = False
    scene.render.filepath = png
    t0 = time.perf_counter()
    bpy.ops.render.render(write_still=True)
    return t_mesh, time.perf_counter() - t0


def main():
    a = args()
    ext = common.extension()
    path = os.path.join(REPO, "examples", f"{a.model}.json")
    out = tempfile.mkdtemp(prefix="bti-freestyle-")
    t_ours = ours(ext, path, out, a.size)
    ours_png = os.path.join(out, f"{a.model}.png")
    fs_png = os.path.join(out, f"{a.model}_freestyle.png")
    t_mesh, t_render = freestyle(ext, path, os.path.join(out, f"{a.model}.blend"), fs_png, a.dense)
    print(f"{a.model}, {a.size} px: ours {t_ours:.2f} s (the whole command: outlines, PNG, .blend, SVG); "
          f"Freestyle {t_mesh + t_render:.2f} s (a dense mesh, grid {a.dense}: {t_mesh:.2f} s; "
          f"the render: {t_render:.2f} s)")
    if a.docs:
        for src, name in ((ours_png, "suggestive_ours.png"), (fs_png, "suggestive_freestyle.png")):
            shutil.copy(src, os.path.join(REPO, "docs", name))
        print("wrote docs/suggestive_ours.png and docs/suggestive_freestyle.png")
    else:
        print(f"pictures: {ours_png}, {fs_png}")


if __name__ == "__main__":
    main()
