"""Blender tier: the extension installed the way a user installs it, then driven
through bpy.

Under the pip ``bpy`` module (5.0 or 4.5): a temporary BLENDER_USER_RESOURCES is set
before bpy is imported, the zip is built by Blender's own extension builder (shipped
inside the bpy wheel) and installed with bpy.ops.extensions.package_install_files.
Inside the real Blender binary (tests/run_in_blender.py), the zip was already
installed by `blender --command extension install-file` and BTI_INSIDE_BLENDER is set.
Every test starts from, and leaves, a factory-empty file.
"""
import glob
import os
import shutil
import subprocess
import sys
import tempfile

import pytest

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(REPO, "tests"))     # helpers shared by the tiers (strokes_match)
EXAMPLES = os.path.join(REPO, "examples")
EXT_MODULE = "bl_ext.user_default.blobtree_ink"
INSIDE_BLENDER = bool(os.environ.get("BTI_INSIDE_BLENDER"))

_tmp_user = None
if not INSIDE_BLENDER:
    _tmp_user = tempfile.mkdtemp(prefix="bti-user-")
    os.environ["BLENDER_USER_RESOURCES"] = _tmp_user   # before bpy is imported

import bpy  # noqa: E402
import addon_utils  # noqa: E402


def _build_zip(out_dir):
    version_dir = os.path.dirname(bpy.utils.resource_path("LOCAL") + "/")
    builder = glob.glob(os.path.join(version_dir, "scripts", "addons_core", "bl_pkg", "cli", "blender_ext.py"))
    if not builder:
        builder = glob.glob(os.path.join(os.path.dirname(bpy.__file__), "*", "scripts", "addons_core",
                                         "bl_pkg", "cli", "blender_ext.py"))
    assert builder, "Blender's extension builder (bl_pkg/cli/blender_ext.py) not found"
    zip_path = os.path.join(out_dir, "blobtree_ink.zip")
    subprocess.run([sys.executable, builder[0], "build", "--source-dir", REPO, "--output-filepath", zip_path],
                   check=True, stdout=subprocess.DEVNULL)
    return zip_path


def _install():
    if INSIDE_BLENDER:
        addon_utils.enable(EXT_MODULE, default_set=True)
    else:
        zip_path = _build_zip(_tmp_user)
        res = bpy.ops.extensions.package_install_files(filepath=zip_path, repo="user_default",
                                                       enable_on_install=True)
        assert res == {"FINISHED"}, res
    loaded, enabled = addon_utils.check(EXT_MODULE)
    assert loaded and enabled, f"{EXT_MODULE} is not enabled"
    return sys.modules[EXT_MODULE]


_ext = _install()


@pytest.fixture(scope="session")
def ext():
    """The installed extension's package module."""
    return _ext


def factory_empty():
    bpy.ops.wm.read_homefile(use_empty=True, use_factory_startup=True)


@pytest.fixture(autouse=True)
def empty_file():
    factory_empty()
    yield
    factory_empty()


@pytest.fixture
def example():
    return lambda name: os.path.join(EXAMPLES, f"{name}.json")


def pytest_sessionfinish(session, exitstatus):
    if _tmp_user and not INSIDE_BLENDER:
        shutil.rmtree(_tmp_user, ignore_errors=True)
