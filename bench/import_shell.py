"""Time importing the 1497-node shell as a node tree (and exporting it back).

    ~/.cache/blobtree-ink/venv-bpy-5.0.1/bin/python bench/import_shell.py
    tools/blender -b --factory-startup --python bench/import_shell.py

Under the pip bpy module the extension is built and installed into a temporary user
directory first; inside a Blender binary it must be installed already (as
./blobtree-ink does) or the repository's zip is installed the same way.
"""
import glob
import os
import subprocess
import sys
import tempfile
import time

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
if "bpy" not in sys.modules:
    os.environ["BLENDER_USER_RESOURCES"] = tempfile.mkdtemp(prefix="bti-bench-")
import bpy  # noqa: E402
import addon_utils  # noqa: E402

EXT = "bl_ext.user_default.blobtree_ink"
if addon_utils.enable(EXT) is None:          # not installed yet: build and install the zip
    z = os.path.join(tempfile.mkdtemp(), "ext.zip")
    if bpy.app.binary_path:
        cmd = [bpy.app.binary_path, "--command", "extension"]
    else:
        cmd = [sys.executable, glob.glob(os.path.join(os.path.dirname(bpy.__file__), "..", "..", "addons_core",
                                                      "bl_pkg", "cli", "blender_ext.py"))[0]]
    subprocess.run(cmd + ["build", "--source-dir", REPO, "--output-filepath", z], check=True,
                   stdout=subprocess.DEVNULL)
    bpy.ops.extensions.package_install_files(filepath=z, repo="user_default", enable_on_install=True)

shell = os.path.join(REPO, "examples", "shell.json")
for preview in (False, True):
    t = time.perf_counter()
    bpy.ops.blobtree_ink.import_json(filepath=shell, preview=preview)
    dt = time.perf_counter() - t
    print(f"import shell (1497 nodes), preview={preview}: {dt:.2f} s  (target < 5 s)")
out = os.path.join(tempfile.mkdtemp(), "shell.json")
t = time.perf_counter()
bpy.ops.blobtree_ink.export_json(filepath=out, tree_name="shell")
print(f"export shell: {time.perf_counter() - t:.2f} s")
print(f"Blender {bpy.app.version_string}")
