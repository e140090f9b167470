"""Grease Pencil output and the render command: layers, bulk-written strokes, one
object per model, PNG/.blend/SVG outputs."""
import io
import os
import xml.etree.ElementTree as ET

import bpy
import numpy as np
import pytest


def mod(ext, name):
    from importlib import import_module
    return import_module(f"{ext.__name__}.{name}")


def stroke_set(ext, n_lines=3, n_dots=2):
    S = mod(ext, "strokes")
    s = S.StrokeSet()
    for i in range(n_lines):
        k = 5 + i
        s.add("Silhouette", S.Stroke(np.c_[np.arange(k), np.full(k, i), np.zeros(k)].astype(float),
                                     np.full(k, 0.01), np.linspace(0.5, 1, k), cyclic=(i == 0)))
    for i in range(n_dots):
        s.add("Stipples", S.Stroke(np.array([[i, 0.0, 1.0]]), np.array([0.02]), np.array([1.0]), dots=True))
    return s


def test_writer_puts_strokes_on_their_layers_in_bulk(ext):
    W = mod(ext, "grease_pencil.writer")
    obj = W.ink_object("model Ink")
    W.write(obj, stroke_set(ext), frame=1)
    gp = obj.data
    assert [l.name for l in gp.layers] == ["Silhouette", "Crease", "Curvature", "Hatching", "Stipples", "Strokes"]
    sil = gp.layers["Silhouette"].frames[0].drawing
    assert len(sil.strokes) == 3 and [len(s.points) for s in sil.strokes] == [5, 6, 7]
    assert sil.strokes[0].cyclic and not sil.strokes[1].cyclic
    p = sil.strokes[2].points[3]
    assert tuple(p.position) == (3.0, 2.0, 0.0) and p.radius == pytest.approx(0.01)
    assert sil.strokes[0].points[4].opacity == pytest.approx(1.0)
    dots = gp.layers["Stipples"].frames[0].drawing
    assert [len(s.points) for s in dots.strokes] == [1, 1]
    mats = [m.name for m in gp.materials]
    assert gp.materials[dots.strokes[0].material_index].grease_pencil.mode == "DOTS"
    assert gp.materials[sil.strokes[0].material_index].grease_pencil.mode == "LINE"
    assert len(mats) == 2


def test_running_again_replaces_the_drawing_and_keeps_one_object(ext):
    W = mod(ext, "grease_pencil.writer")
    W.write(W.ink_object("model Ink"), stroke_set(ext, 3, 2))
    W.write(W.ink_object("model Ink"), stroke_set(ext, 1, 0))
    gps = [o for o in bpy.data.objects if o.type == "GREASEPENCIL"]
    assert len(gps) == 1
    assert len(gps[0].data.layers["Silhouette"].frames[0].drawing.strokes) == 1
    assert len(gps[0].data.layers["Stipples"].frames[0].drawing.strokes) == 0
    assert len(gps[0].data.layers["Silhouette"].frames) == 1


def test_render_command_writes_png_blend_and_svg(ext, example, tmp_path):
    out = io.StringIO()
    code = ext.cli.main(["render", example("pear"), "--out", str(tmp_path), "--size", "256", "--grid", "14"], out=out)
    assert code == 0, out.getvalue()
    png, blend, svg = (tmp_path / f"pear.{e}" for e in ("png", "blend", "svg"))
    assert png.exists() and blend.exists() and svg.exists()
    assert not [p for p in os.listdir(tmp_path) if ".partial" in p]
    img = bpy.data.images.load(str(png))
    px = np.array(img.pixels[:]).reshape(img.size[1], img.size[0], img.channels)[..., :3]
    assert img.size[0] == 256
    assert np.median(px) > 0.95                     # white paper
    dark = (px.mean(axis=2) < 0.5).mean()
    assert 0.002 < dark < 0.2                       # ink lines, not a blank or a black image
    root = ET.parse(svg).getroot()
    paths = [e for e in root.iter() if e.tag.endswith(("path", "polyline", "polygon"))]
    bpy.ops.wm.open_mainfile(filepath=str(blend))
    gp = [o for o in bpy.data.objects if o.type == "GREASEPENCIL"]
    assert len(gp) == 1 and bpy.context.scene.camera is not None
    layers = {l.name: len(l.frames[0].drawing.strokes) if len(l.frames) else 0 for l in gp[0].data.layers}
    assert layers["Silhouette"] >= 1 and layers["Crease"] >= 1    # the outline and the bite's rim
    assert len(paths) == sum(layers.values())                       # every stroke reached the SVG


def test_visible_strokes_lie_on_the_surface_and_face_the_eye(ext, example):
    M = mod(ext, "model")
    R = mod(ext, "grease_pencil.render")
    A = mod(ext, "agents")
    V = mod(ext, "blackboard.view")
    model = M.load(example("sphere"))
    ev = M.Evaluator(model)
    centre, radius, eye = R.plan_view(ev)
    s = A.Session(ev, V.View(eye=eye), A.Settings(resolution=12))
    s.request("OUTLINES")
    s.run()
    strokes = mod(ext, "strokes.style").outline_strokes(s.outlines(), ev, eye, 0.01)
    pts = np.concatenate([st.points for st in strokes.layers["Silhouette"]])
    f, g = ev.field_grad(pts)
    assert np.abs(f - 0.5).max() < 1e-9
    assert strokes.count("Silhouette") == 1        # a sphere's whole silhouette is visible


def test_render_rejects_bad_options(ext, example, tmp_path, capsys):
    assert ext.cli.main(["render", example("pear"), "--out", str(tmp_path / "missing" / "deeper")]) == 1
    assert "does not exist (nor does its parent)" in capsys.readouterr().err
    assert ext.cli.main(["render", example("pear"), "--out", str(tmp_path), "--grid", "500"]) == 1
    assert "resolution must be a whole number from 8 to 128" in capsys.readouterr().err
    assert ext.cli.main(["render", example("pear"), "--out", str(tmp_path), "--size", "10"]) == 1
    assert "--size must be from 64 to 8192" in capsys.readouterr().err
    assert not os.listdir(tmp_path)


def test_render_with_hatching_and_stipples(ext, example, tmp_path):
    out = io.StringIO()
    code = ext.cli.main(["render", example("pear"), "--out", str(tmp_path), "--size", "256", "--grid", "12",
                         "--requests", "outlines,hatching,stipples"], out=out)
    assert code == 0, out.getvalue()
    bpy.ops.wm.open_mainfile(filepath=str(tmp_path / "pear.blend"))
    gp = [o for o in bpy.data.objects if o.type == "GREASEPENCIL"][0].data
    hatch = gp.layers["Hatching"].frames[0].drawing
    dots = gp.layers["Stipples"].frames[0].drawing
    assert len(hatch.strokes) > 10 and all(len(s.points) >= 2 for s in hatch.strokes)
    assert len(dots.strokes) > 10 and all(len(s.points) == 1 for s in dots.strokes)
    assert {gp.materials[s.material_index].grease_pencil.mode for s in dots.strokes} == {"DOTS"}
    root = ET.parse(tmp_path / "pear.svg").getroot()
    circles = [e for e in root.iter() if e.tag.endswith("circle")]
    assert len(circles) == len(dots.strokes)      # the exporter drops one-point strokes: added back
    w, h = (float(x) for x in root.get("viewBox").split()[2:])
    assert all(0 <= float(c.get("cx")) <= w and 0 <= float(c.get("cy")) <= h for c in circles)


def test_bad_requests_are_named(ext, example, tmp_path, capsys):
    assert ext.cli.main(["render", example("pear"), "--out", str(tmp_path), "--requests", "outlines,shading"]) == 1
    assert "requests must be some of outlines, hatching, stipples" in capsys.readouterr().err


def test_render_a_flocked_jug_with_chain_and_short_strokes(ext, example, tmp_path):
    out = io.StringIO()
    code = ext.cli.main(["render", example("jug"), "--out", str(tmp_path), "--size", "256", "--grid", "14",
                         "--style", "flocked", "--requests", "outlines,hatching,chains,short",
                         "--weights", "flow=1,wander=0.2,separation=0.6,alignment=0.5,cohesion=0.05",
                         "--chain-step", "2", "--light=-1,-1,1"], out=out)
    assert code == 0, out.getvalue()
    bpy.ops.wm.open_mainfile(filepath=str(tmp_path / "jug.blend"))
    gp = [o for o in bpy.data.objects if o.type == "GREASEPENCIL"][0].data
    hatch = gp.layers["Hatching"].frames[0].drawing
    short = gp.layers["Strokes"].frames[0].drawing
    assert len(hatch.strokes) > 20 and len(short.strokes) > 5
    r = np.array([p.radius for s in hatch.strokes for p in s.points])
    o = np.array([p.opacity for s in hatch.strokes for p in s.points])
    assert r.min() < 0.8 * r.max() and o.min() < 0.8 * o.max()     # per-point radius and opacity from the light
    sun = bpy.data.objects["BlobTree Ink Light"]
    towards = np.array(sun.matrix_world.to_3x3().col[2])
    assert np.allclose(towards, np.array([-1, -1, 1]) / np.sqrt(3), atol=1e-6)   # the .blend's sun is the light used


@pytest.mark.parametrize("args, message", [
    (["--weights", "gravity=1"], "unknown behaviour 'gravity'"),
    (["--weights", "flow=lots"], "'flow=lots' is not name=number"),
    (["--axis", "1,2"], "--axis must be three comma-separated numbers"),
    (["--contrast", "5"], "contrast must be a number from 0 to 1"),
    (["--light", "0,0,0"], "light direction must be three finite numbers, not all zero"),
    (["--chain-step", "0"], "chain_step must be a whole number from 1"),
])
def test_bad_style_options_are_named(ext, example, tmp_path, capsys, args, message):
    assert ext.cli.main(["render", example("pear"), "--out", str(tmp_path), "--grid", "8"] + args) == 1
    assert message in capsys.readouterr().err
    assert not os.listdir(tmp_path)


def test_stipples_alone_show_in_the_png(ext, example, tmp_path):
    """Stipples are one-point DOTS strokes in the .blend and visible in the render."""
    out = io.StringIO()
    code = ext.cli.main(["render", example("pear"), "--out", str(tmp_path), "--size", "256", "--grid", "12",
                         "--requests", "stipples"], out=out)
    assert code == 0, out.getvalue()
    bpy.ops.wm.open_mainfile(filepath=str(tmp_path / "pear.blend"))
    gp = [o for o in bpy.data.objects if o.type == "GREASEPENCIL"][0].data
    dots = gp.layers["Stipples"].frames[0].drawing
    assert len(dots.strokes) > 50
    assert {gp.materials[s.material_index].grease_pencil.mode for s in dots.strokes} == {"DOTS"}
    img = bpy.data.images.load(str(tmp_path / "pear.png"))
    px = np.array(img.pixels[:]).reshape(img.size[1], img.size[0], 4)
    dark = (px[..., :3].max(axis=2) < 0.6).sum()
    assert dark > 100, f"only {dark} dark pixels: the stipples did not render"


def test_style_options_reach_the_style(ext):
    import argparse
    CR = mod(ext, "grease_pencil.cli_render")
    parser = argparse.ArgumentParser()
    CR.add_parser(parser.add_subparsers())
    args = parser.parse_args(["render", "m.json", "--out", "o", "--style", "hatched", "--field", "axis",
                              "--axis", "1,0,0", "--cross-field", "contour", "--weights", "sketchy",
                              "--flock-size", "3", "--surface", "concave", "--contrast", "0.25",
                              "--requests", "hatching,chains"])
    st = CR.style_from_args(args)
    assert (st.hatch_field, st.hatch_axis, st.cross_field, st.weights) == ("axis", (1.0, 0.0, 0.0), "contour", "sketchy")
    assert (st.flock_size, st.surface, st.contrast) == (3, "concave", 0.25)
    assert st.hatching and st.chains and not (st.outlines or st.stipples or st.short) and st.cross_hatching
    args = parser.parse_args(["render", "m.json", "--out", "o", "--style", "hatched", "--no-cross"])
    assert CR.style_from_args(args).cross_hatching is False
