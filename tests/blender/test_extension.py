"""The installed extension: registration, command line, Grease Pencil shim."""
import io
import os

import bpy
import numpy as np
import pytest


def test_installed_from_the_zip_not_the_repository(ext):
    assert os.path.join("extensions", "user_default", "blobtree_ink") in ext.__file__
    assert ext.__name__ == "bl_ext.user_default.blobtree_ink"
    assert bpy.types.NodeTree.bl_rna_get_subclass_py("BlobTreeInkNodeTree") is not None


def test_cli_info_on_an_example(ext, example):
    out = io.StringIO()
    assert ext.cli.main(["info", example("heart")], out=out) == 0
    text = out.getvalue()
    assert "nodes: 76" in text and "iso: 0.5" in text and "surface bounds: (" in text


def test_cli_eval_writes_field_and_gradient(ext, example, tmp_path):
    pts = np.array([[0.0, 0, 0], [0.2, 0, 0], [5, 5, 5]])
    np.save(tmp_path / "in.npy", pts)
    out = io.StringIO()
    code = ext.cli.main(["eval", example("sphere"), "--points", str(tmp_path / "in.npy"),
                         "--out", str(tmp_path / "out.npy"), "--gradient"], out=out)
    assert code == 0
    res = np.load(tmp_path / "out.npy")
    assert res.shape == (3, 4)
    np.testing.assert_allclose(res[:, 0], [1.0, (1 - 0.04) ** 3, 0.0])
    np.testing.assert_allclose(res[1, 1:], [-6 * 0.2 * (1 - 0.04) ** 2, 0, 0])


def test_cli_rejects_an_invalid_model_with_its_message(ext, tmp_path, capsys):
    bad = tmp_path / "bad.json"
    bad.write_text('{"format": "blobtree-1", "root": {"type": "point", "center": [0,0,0], "radius": -1}}')
    assert ext.cli.main(["info", str(bad)]) == 1
    err = capsys.readouterr().err
    assert "root.radius: must be > 0, got -1" in err and "Traceback" not in err


def test_grease_pencil_shim_names_the_right_collection(ext):
    from importlib import import_module
    compat = import_module(ext.__name__ + ".grease_pencil.compat")
    coll = compat.grease_pencil_data()
    expected = "grease_pencils_v3" if bpy.app.version < (5, 0, 0) else "grease_pencils"
    assert coll == getattr(bpy.data, expected)
    gp = coll.new("ink")
    obj = bpy.data.objects.new("ink", gp)
    bpy.context.scene.collection.objects.link(obj)
    assert obj.type == "GREASEPENCIL"
    layer = gp.layers.new("Silhouette")
    frame = layer.frames.new(1)
    frame.drawing.add_strokes([3])
    assert len(frame.drawing.strokes) == 1


def test_every_test_starts_factory_empty():
    assert len(bpy.data.objects) == 0 and len(bpy.data.node_groups) == 0
    bpy.data.node_groups.new("left over", "BlobTreeInkNodeTree")


def test_and_leaves_nothing_behind():
    assert len(bpy.data.node_groups) == 0


def test_what_a_button_leaves_unset_is_not_the_last_calls(ext):
    """Blender gives a property a button or menu item does not set the value of the last
    call from the UI, unless it is SKIP_SAVE: without it, a request button after a Look
    would run the Look again, and a menu item after a sidebar button would work on that
    button's tree. Every operator's tree, request, look, node and frame range is the
    call's own."""
    import sys
    ops = {c for name, m in list(sys.modules.items()) if name.startswith(ext.__name__ + ".")
           for c in getattr(m, "classes", ()) if isinstance(c, type) and issubclass(c, bpy.types.Operator)}
    own = {"tree_name", "request", "preset", "node_name", "frame", "frame_start", "frame_end"}
    checked = []
    for op in ops:
        group, name = op.bl_idname.split(".")
        for p in getattr(getattr(bpy.ops, group), name).get_rna_type().properties:
            if p.identifier in own:
                checked.append((op.bl_idname, p.identifier))
                assert p.is_skip_save, f"{op.bl_idname}.{p.identifier} is remembered from the last call"
    assert ("blobtree_ink.illustrate", "preset") in checked and len({o for o, _ in checked}) >= 8
