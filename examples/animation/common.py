"""What the animated examples share: the extension enabled (installed from this
repository when it is not), a model imported as a BlobTree from a blobtree-1 document,
a camera and a sun on it, the frame range, its first frame drawn and the .blend saved."""
import glob
import json
import math
import os
import subprocess
import sys
import tempfile

import addon_utils
import bpy
from mathutils import Vector

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
FRAMES = (1, 24)


def extension():
    """The BlobTree Ink extension's module, enabled (built from this repository and
    installed into the user's extensions when it is not installed)."""
    names = [m.__name__ for m in addon_utils.modules() if m.__name__.endswith(".blobtree_ink")]
    on = [n for n in names if addon_utils.check(n)[1]]
    if on:                                  # enabled already: enabling again would register it twice
        return sys.modules[on[0]]
    if not names:
        z = os.path.join(tempfile.mkdtemp(), "blobtree_ink.zip")
        if bpy.app.binary_path:
            cmd = [bpy.app.binary_path, "--command", "extension"]
        else:                               # the pip bpy module: Blender's extension tool as a script
            cmd = [sys.executable, glob.glob(os.path.join(os.path.dirname(bpy.__file__), "..", "..",
                                                          "addons_core", "bl_pkg", "cli", "blender_ext.py"))[0]]
        subprocess.run(cmd + ["build", "--source-dir", REPO, "--output-filepath", z], check=True,
                       stdout=subprocess.DEVNULL)
        bpy.ops.extensions.package_install_files(filepath=z, repo="user_default", enable_on_install=True)
        names = ["bl_ext.user_default.blobtree_ink"]
    addon_utils.enable(names[0], default_set=True)
    return sys.modules[names[0]]


def empty_scene():
    """The start-up scene's objects gone."""
    for obj in list(bpy.data.objects):
        bpy.data.objects.remove(obj)


def example(name):
    """A bundled model's blobtree-1 document."""
    return json.load(open(os.path.join(REPO, "examples", f"{name}.json")))


def import_model(doc):
    """A BlobTree node tree (with its preview) from a blobtree-1 document."""
    path = os.path.join(tempfile.mkdtemp(), f"{doc['name']}.json")
    with open(path, "w") as fh:
        json.dump(doc, fh)
    bpy.ops.blobtree_ink.import_json(filepath=path, preview=True)
    return bpy.data.node_groups[doc["name"]]


def node(tree, name):
    """The node a document named ``name`` (its label)."""
    return next(n for n in tree.nodes if n.label == name)


def look_at(obj, target):
    d = Vector(target) - obj.location
    obj.rotation_euler = d.to_track_quat("-Z", "Y").to_euler()


def stage(eye, target, light=(-0.5, -0.6, 0.8)):
    """A camera at ``eye`` on ``target``, a sun from ``light``, the example's frames, and
    the tree's look drawn per rendered frame (its default)."""
    sc = bpy.context.scene
    cam = bpy.data.objects.new("Camera", bpy.data.cameras.new("Camera"))
    sc.collection.objects.link(cam)
    cam.location = eye
    look_at(cam, target)
    sc.camera = cam
    sun = bpy.data.objects.new("Sun", bpy.data.lights.new("Sun", "SUN"))
    sc.collection.objects.link(sun)
    sun.location = Vector(target) + 5 * Vector(light).normalized()
    look_at(sun, target)
    sc.frame_start, sc.frame_end = FRAMES
    sc.render.resolution_x, sc.render.resolution_y, sc.render.resolution_percentage = 1024, 768, 100
    sc.frame_set(FRAMES[0])


def key(target, prop, frames_values):
    """Keyframes of a property (linear between them)."""
    for frame, value in frames_values:
        setattr(target, prop, value)
        target.keyframe_insert(prop, frame=frame)
    ad = target.id_data.animation_data
    for fc in _curves(ad):
        for k in fc.keyframe_points:
            k.interpolation = "LINEAR"


def _curves(ad):
    if ad is None or ad.action is None:
        return []
    if hasattr(ad.action, "fcurves"):
        return list(ad.action.fcurves)
    from bpy_extras import anim_utils
    bag = anim_utils.action_get_channelbag_for_slot(ad.action, ad.action_slot)
    return list(bag.fcurves) if bag is not None else []


def save(path, tree):
    """The tree's look (hatched) drawn at the first frame (a render then draws the other
    frames: the tree has ink), the scene on white paper, saved to ``path``."""
    tree.ink.hatching = True
    bpy.ops.blobtree_ink.bake(tree_name=tree.name, frame_start=FRAMES[0], frame_end=FRAMES[0])
    bpy.ops.wm.save_as_mainfile(filepath=os.path.abspath(path))
    print(f"wrote {path}: '{tree.name}', frames {FRAMES[0]}-{FRAMES[1]}")


def out_path(default):
    """The .blend to write: the argument after --, or ``default``."""
    args = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    return args[0] if args else default


def degrees(*a):
    return tuple(math.radians(x) for x in a)
