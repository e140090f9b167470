"""Run the blobtree-ink command line through the pip `bpy` module.

The extension is installed the way a user installs it (the zip built by Blender's own
extension builder, via bpy.ops.extensions.package_install_files) into the user
resources directory named by BLENDER_USER_RESOURCES, which must be set before bpy is
imported; the installed copy's command line is then called.

    python tools/bpy_run.py ZIP STAMP -- ARGS...
"""
import os
import sys


def main():
    zip_path, stamp, sep, *args = sys.argv[1:]
    assert sep == "--"
    if not os.environ.get("BLENDER_USER_RESOURCES"):
        sys.exit("tools/bpy_run.py: BLENDER_USER_RESOURCES must be set")
    import bpy  # noqa: F401  (after BLENDER_USER_RESOURCES)
    import importlib
    marker = os.path.join(os.environ["BLENDER_USER_RESOURCES"], "blobtree_ink.stamp")
    have = open(marker).read() if os.path.exists(marker) else ""
    if have != stamp or not _installed():
        res = bpy.ops.extensions.package_install_files(filepath=zip_path, repo="user_default",
                                                      enable_on_install=True)
        if res != {"FINISHED"}:
            sys.exit(f"tools/bpy_run.py: installing {zip_path} failed: {res}")
        with open(marker, "w") as fh:
            fh.write(stamp)
    import addon_utils
    addon_utils.enable("bl_ext.user_default.blobtree_ink", default_set=True)
    ext = importlib.import_module("bl_ext.user_default.blobtree_ink")
    sys.stdout.flush()
    code = ext.cli.main(args)
    sys.stdout.flush()
    os._exit(code)   # skip bpy's slow teardown; everything is flushed


def _installed():
    import importlib.util
    return importlib.util.find_spec("bl_ext.user_default.blobtree_ink") is not None


if __name__ == "__main__":
    main()
