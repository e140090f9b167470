"""The extension in the real Blender binary: build, validate, install, the Blender-tier
tests inside it, the command line, and a UI smoke test under Xvfb."""
import json
import os
import re
import shutil

import numpy as np
import pytest
from conftest import REPO, artifact, blender, blender_env, darkest, read_png, run, run_ui_script


def test_extension_build_and_validate(built_zip):
    p = blender("--command", "extension", "validate", REPO)
    assert "Success" in p.stdout + p.stderr
    p = blender("--command", "extension", "validate", built_zip)
    assert "Success" in p.stdout + p.stderr
    import zipfile
    names = zipfile.ZipFile(built_zip).namelist()
    assert "blender_manifest.toml" in names and "__init__.py" in names
    assert "examples/pear.json" in names
    assert not [n for n in names if n.startswith(("tests/", "tools/", "bench/", ".git"))]


def test_blender_tier_runs_inside_the_real_binary(user_dir):
    p = blender("-b", "--factory-startup", "--python-exit-code", "1",
                "--python", os.path.join(REPO, "tests", "run_in_blender.py"),
                env={"BLENDER_USER_RESOURCES": user_dir}, timeout=1200)
    m = re.search(r"(\d+) passed", p.stdout)
    assert m, p.stdout[-3000:]
    assert "failed" not in p.stdout.splitlines()[-1]
    ran = int(m.group(1))
    print(f"Blender-tier tests inside the real Blender: {ran} passed")
    here = os.path.join(REPO, "tests", "blender")
    defined = sum(len(re.findall(r"^def test_", open(os.path.join(here, f)).read(), re.M))
                  for f in os.listdir(here) if f.startswith("test_") and f.endswith(".py"))
    assert ran >= defined


def test_command_line_through_the_real_blender(tmp_path):
    env = {"BTI_RUNNER": "blender", "BTI_QUIET": "1"}
    p = run([os.path.join(REPO, "blobtree-ink"), "info", os.path.join(REPO, "examples", "pear.json")], env=env)
    assert "nodes: 6" in p.stdout and "iso: 0.5" in p.stdout
    pts = np.array([[0.0, 0, 0], [3, 3, 3]])
    np.save(tmp_path / "in.npy", pts)
    run([os.path.join(REPO, "blobtree-ink"), "eval", os.path.join(REPO, "examples", "sphere.json"),
         "--points", str(tmp_path / "in.npy"), "--out", str(tmp_path / "out.npy")], env=env)
    np.testing.assert_allclose(np.load(tmp_path / "out.npy"), [1.0, 0.0])
    bad = tmp_path / "bad.json"
    bad.write_text('{"format": "blobtree-1", "root": {"type": "twist", "child": {"type": "point"}, "rate": 1}}')
    p = run([os.path.join(REPO, "blobtree-ink"), "info", str(bad)], env=env, check=False)
    assert p.returncode == 1
    assert "root.child.center: missing (a point node needs it)" in p.stderr
    assert "Traceback" not in p.stderr + p.stdout


def test_ui_smoke_shows_an_imported_tree_and_its_preview(user_dir, tmp_path):
    out = str(tmp_path / "ui")
    blender_env("python3", os.path.join(REPO, "tests", "real", "ui", "harness.py"),
                "--script", os.path.join(REPO, "tests", "real", "ui", "smoke.py"),
                "--out", out, "--user", user_dir, timeout=300)
    facts = json.load(open(os.path.join(out, "facts.json")))
    assert facts["extension_enabled"] is True and facts["background"] is False
    assert facts["import_result"] == ["FINISHED"]
    assert facts["area_type"] == "NODE_EDITOR" and facts["tree_type"] == "BlobTreeInkNodeTree"
    assert facts["shown_tree"] == "pear" and facts["tree_nodes"] == 7     # 6 model nodes + output
    assert facts["preview_faces"] > 500 and facts["preview_visible"] is True
    png = artifact("ui_smoke.png")
    shutil.copy(os.path.join(out, "ui_smoke.png"), png)
    img = read_png(png)
    assert img.shape[0] >= 600 and img.shape[1] >= 800
    # not blank: Blender's UI has many distinct colours and real contrast
    assert img.std() > 10
    assert len(np.unique(img.reshape(-1, 3), axis=0)) > 50


def test_real_ui_illustrate_runs_modally_stops_on_escape_and_undoes(user_dir, tmp_path):
    out = str(tmp_path / "ui")
    blender_env("python3", os.path.join(REPO, "tests", "real", "ui", "harness.py"),
                "--script", os.path.join(REPO, "tests", "real", "ui", "illustrate.py"),
                "--out", out, "--user", user_dir, timeout=300)
    facts = json.load(open(os.path.join(out, "facts.json")))
    print("real-UI illustrate:", json.dumps(facts))
    assert facts["invoke_result"] == ["RUNNING_MODAL"]           # a modal run, not execute
    assert facts["running_state"] == "running" and facts["strokes_while_running"] > 0
    assert facts["running_iterations"] == 2                     # held by the runner's test hook
    assert facts["stopped_state"] == "stopped"                  # Esc reached the operator
    assert facts["iterations_at_stop"] == 2 and facts["fraction_at_stop"] < 1.0   # stopped mid-run
    # the outlines found so far stay (stitched, their hidden lines removed: the core
    # tier's runner tests check those)
    assert facts["strokes_while_running"] > 0 and facts["length_while_running"] > 0
    assert facts["strokes_after_esc"] > 0 and facts["length_after_esc"] > 0
    # the UI kept processing events: another timer fired throughout the run
    assert facts["other_timer_ticks"] >= 3
    # one undo removes the whole run, and only the run
    assert facts["strokes_after_undo"] == 0 and facts["ink_object_after_undo"] is False
    assert facts["tree_after_undo"] is True
    # the sidebar's "Last run" tells the run it shows was taken back
    assert facts["changed_before_undo"] is False and facts["changed_after_undo"] is True
    assert facts["edited_state"] == "tree edited"                # editing the tree stops a run
    # Ctrl+Z while a run goes on stops it, keeping what it drew as one step (not undoing the
    # step before it, which would take the model away); Ctrl+Z again takes the run back
    assert facts["undo_key_state"] == "stopped" and facts["tree_after_undo_key"] is True
    assert facts["length_after_undo_key"] > 0 and facts["length_after_undo_key"] != facts["length_before_undo_key"]
    assert facts["tree_after_second_undo"] is True
    assert facts["length_after_second_undo"] == pytest.approx(facts["length_before_undo_key"])
    # an undo from a script or the Edit menu while a run goes on ends it, writing nothing
    assert facts["script_undo_state"] == "undone"
    # a look stopped by Esc is one drawing: the other look's stipples are cleared
    assert facts["stippled_state"] == "done" and facts["stipples_before_hatched"] > 100
    assert facts["hatched_stopped_state"] == "stopped" and facts["stipples_after_stopped_hatched"] == 0
    for name in ("illustrate_running.png", "illustrate_stopped.png"):
        png = artifact(name)
        shutil.copy(os.path.join(out, name), png)
        img = read_png(png)
        assert img.std() > 10 and len(np.unique(img.reshape(-1, 3), axis=0)) > 50


def test_real_ui_modal_runs_draw_what_the_background_path_draws(user_dir, tmp_path):
    """Per style: the operator invoked in the UI (its pipeline on the worker thread) and
    run through execute (the background path) draw the same strokes, bit for bit."""
    out = str(tmp_path / "ui")
    blender_env("python3", os.path.join(REPO, "tests", "real", "ui", "harness.py"),
                "--script", os.path.join(REPO, "tests", "real", "ui", "same_strokes.py"),
                "--out", out, "--user", user_dir, "--timeout", "300", timeout=400)
    facts = json.load(open(os.path.join(out, "facts.json")))
    assert "error" not in facts, facts.get("error")
    for preset in facts["presets"]:
        modal, execd = (np.load(os.path.join(out, f"{w}-{preset}.npz")) for w in ("modal", "exec"))
        assert sorted(modal.files) == sorted(execd.files) and len(modal.files) >= 8, preset
        for k in modal.files:
            np.testing.assert_array_equal(modal[k], execd[k], err_msg=f"{preset} {k}")
        assert facts["counts"][f"modal-{preset}"]["Silhouette"] > 0


def test_real_ui_stays_responsive_while_the_shell_is_illustrated(user_dir, tmp_path):
    """An independent 50 ms timer keeps firing during every request on the 1497-node
    shell: no gap above 250 ms (the target is 100 ms; a slow CI machine gets some room)
    but for the drawing of the 3D viewport, which with this machine's software GL takes
    about 0.2 s a redraw (0.1 s for an empty viewport: Blender's own cost, not a stall of
    the extension's; the screen is 1280x720 and viewport anti-aliasing off to keep it
    small). The raw gaps, the drawing and the gaps less drawing are printed; the run's
    writes are spaced so that redrawing them takes at most a quarter of the time: the
    median gap stays at the timer's interval."""
    out = str(tmp_path / "ui")
    blender_env("python3", os.path.join(REPO, "tests", "real", "ui", "harness.py"),
                "--script", os.path.join(REPO, "tests", "real", "ui", "responsive.py"),
                "--out", out, "--user", user_dir, "--timeout", "600", "--screen", "1280x720", timeout=700)
    facts = json.load(open(os.path.join(out, "facts.json")))
    assert "error" not in facts, facts.get("error")
    print("real-UI responsiveness (s):", json.dumps(facts, indent=1))
    assert facts["nodes"] > 1400
    for name, run_ in facts["runs"].items():
        assert run_["invoke"] == ["RUNNING_MODAL"] and run_["state"] == "done", (name, run_)
        assert run_["ticks"] >= 1, (name, run_)
        assert run_["max_gap_less_drawing"] < 0.25, f"{name}: the UI stalled for {run_['max_gap_less_drawing']:.3f} s"
        assert run_["median_gap"] < 0.1, f"{name}: the UI was busy half the time ({run_['median_gap']:.3f} s)"
    shutil.copy(os.path.join(out, "responsive_shell.png"), artifact("responsive_shell.png"))


def test_real_ui_add_menu_search_and_whole_node_errors(user_dir, tmp_path):
    """Shift+A, "poi", Return and a click add a Point node; an error is on its node
    whole (wrapped), in the sidebar's Errors panel and in the error icon's tooltip. The
    editor follows the active object's tree."""
    out, facts = run_ui_script("node_editor.py", user_dir, tmp_path)
    assert "error" not in facts, facts.get("error")
    assert facts["nodes_before"] == [] and facts["nodes_after_add"] == ["point"]
    assert facts["added_is_active"] is True
    # it followed the mouse from where the menu opened to the click that placed it
    near_click, near_start = (np.hypot(*np.subtract(facts["point_top_left"], p)) for p in (facts["click"], facts["mouse"]))
    assert near_click < 150 and near_click < near_start, (near_click, near_start)
    assert facts["point_center"] == [1.1, -2.25, 12.34]
    assert facts["output_error"] == "nothing is linked to the Model Output"
    assert facts["panel_shown"] is True and facts["sidebar_category"] == "Node"
    assert " ".join(facts["sidebar_lines"]) == facts["output_error"]
    assert facts["blend_error"] == "needs at least 1 linked input" and facts["output_error_after_link"] == ""
    assert facts["blend_inputs"] == ["Field 1"]
    shots = {}
    for name in ("node_add_search.png", "node_error_output.png", "node_error_blend.png", "node_error_tooltip.png"):
        png = artifact(name)
        shutil.copy(os.path.join(out, name), png)
        shots[name] = img = read_png(png).astype(int)
        assert img.std() > 10 and len(np.unique(img.reshape(-1, 3), axis=0)) > 50
    # hovering the error icon drew a tooltip below the mouse
    x, y = facts["icon_at"]
    below = (slice(y + 10, y + 60), slice(max(x - 40, 0), x + 200))
    changed = np.abs(shots["node_error_tooltip.png"][below] - shots["node_error_blend.png"][below]).sum(axis=2) > 30
    assert changed.mean() > 0.2
    # the editor shows the active object's tree, and a tree browsed to until another object is made active
    assert facts["active_after_import"] == "pear Preview" and facts["shown_after_import"] == "pear"
    assert facts["shown_after_browse"] == "Sketch" and facts["shown_with_cube_active"] == "Sketch"
    assert facts["shown_with_pear_active"] == "pear" and facts["cube"] == "Cube"
    assert facts["shown_when_emptied"] == "pear" and facts["shown_pinned"] == "Sketch"


def _ink_mask(strokes, shape, reach=3, step=0.5):
    """Pixels within ``reach`` of the strokes' polylines (pixel points, x right, y down)."""
    h, w = shape
    pieces = []
    for s in strokes:
        P = np.asarray(s, float).reshape(-1, 2)
        pieces.append(P)
        pieces += [a + np.linspace(0, 1, int(np.ceil(np.linalg.norm(b - a) / step)) + 1)[:, None] * (b - a)
                   for a, b in zip(P, P[1:])]
    Q = np.floor(np.concatenate(pieces)).astype(int)
    near = np.zeros(shape, bool)
    for dy in range(-reach, reach + 1):
        for dx in range(-reach, reach + 1):
            near[np.clip(Q[:, 1] + dy, 0, h - 1), np.clip(Q[:, 0] + dx, 0, w - 1)] = True
    return near


def test_real_ui_an_artists_first_hour(user_dir, tmp_path):
    """Issue #28: an artist's first hour in the real UI, keys and clicks by xdotool
    (tests/real/ui/first_hour.py says which steps are Python set-up): the cube deleted, a
    tree of two Points, a Blend and a Model Output added with Shift+A and linked by mouse
    drags, a Center typed into its field, the camera aligned to the view; outlines,
    the stippled look and the hatched look from menu search (F3), the hatching stopped
    by Esc in the middle (the runner's hook holds it there); F12 in EEVEE and Workbench.
    The renders are ink on white paper: each layer's strokes dark where the camera
    projects them, white paper elsewhere, no preview mesh; the viewport draws the
    stipples."""
    out = str(tmp_path / "ui")
    blender_env("python3", os.path.join(REPO, "tests", "real", "ui", "harness.py"),
                "--script", os.path.join(REPO, "tests", "real", "ui", "first_hour.py"),
                "--out", out, "--user", user_dir, "--timeout", "900", timeout=1000)
    facts = json.load(open(os.path.join(out, "facts.json")))
    print("real-UI first hour:", json.dumps({k: v for k, v in facts.items() if not k.startswith("sockets")}))
    for name in sorted(os.listdir(out)):
        if name.startswith("first_hour_") and name.endswith(".png"):
            shutil.copy(os.path.join(out, name), artifact(name))
    for label in ("scene", "workbench"):
        if os.path.exists(os.path.join(out, f"render_{label}.png")):
            shutil.copy(os.path.join(out, f"render_{label}.png"), artifact(f"first_hour_render_{label}.png"))
    assert "error" not in facts, facts.get("error")
    # 1. the extension on, the default cube deleted by Delete over the viewport
    assert facts["extension_enabled"] is True and facts["background"] is False
    assert facts["selected_at_start"] == ["Cube"] and facts["objects_after_delete"] == ["Camera", "Light"]
    # 2. a new tree is empty (no Model Output): four nodes added by hand, linked by drags
    assert facts["nodes_in_new_tree"] == []
    assert facts["node_kinds"] == ["blend", "output", "point", "point"]
    assert facts["links"] == [["Blend", "Field", "Model Output", "Model"], ["Point", "Field", "Blend", "Field 1"],
                              ["Point.001", "Field", "Blend", "Field 2"]]
    assert facts["centers"] == [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]]                   # typed into the field
    assert facts["node_errors"] == ["", "", "", ""] and facts["preview_faces"] > 1000  # it compiles
    (u0, u1), (v0, v1) = facts["model_in_camera"]                                   # the camera frames it
    assert 0 < u0 < u1 < 1 and 0 < v0 < v1 < 1 and v1 - v0 > 0.4, facts["model_in_camera"]
    assert facts["view_perspective"] == "CAMERA" and facts["ink_parent"] == facts["preview_name"]
    assert facts["paper_viewport"] == ["WORLD", False, False, False]          # white paper, no floor over it
    # 3.-5. each request writes its own layers; the others stay, point for point
    runs = facts["runs"]
    assert [runs[k]["state"] for k in ("outlines", "stippled", "hatched_esc", "hatched_full")] == \
        ["done", "done", "stopped", "done"]
    c3, c4, held, esc, full = (facts[k] for k in ("counts_outlines", "counts_stippled", "counts_held",
                                                   "counts_after_esc", "counts_full"))
    assert c3["Silhouette"] > 0 and c3["Stipples"] == c3["Hatching"] == 0
    assert c3["Crease"] == 0                          # a blend of two balls is smooth: no CSG creases
    assert c4["Stipples"] > 100 and c4["Hatching"] == 0
    assert facts["same_outlines_after_stippled"] == {"Silhouette": True, "Crease": True, "Curvature": True}
    assert facts["held_state"] == "running" and facts["held_stage"] == "hatching" and held["Hatching"] > 0
    # Esc kept the part-drawn hatching: more than none, less than the whole look draws
    assert esc["Hatching"] >= held["Hatching"] and 0 < esc["Hatching"] < full["Hatching"], (esc, full)
    assert runs["hatched_esc"]["fraction"] < 1.0
    every = {"Silhouette": True, "Crease": True, "Curvature": True, "Stipples": True}
    # the hatched look, stopped, is one drawing: the stipples of the stippled look go, the outlines stay
    assert facts["same_after_esc"] == dict(every, Stipples=False) and esc["Stipples"] == 0
    assert facts["esc_warnings"][-1] == "Stipples cleared: not in this look (Ctrl+Z brings it back)"
    # ... and run to its end, it has nothing more to clear
    assert facts["same_after_full"] == dict(every, Stipples=False) and full["Stipples"] == 0
    assert not any("cleared" in w for w in facts["full_warnings"])
    # a request after a look: the look's settings were not applied again, its hatching kept
    assert runs["outlines_after_look"]["state"] == "done" and facts["hatching_after_request"] is False
    assert facts["counts_after_request"]["Hatching"] == full["Hatching"]
    # Place Strokes with both ticked: hatching and stipples together (a request builds the drawing up)
    assert runs["place_strokes"]["state"] == "done"
    assert facts["counts_placed"]["Hatching"] == full["Hatching"] and facts["counts_placed"]["Stipples"] > 100
    # 6. F12 in the scene's engine (EEVEE in factory settings), then in Workbench
    renders = facts["renders"]
    assert renders["scene"]["engine"] == "BLENDER_EEVEE" and renders["workbench"]["engine"] == "BLENDER_WORKBENCH"
    assert all(r["end"] == "complete" and r["size"] == facts["render_size"] == [960, 540] for r in renders.values())
    assert facts["preview_hide_render"] is True and facts["world"] == "BlobTree Ink Paper"
    points = json.load(open(os.path.join(out, "render_points.json")))
    assert points["Crease"] == [] and all(points[k] for k in ("Silhouette", "Stipples", "Hatching"))
    for label in ("scene", "workbench"):
        img = read_png(artifact(f"first_hour_render_{label}.png")).astype(float).mean(axis=2) / 255
        assert img.shape == (540, 960)
        near_ink = np.zeros(img.shape, bool)
        for name in ("Silhouette", "Stipples", "Hatching"):
            xy = np.array([q for s in points[name] for q in s], float)
            inside = (xy[:, 0] >= 1) & (xy[:, 0] < 959) & (xy[:, 1] >= 1) & (xy[:, 1] < 539)
            assert inside.all(), f"{label}: the {name} layer leaves the frame"
            dark = darkest(img, xy)
            assert np.median(dark) < 0.55, f"{label}: the {name} layer is not ink in the render ({np.median(dark):.2f})"
            near_ink |= _ink_mask(points[name], img.shape)
        paper = img[~near_ink]
        assert np.median(paper) > 0.97 and np.quantile(paper, 0.05) > 0.9, f"{label}: not white paper"
        # inside the model's silhouette (its preview's vertices, projected) and away from the ink: white, so
        # no preview mesh shows
        V = np.floor(np.array(points["preview_vertices"], float)).astype(int)
        model = np.zeros(img.shape, bool)
        model[V[:, 1], V[:, 0]] = True
        blank = img[model & ~near_ink]
        assert len(blank) > 500 and np.median(blank) > 0.97 and np.quantile(blank, 0.05) > 0.9, \
            f"{label}: the preview mesh shows in the render"
    # 4. the viewport draws the stipples: after the stippled look, the pixels where the stipples project got
    # dark, and what changed in the viewport is there
    view = json.load(open(os.path.join(out, "viewport_points.json")))
    S = np.array(view["stipples"], float)
    assert len(S) > 100
    before, after = (read_png(artifact(n)).astype(float).mean(axis=2) / 255
                     for n in ("first_hour_3_outlines.png", "first_hour_4_stippled.png"))
    d0, d1 = darkest(before, S), darkest(after, S)
    assert np.median(d1) < np.median(d0) - 0.1, (np.median(d0), np.median(d1))
    assert (d0 - d1 > 0.15).sum() > 200, "the stipples do not show in the viewport"
    x, y, w, h = view["viewport"]
    changed = np.abs(after - before)[y:y + h, x:x + w] > 0.1
    near = _ink_mask([[p] for p in S - [x, y]], (h, w))
    assert changed.sum() > 300 and (changed & near).sum() > 0.95 * changed.sum(), \
        (changed.sum(), (changed & near).sum())
    # for the record (not checked): how much the outlines and the hatching darken the viewport where they
    # project (the preview mesh hides much of them there; the renders show them whole)
    camera, full = (read_png(artifact(n)).astype(float).mean(axis=2) / 255
                    for n in ("first_hour_2_camera.png", "first_hour_5_hatched_full.png"))
    for name, a, b in (("silhouette", camera, before), ("hatching", after, full)):
        P = np.array(view[name], float)
        print(f"viewport {name}: {len(P)} points, darkened by 0.15 or more at "
              f"{np.mean(darkest(a, P) - darkest(b, P) >= 0.15):.0%}")


def test_real_ui_an_artist_turns_on_curvature_lines_suggestive_contours_and_ridges(user_dir, tmp_path):
    """Issue #30 in the real UI (tests/real/ui/lines.py): clicks on the sidebar's
    Curvature, Suggestive and Ridges toggles (Silhouette and Crease are on by default),
    then Trace Feature Outlines from menu search: the heart's curvature-sign lines,
    suggestive contours and apparent ridges (its wrinkles and veins, seen from the scene
    camera) are drawn on their layers, and show as ink on screen."""
    out, facts = run_ui_script("lines.py", user_dir, tmp_path)
    assert "error" not in facts, facts.get("error")
    assert facts["lines_before"] == ["silhouette", "crease"]
    assert facts["lines_after"] == ["silhouette", "crease", "curvature"]     # a click adds one kind
    assert facts["lines_two"] == ["silhouette", "crease", "curvature", "suggestive"]
    assert facts["lines_last"] == ["silhouette", "crease", "curvature", "suggestive", "ridges"]
    assert facts["state"] == "done"
    assert all(facts["counts"][k] > 0 for k in ("Silhouette", "Curvature", "Suggestive", "Ridges")), facts["counts"]
    for name in ("lines_1_sidebar.png", "lines_2_curvature_on.png", "lines_3_traced.png"):
        shutil.copy(os.path.join(out, name), artifact(name))
    shot = read_png(artifact("lines_3_traced.png")).astype(float).mean(axis=2) / 255
    drawn = json.load(open(os.path.join(out, "lines_points.json")))
    pts = np.array(drawn["curvature"], float)
    assert len(pts) >= 5
    assert np.median(darkest(shot, pts)) < 0.3           # the curvature lines are ink on screen
    pts = np.array(drawn["suggestive"], float)
    assert len(pts) >= 5
    assert np.median(darkest(shot, pts)) < 0.3           # and so are the suggestive contours
    pts = np.array(drawn["ridges"], float)
    assert len(pts) >= 5
    assert np.median(darkest(shot, pts)) < 0.3           # and the apparent ridges
