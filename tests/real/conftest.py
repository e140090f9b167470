"""Real Blender tier: the Blender binary set up by tools/provision (Debian sid's 5.2 LTS
in the project's chroot, or the machine's own blender 4.5+), driven from plain pytest."""
import json
import os
import shutil
import subprocess
import tempfile

import numpy as np
import pytest

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
TOOLS = os.path.join(REPO, "tools")
ARTIFACTS = os.path.join(REPO, "tests", "artifacts")


def run(cmd, env=None, timeout=600, check=True, **kw):
    e = dict(os.environ)
    e.update(env or {})
    p = subprocess.run(cmd, env=e, timeout=timeout, capture_output=True, text=True, **kw)
    if check and p.returncode != 0:
        raise AssertionError(f"{cmd} exited {p.returncode}\n--- stdout\n{p.stdout[-4000:]}\n--- stderr\n{p.stderr[-4000:]}")
    return p


def blender(*args, **kw):
    return run([os.path.join(TOOLS, "blender"), *args], **kw)


def blender_env(*args, **kw):
    return run([os.path.join(TOOLS, "blender-env"), *args], **kw)


@pytest.fixture(scope="session")
def workdir():
    d = tempfile.mkdtemp(prefix="bti-real-", dir="/tmp")
    yield d
    shutil.rmtree(d, ignore_errors=True)


@pytest.fixture(scope="session")
def built_zip(workdir):
    z = os.path.join(workdir, "blobtree_ink.zip")
    p = blender("--command", "extension", "build", "--source-dir", REPO, "--output-filepath", z)
    assert os.path.exists(z), p.stdout
    return z


@pytest.fixture(scope="session")
def user_dir(workdir, built_zip):
    """A temporary user resources directory with the built zip installed by Blender."""
    u = os.path.join(workdir, "user")
    os.makedirs(u)
    p = blender("--command", "extension", "install-file", "-r", "user_default", "-e", built_zip,
                env={"BLENDER_USER_RESOURCES": u})
    assert 'Installed "blobtree_ink"' in p.stdout, p.stdout
    return u


def read_png(path):
    """RGB pixels of a PNG, through ImageMagick where Blender lives (no PIL needed)."""
    env_tool = os.path.join(TOOLS, "blender-env")
    size = subprocess.run([env_tool, "identify", "-format", "%w %h", path], capture_output=True,
                          check=True, text=True).stdout.split()
    w, h = int(size[0]), int(size[1])
    raw = subprocess.run([env_tool, "convert", path, "-depth", "8", "rgb:-"], capture_output=True,
                         check=True).stdout
    return np.frombuffer(raw, np.uint8)[:w * h * 3].reshape(h, w, 3)


def artifact(name):
    os.makedirs(ARTIFACTS, exist_ok=True)
    return os.path.join(ARTIFACTS, name)


def run_ui_script(script, user_dir, tmp_path):
    """Run a tests/real/ui script through the harness: (its output folder, its facts)."""
    out = str(tmp_path / "ui")
    blender_env("python3", os.path.join(REPO, "tests", "real", "ui", "harness.py"),
                "--script", os.path.join(REPO, "tests", "real", "ui", script),
                "--out", out, "--user", user_dir, timeout=300)
    facts = json.load(open(os.path.join(out, "facts.json")))
    print(f"real-UI {script}:", json.dumps(facts))
    return out, facts


def darkest(img, xy):
    """The darkest pixel of each point's 3x3 neighbourhood (points inside the image)."""
    x, y = np.floor(xy[:, 0]).astype(int), np.floor(xy[:, 1]).astype(int)
    return np.min([img[y + dy, x + dx] for dy in (-1, 0, 1) for dx in (-1, 0, 1)], axis=0)
