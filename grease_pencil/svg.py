"""Complete Blender's Grease Pencil SVG export where it falls short: it drops one-point
strokes (and writes DOTS strokes as lines), so stipples are added as circles.

The exporter's mapping from the camera image to SVG coordinates is not exposed; it is
recovered by fitting a scale and offset from the exported paths' first points to the
same strokes' first points projected through the scene camera (least squares over every
line stroke), and the stipples are projected through the same camera and mapping.
"""
import re
import xml.etree.ElementTree as ET

import numpy as np

SVG_NS = "http://www.w3.org/2000/svg"


def camera_pixels(sc, P):
    """Pixel coordinates (x right, y down) of world points in the scene camera's image."""
    from bpy_extras.object_utils import world_to_camera_view
    from mathutils import Vector
    cam = sc.camera
    w, h = sc.render.resolution_x, sc.render.resolution_y
    out = np.empty((len(P), 2))
    for i, p in enumerate(P):
        v = world_to_camera_view(sc, cam, Vector(tuple(float(x) for x in p)))
        out[i] = (v.x * w, (1.0 - v.y) * h)
    return out


_NUM = re.compile(r"-?\d+(?:\.\d+)?(?:[eE][-+]?\d+)?")


def _first_points(root):
    pts = []
    for el in root.iter():
        if el.tag.endswith("path") and el.get("d"):
            nums = _NUM.findall(el.get("d"))
            if len(nums) >= 2:
                pts.append((float(nums[0]), float(nums[1])))
    return np.array(pts)


def complete_stipples(path, strokes, sc):
    dots = [s for s in strokes.layers.get("Stipples", []) if s.dots]
    if not dots:
        return 0
    ET.register_namespace("", SVG_NS)
    tree = ET.parse(path)
    root = tree.getroot()
    lines = [s for name, ss in strokes.layers.items() for s in ss if not s.dots]
    svg_first = _first_points(root)
    if len(lines) == 0 or len(svg_first) != len(lines):
        raise ValueError(f"cannot match the SVG's {len(svg_first)} paths to {len(lines)} line strokes")
    cam_first = camera_pixels(sc, np.array([s.points[0] for s in lines]))
    # svg = a * cam + b, one scale for both axes (the exporter keeps the aspect)
    A = np.concatenate([cam_first[:, 0], cam_first[:, 1]])
    B = np.concatenate([svg_first[:, 0], svg_first[:, 1]])
    M = np.zeros((2 * len(lines), 3))
    M[:, 0] = A
    M[:len(lines), 1] = 1.0
    M[len(lines):, 2] = 1.0
    (a, bx, by), *_ = np.linalg.lstsq(M, B, rcond=None)
    P = camera_pixels(sc, np.array([s.points[0] for s in dots]))
    g = ET.SubElement(root, f"{{{SVG_NS}}}g", {"id": "layer.Stipples.circles"})
    px_radius = max(0.5, a * 1.0)
    for x, y in P:
        ET.SubElement(g, f"{{{SVG_NS}}}circle", {"cx": f"{a * x + bx:.4f}", "cy": f"{a * y + by:.4f}",
                                                 "r": f"{px_radius:.3f}", "fill": "#050508", "stroke": "none"})
    tree.write(path, xml_declaration=True, encoding="UTF-8")
    return len(P)
