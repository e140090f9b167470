"""Grease Pencil output and the render command: layers, bulk-written strokes, requests
that build a drawing up, one object per model, PNG/.blend/SVG outputs, and the same
strokes through the command line and the operator."""
import io
import os
import re
import xml.etree.ElementTree as ET

import bpy
import numpy as np
import pytest
import strokes_match as SM


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


def pixels(path):
    img = bpy.data.images.load(str(path))
    px = np.array(img.pixels[:]).reshape(img.size[1], img.size[0], img.channels)[..., :3]
    bpy.data.images.remove(img)
    return px


def test_writer_puts_strokes_on_their_layers_in_bulk(ext):
    W = mod(ext, "grease_pencil.writer")
    obj = W.ink_object("model Ink")
    W.write_set(obj, stroke_set(ext), frame=1)
    gp = obj.data
    assert [l.name for l in gp.layers] == list(mod(ext, "strokes.data").LAYERS)
    sil = gp.layers["Silhouette"].frames[0].drawing
    assert len(sil.strokes) == 3 and [len(s.points) for s in sil.strokes] == [5, 6, 7]
    assert sil.strokes[0].cyclic and not sil.strokes[1].cyclic
    p = sil.strokes[2].points[3]
    assert tuple(p.position) == (3.0, 2.0, 0.0) and p.radius == pytest.approx(0.01)
    assert sil.strokes[0].points[4].opacity == pytest.approx(1.0)
    dots = gp.layers["Stipples"].frames[0].drawing
    assert [len(s.points) for s in dots.strokes] == [1, 1]
    mats = [m.name for m in gp.materials]
    dots_style = gp.materials[dots.strokes[0].material_index].grease_pencil
    assert dots_style.mode == "DOTS"
    if bpy.app.version >= (5, 2, 0):            # one dot per one-point stroke (RADIUS would draw none)
        assert (dots_style.placement_mode, dots_style.placement_count) == ("COUNT", 1)
    assert gp.materials[sil.strokes[0].material_index].grease_pencil.mode == "LINE"
    assert len(mats) == 2


def test_a_result_replaces_its_own_layers_and_adds_to_its_appended_ones(ext):
    W = mod(ext, "grease_pencil.writer")
    PL = mod(ext, "pipeline")
    S = mod(ext, "strokes")
    obj = W.ink_object("model Ink")
    W.write_set(obj, stroke_set(ext, 3, 2))
    single = S.StrokeSet()
    single.add("Single Strokes", S.Stroke(np.zeros((4, 3)) + [0, 0, 5], np.full(4, 0.03), np.full(4, 0.5)))
    W.write(obj, PL.Result(single, owned=(), appended=("Single Strokes",), progress=PL.Progress()))
    W.write(obj, PL.Result(single, owned=(), appended=("Single Strokes",), progress=PL.Progress()))
    gp = obj.data
    layer = lambda n: gp.layers[n].frames[0].drawing.strokes      # noqa: E731
    assert len(layer("Single Strokes")) == 2                       # added to, not replaced
    assert layer("Single Strokes")[1].points[2].radius == pytest.approx(0.03)
    assert layer("Single Strokes")[0].points[0].opacity == pytest.approx(0.5)
    # a result owning Silhouette (with no strokes) clears it; the stipples are not its own
    W.write(obj, PL.Result(S.StrokeSet(), owned=("Silhouette",), appended=(), progress=PL.Progress()))
    assert len(layer("Silhouette")) == 0 and len(layer("Stipples")) == 2 and len(layer("Single Strokes")) == 2
    assert layer("Stipples")[1].points[0].position[0] == pytest.approx(1.0)


def test_running_again_replaces_the_drawing_and_keeps_one_object(ext):
    W = mod(ext, "grease_pencil.writer")
    W.write_set(W.ink_object("model Ink"), stroke_set(ext, 3, 2))
    W.write_set(W.ink_object("model Ink"), stroke_set(ext, 1, 0))
    gps = [o for o in bpy.data.objects if o.type == "GREASEPENCIL"]
    assert len(gps) == 1
    assert len(gps[0].data.layers["Silhouette"].frames[0].drawing.strokes) == 1
    assert len(gps[0].data.layers["Stipples"].frames[0].drawing.strokes) == 0
    assert len(gps[0].data.layers["Silhouette"].frames) == 1


def test_render_command_writes_png_blend_and_svg(ext, example, tmp_path):
    out = io.StringIO()
    code = ext.cli.main(["render", example("pear"), "--out", str(tmp_path), "--size", "768", "--grid", "14"], out=out)
    assert code == 0, out.getvalue()
    png, blend, svg = (tmp_path / f"pear.{e}" for e in ("png", "blend", "svg"))
    assert png.exists() and blend.exists() and svg.exists()
    assert not [p for p in os.listdir(tmp_path) if ".partial" in p]
    px = pixels(png)
    assert px.shape[:2] == (768, 768)
    assert np.median(px) > 0.95                     # white paper
    ink = px.mean(axis=2) < 0.6
    assert 0.002 < ink.mean() < 0.2                 # ink lines, not a blank or a black image
    # the camera is cut close about the drawing: it fills the frame, with a margin all round
    rows, cols = np.flatnonzero(ink.any(axis=1)), np.flatnonzero(ink.any(axis=0))
    spans = np.array([rows[-1] - rows[0], cols[-1] - cols[0]]) / 768
    assert spans.max() > 0.8 and min(rows[0], cols[0], 767 - rows[-1], 767 - cols[-1]) > 10, (rows, cols)
    root = ET.parse(svg).getroot()
    paths = [e for e in root.iter() if e.tag.endswith(("path", "polyline", "polygon"))]
    # the SVG is the PNG's drawing, line on line: on a page of the picture's size, every
    # point of the outlines lies on the PNG's ink
    assert root.get("viewBox") == "0 0 768 768"
    outline = next(g for g in root if g.get("id") == "layer.Silhouette")
    xy = np.concatenate([np.array([float(v) for v in re.findall(r"-?\d+\.?\d*", p.get("d"))]).reshape(-1, 2)
                         for p in outline])
    dark = np.pad(px.mean(axis=2) < 0.8, 1)
    near = np.zeros_like(dark)
    for dy in (-1, 0, 1):                                              # within a pixel
        for dx in (-1, 0, 1):
            near |= np.roll(np.roll(dark, dy, 0), dx, 1)
    col, row = np.clip(xy[:, 0].astype(int) + 1, 0, 769), np.clip(767 - xy[:, 1].astype(int) + 1, 0, 769)
    assert near[row, col].mean() > 0.98, near[row, col].mean()
    bpy.ops.wm.open_mainfile(filepath=str(blend))
    gp = [o for o in bpy.data.objects if o.type == "GREASEPENCIL"]
    assert len(gp) == 1 and bpy.context.scene.camera is not None
    layers = {l.name: len(l.frames[0].drawing.strokes) if len(l.frames) else 0 for l in gp[0].data.layers}
    assert layers["Silhouette"] >= 1 and layers["Crease"] >= 1    # the outline and the bite's rim
    # every stroke reached the SVG: a path, or paths end to end where its width changes along it
    ends = [re.findall(r"-?\d+\.?\d*,-?\d+\.?\d*", p.get("d")) for p in paths]
    strokes = sum(1 for i, e in enumerate(ends) if i == 0 or e[0] != ends[i - 1][-1])
    assert strokes == sum(layers.values())


def test_visible_strokes_lie_on_the_surface_and_face_the_eye(ext, example):
    M = mod(ext, "model")
    PL = mod(ext, "pipeline")
    A = mod(ext, "agents")
    V = mod(ext, "blackboard.view")
    ev = M.Evaluator(M.load(example("sphere")))
    centre, radius = PL.bounds(ev)
    eye = PL.three_quarter_eye(centre, radius)
    job = PL.Job(ev, V.View(eye=eye), PL.default_light(centre, eye), settings=A.Settings(resolution=12))
    strokes = PL.Illustration(job).run().strokes
    pts = np.concatenate([st.points for st in strokes.layers["Silhouette"]])
    f, g = ev.field_grad(pts)
    assert np.abs(f - 0.5).max() < 1e-9
    n = -g / np.linalg.norm(g, axis=1, keepdims=True)
    assert np.abs(np.einsum("ij,ij->i", n, pts - eye)).max() < 1e-6 * np.linalg.norm(eye)
    assert strokes.count("Silhouette") == 1        # a sphere's whole silhouette is visible


def test_render_rejects_bad_options(ext, example, tmp_path, capsys):
    assert ext.cli.main(["render", example("pear"), "--out", str(tmp_path / "missing" / "deeper")]) == 1
    assert "does not exist (nor does its parent)" in capsys.readouterr().err
    assert ext.cli.main(["render", example("pear"), "--out", str(tmp_path), "--grid", "500"]) == 1
    assert "resolution must be a whole number from 8 to 128" in capsys.readouterr().err
    assert ext.cli.main(["render", example("pear"), "--out", str(tmp_path), "--size", "10"]) == 1
    assert "--size must be from 64 to 8192" in capsys.readouterr().err
    empty = tmp_path / "empty.json"
    empty.write_text('{"format": "blobtree-1", "iso": 5, "root": {"type": "point", "center": [0,0,0], "radius": 1}}')
    assert ext.cli.main(["render", str(empty), "--out", str(tmp_path)]) == 1
    assert "the model has no surface to draw" in capsys.readouterr().err
    assert os.listdir(tmp_path) == ["empty.json"]


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
    chains = gp.layers["Chains"].frames[0].drawing
    short = gp.layers["Short Strokes"].frames[0].drawing
    assert len(hatch.strokes) > 20 and len(chains.strokes) > 5 and len(short.strokes) > 5
    r = np.array([p.radius for s in hatch.strokes for p in s.points])
    o = np.array([p.opacity for s in hatch.strokes for p in s.points])
    assert r.min() < 0.8 * r.max() and (o == 1.0).all()     # per-point width from the light, the pen's full ink
    sun = bpy.data.objects["BlobTree Ink Light"]
    towards = np.array(sun.matrix_world.to_3x3().col[2])
    assert np.allclose(towards, np.array([-1, -1, 1]) / np.sqrt(3), atol=1e-6)   # the .blend's sun is the light used


def test_stipples_alone_show_in_the_png(ext, example, tmp_path):
    """Stipples are one-point DOTS strokes in the .blend and visible in the render (in
    every version: 5.2 needs its placement set up)."""
    out = io.StringIO()
    code = ext.cli.main(["render", example("pear"), "--out", str(tmp_path), "--size", "512", "--grid", "12",
                         "--requests", "stipples"], out=out)
    assert code == 0, out.getvalue()
    bpy.ops.wm.open_mainfile(filepath=str(tmp_path / "pear.blend"))
    gp = [o for o in bpy.data.objects if o.type == "GREASEPENCIL"][0].data
    dots = gp.layers["Stipples"].frames[0].drawing
    assert len(dots.strokes) > 50
    assert {gp.materials[s.material_index].grease_pencil.mode for s in dots.strokes} == {"DOTS"}
    dark = (pixels(tmp_path / "pear.png").max(axis=2) < 0.6).sum()
    assert dark > 100, f"only {dark} dark pixels: the stipples did not render"


@pytest.mark.parametrize("style, preset", [("stippled", "STIPPLED"), ("hatched", "HATCHED"),
                                           ("silhouette-shading", "SILHOUETTE_SHADING")])
def test_the_command_line_and_the_operator_draw_the_same_strokes(ext, example, tmp_path, style, preset):
    """The command line's drawing, and the operator's in the scene the command line
    saved (its camera and sun) for the same model, style, grid and seed, match."""
    code = ext.cli.main(["render", example("pear"), "--out", str(tmp_path), "--size", "128", "--grid", "12",
                         "--seed", "3", "--style", style], out=io.StringIO())
    assert code == 0
    bpy.ops.wm.open_mainfile(filepath=str(tmp_path / "pear.blend"))
    cli = SM.from_grease_pencil(bpy.data.objects["pear Ink"])
    bpy.data.objects.remove(bpy.data.objects["pear Ink"])
    bpy.ops.blobtree_ink.import_json(filepath=example("pear"), preview=False)
    tree = bpy.data.node_groups["pear"]
    assert bpy.ops.blobtree_ink.apply_preset(tree_name="pear", preset=preset) == {"FINISHED"}
    tree.ink.grid_resolution, tree.ink.seed = 12, 3
    for request in ("OUTLINES", "PLACE_STROKES"):
        assert bpy.ops.blobtree_ink.illustrate(tree_name="pear", request=request) == {"FINISHED"}
    op = SM.from_grease_pencil(bpy.data.objects["pear Ink"])
    assert set(cli) == set(op) and len(cli) >= 2
    _, radius = mod(ext, "pipeline").bounds(mod(ext, "model").Evaluator(mod(ext, "model").load(example("pear"))))
    # the same strokes: the style's float settings are single precision on the tree (a
    # radius may differ in its last bits), nothing else
    assert SM.differences(cli, op, dist=1e-6 * radius, count=0, rel=1e-5, q=1.0) == []


def lines_by_cli_and_panel(ext, example, tmp_path, name, grid, lines):
    """The strokes of ``name`` traced with the kinds ``lines`` through the command line
    (--lines, at grid ``grid``) and through the sidebar's toggles (the tree's line_*
    settings): the same strokes, each layer's stroke count; the tree's, for more."""
    code = ext.cli.main(["render", example(name), "--out", str(tmp_path), "--size", "128", "--grid", str(grid),
                         "--lines", ",".join(lines)], out=io.StringIO())
    assert code == 0
    bpy.ops.wm.open_mainfile(filepath=str(tmp_path / f"{name}.blend"))
    gp = bpy.data.objects[f"{name} Ink"].data
    count = {layer.name: len(layer.frames[0].drawing.strokes) if len(layer.frames) else 0 for layer in gp.layers}
    cli = SM.from_grease_pencil(bpy.data.objects[f"{name} Ink"])
    bpy.data.objects.remove(bpy.data.objects[f"{name} Ink"])
    bpy.ops.blobtree_ink.import_json(filepath=example(name), preview=False)
    tree = bpy.data.node_groups[name]
    tree.ink.grid_resolution = grid
    for kind in ("silhouette", "crease", "curvature", "suggestive", "ridges"):
        setattr(tree.ink, f"line_{kind}", kind in lines)
    assert bpy.ops.blobtree_ink.illustrate(tree_name=name, request="OUTLINES") == {"FINISHED"}
    op = SM.from_grease_pencil(bpy.data.objects[f"{name} Ink"])
    _, radius = mod(ext, "pipeline").bounds(mod(ext, "model").Evaluator(mod(ext, "model").load(example(name))))
    assert SM.differences(cli, op, dist=1e-6 * radius, count=0, rel=1e-5, q=1.0) == []
    return count, op, tree


def test_curvature_lines_through_the_command_line_and_the_panel_toggles(ext, example, tmp_path):
    """--lines picks the kinds of outline the agents trace, as the sidebar's Lines toggles
    do; both draw the pear's curvature-sign lines (its concave neck) and suggestive
    contours on their own layers, the same strokes."""
    count, op, tree = lines_by_cli_and_panel(ext, example, tmp_path, "pear", 12,
                                             ("suggestive", "curvature", "silhouette"))
    assert count["Curvature"] > 0 and count["Silhouette"] > 0 and count["Suggestive"] > 0, count
    assert count.get("Crease", 0) == 0
    # with every kind off there is nothing to trace: a named error, the drawing kept
    tree.ink.line_silhouette = tree.ink.line_curvature = tree.ink.line_suggestive = False
    with pytest.raises(RuntimeError, match="must be one or more of silhouette, crease, curvature, suggestive, ridges, got none"):
        bpy.ops.blobtree_ink.illustrate(tree_name="pear", request="OUTLINES")
    assert SM.differences(SM.from_grease_pencil(bpy.data.objects["pear Ink"]), op, dist=0, count=0, rel=0, q=1.0) == []


def test_apparent_ridges_through_the_command_line_and_the_panel_toggle(ext, example, tmp_path):
    """--lines ridges and the sidebar's Ridges toggle draw the heart's apparent ridges
    (its veins' crests) on their own layer, the same strokes."""
    count, _, _ = lines_by_cli_and_panel(ext, example, tmp_path, "heart", 16, ("ridges", "silhouette"))
    assert count["Ridges"] > 0 and count["Silhouette"] > 0, count
    assert count.get("Crease", 0) == 0 and count.get("Suggestive", 0) == 0


def test_bad_lines_are_named(ext, example, tmp_path, capsys):
    assert ext.cli.main(["render", example("pear"), "--out", str(tmp_path), "--lines", "edges"]) == 1
    assert "--lines must be one or more of silhouette, crease, curvature, suggestive, ridges, got edges" in capsys.readouterr().err
