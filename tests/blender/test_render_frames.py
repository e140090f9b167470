"""The command line on a saved scene: `render SCENE.blend --tree NAME --frames A-B --out
DIR` writes a PNG and an SVG per frame and the .blend with the drawings, each frame
the tree's illustration at that frame; bad options are named."""
import io
import os

import bpy
import numpy as np
import pytest
from moving_scene import moving_spheres


def scene_file(example, path):
    """A saved scene: two spheres, the second following an Empty from x=0 (frame 1) to
    x=2 (frame 5), a camera, the stippled look."""
    tree, _ = moving_spheres(example)
    tree.ink.stipples, tree.ink.line_width = True, 4.0
    sc = bpy.context.scene
    sc.render.engine = "BLENDER_WORKBENCH"
    sc.frame_set(1)
    bpy.ops.wm.save_as_mainfile(filepath=str(path))
    return str(path)


def test_frames_of_a_scene(ext, example, tmp_path):
    blend = scene_file(example, tmp_path / "scene.blend")
    out = io.StringIO()
    code = ext.cli.main(["render", blend, "--tree", "two_spheres", "--frames", "2-4", "--out", str(tmp_path / "o"),
                         "--size", "160"], out=out)
    assert code == 0, out.getvalue()
    lines = out.getvalue().splitlines()
    assert [ln.split(":")[0] for ln in lines if ln.startswith("frame ")] == ["frame 2", "frame 3", "frame 4"]
    assert "in all" in lines[-1]
    files = sorted(os.listdir(tmp_path / "o"))
    assert files == ["two_spheres.blend"] + [f"two_spheres_{f:04d}.{e}" for f in (2, 3, 4) for e in ("png", "svg")]
    imgs = []
    for f in (2, 3, 4):
        img = bpy.data.images.load(str(tmp_path / "o" / f"two_spheres_{f:04d}.png"))
        assert tuple(img.size) == (160, 160)
        imgs.append(np.array(img.pixels[:]).reshape(160, 160, -1)[..., :3].mean(axis=2))
        svg = (tmp_path / "o" / f"two_spheres_{f:04d}.svg").read_text()
        assert svg.count("<circle") > 10                              # stipples as dots
    assert np.abs(imgs[0] - imgs[2]).max() > 0.5                       # the frames differ
    bpy.ops.wm.open_mainfile(filepath=str(tmp_path / "o" / "two_spheres.blend"))
    ink = bpy.data.objects["two_spheres Ink"]
    assert sorted(f.frame_number for f in ink.data.layers["Silhouette"].frames) == [2, 3, 4]


@pytest.mark.parametrize("args, message", [
    (["--frames", "4-2"], "the range is empty"),
    (["--frames", "two"], "--frames must be A-B"),
    ([], "needs --tree NAME"),
    (["--tree", "nope"], "no BlobTree named 'nope' (its BlobTrees: two_spheres)"),
    (["--tree", "two_spheres", "--style", "hatched"], "--style: a scene's tree has its own settings and style"),
])
def test_bad_scene_options_are_named(ext, example, tmp_path, capsys, args, message):
    blend = scene_file(example, tmp_path / "scene.blend")
    if "--frames" in args and "--tree" not in args:
        args = ["--tree", "two_spheres"] + args
    assert ext.cli.main(["render", blend, "--out", str(tmp_path / "o")] + args) == 1
    assert message in capsys.readouterr().err
    assert not (tmp_path / "o").exists()
