"""The scene around an illustration: white paper (a white world, a view transform that
keeps white white, the 3D viewports' Solid background the world's) for the UI and the
command line, and the command line's camera at
the eye looking at the model and sun towards the light, all reused when they exist."""
import json

import bpy
import numpy as np

from ..pipeline.framing import CROP_MOST, LENS, SENSOR, crop

CAMERA, LIGHT = "BlobTree Ink Camera", "BlobTree Ink Light"
PAPER_WORLD = "BlobTree Ink Paper"
PAPER = (1.0, 1.0, 1.0)


def paper(scene):
    """Put the scene on white paper: the paper world (white in Workbench, EEVEE and
    Material Preview), the Standard view transform with no look (white stays white),
    an opaque film, and the depth pass on in every view layer (Grease Pencil renders
    hidden by the scene's objects with it, and Blender warns on every render without
    it). Returns what it replaced, as a JSON string for :func:`unpaper` ("" when the
    scene was on paper already)."""
    vs = scene.view_settings
    if scene.world is not None and scene.world.name == PAPER_WORLD and vs.view_transform == "Standard":
        return ""
    was = json.dumps({"world": scene.world.name if scene.world is not None else "",
                      "view_transform": vs.view_transform, "look": vs.look, "exposure": vs.exposure,
                      "gamma": vs.gamma, "film_transparent": scene.render.film_transparent,
                      "depth": {vl.name: vl.use_pass_z for vl in scene.view_layers}})
    depth_pass(scene, True)
    world = bpy.data.worlds.get(PAPER_WORLD) or bpy.data.worlds.new(PAPER_WORLD)
    world.color = PAPER
    tree = getattr(world, "node_tree", None)
    if tree is not None:                            # a node world (EEVEE, Material Preview): its background
        for node in tree.nodes:
            if node.type == "BACKGROUND":
                node.inputs["Color"].default_value = (*PAPER, 1.0)
                node.inputs["Strength"].default_value = 1.0
    scene.world = world
    vs.view_transform = "Standard"
    vs.look = "None"
    vs.exposure, vs.gamma = 0.0, 1.0
    scene.render.film_transparent = False
    return was


def unpaper(scene, was):
    """Give the scene back what :func:`paper` replaced."""
    if not was:
        return
    d = json.loads(was)
    scene.world = bpy.data.worlds.get(d["world"]) if d["world"] else None
    vs = scene.view_settings
    vs.view_transform = d["view_transform"]
    vs.look = d["look"]
    vs.exposure, vs.gamma = d["exposure"], d["gamma"]
    scene.render.film_transparent = d["film_transparent"]
    for vl in scene.view_layers:
        if vl.name in d.get("depth", {}):
            vl.use_pass_z = d["depth"][vl.name]


def paper_viewports(screen, on):
    """The 3D viewports of a screen on paper in Solid shading (their background the
    world's: white on paper, so the ink reads, and no floor grid or axes drawn over
    it), or back on the theme's, with the floor and its axes."""
    if screen is None:
        return
    for area in screen.areas:
        if area.type != "VIEW_3D":
            continue
        space = area.spaces.active
        if on:
            space.shading.background_type = "WORLD"
        elif space.shading.background_type == "WORLD":
            space.shading.background_type = "THEME"
        else:
            continue                       # not on paper: the artist's own floor stays as it is
        overlay = space.overlay
        overlay.show_floor = overlay.show_axis_x = overlay.show_axis_y = not on


def depth_pass(scene, on):
    """The depth pass on or off in every view layer: off while the preview mesh renders,
    so that the ink on the exact surface is not hidden by the rough mesh about it."""
    for vl in scene.view_layers:
        vl.use_pass_z = on


def setup(scene, centre, eye, size, light_dir):
    cam = bpy.data.objects.get(CAMERA)
    if cam is None:
        cam = bpy.data.objects.new(CAMERA, bpy.data.cameras.new(CAMERA))
        scene.collection.objects.link(cam)
    cam.data.lens = LENS
    cam.data.sensor_width = SENSOR
    cam.location = tuple(float(x) for x in eye)
    look = np.asarray(centre, float) - np.asarray(eye, float)
    cam.rotation_euler = look_rotation(look)
    cam.data.clip_end = max(1000.0, 10 * float(np.linalg.norm(look)))
    scene.camera = cam
    light = bpy.data.objects.get(LIGHT)
    if light is None:
        light = bpy.data.objects.new(LIGHT, bpy.data.lights.new(LIGHT, "SUN"))
        scene.collection.objects.link(light)
    light.rotation_euler = look_rotation(-np.asarray(light_dir, float))
    r = scene.render
    r.engine = "BLENDER_WORKBENCH"
    r.resolution_x = r.resolution_y = int(size)
    r.resolution_percentage = 100
    r.image_settings.file_format = "PNG"
    paper(scene)
    bpy.context.view_layer.update()              # the objects' world matrices, read by the job
    return cam, light


def crop_camera(scene, cam, points):
    """Cut the camera's view closer about ``points`` (n, 3) in the scene (the drawing),
    from where it is: a longer lens and a lens shift, so the drawing fills the render's
    frame with the framing margin and looks exactly as it did, only larger."""
    r = scene.render
    aspect = (r.resolution_x * r.pixel_aspect_x) / (r.resolution_y * r.pixel_aspect_y)
    m, data = cam.matrix_world, cam.data
    least = data.sensor_width / (2 * data.lens) / CROP_MOST
    tan_half, sx, sy = crop(np.array(m.to_3x3().normalized(), float), np.array(m.translation, float), points, aspect,
                            least=least)
    data.sensor_fit = "AUTO"
    data.lens = data.sensor_width / (2 * tan_half)
    data.shift_x, data.shift_y = sx, sy


def look_rotation(direction):
    """Euler angles pointing an object's -Z along direction with +Y up."""
    from mathutils import Vector
    return Vector(tuple(float(x) for x in direction)).to_track_quat("-Z", "Y").to_euler()
