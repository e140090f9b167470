"""Complete Blender's Grease Pencil SVG export where it falls short: it drops one-point
strokes (and writes DOTS strokes as lines), so stipples would vanish from the SVG.

For the export only, each stipple is written as a two-point stroke a hair long (so the
exporter maps it with its own projection and keeps it); afterwards those polylines of
the Stipples layer are replaced by circles of the stroke's width, and the drawing gets
its one-point DOTS strokes back.
"""
import re
import xml.etree.ElementTree as ET

import numpy as np

from ..strokes.data import Stroke

SVG_NS = "http://www.w3.org/2000/svg"
_NUM = re.compile(r"-?\d+(?:\.\d+)?(?:[eE][-+]?\d+)?")


def exportable_dots(strokes, nudge):
    """The stipples as two-point strokes (p, p + nudge)."""
    out = []
    for s in strokes:
        p = s.points[0]
        out.append(Stroke(np.array([p, p + nudge]), np.repeat(s.radius[:1], 2), np.repeat(s.opacity[:1], 2),
                          dots=True))
    return out


def dots_to_circles(path):
    """Replace the Stipples layer's polylines (or paths) by filled circles; returns the count."""
    ET.register_namespace("", SVG_NS)
    tree = ET.parse(path)
    root = tree.getroot()
    n = 0
    for g in root.iter():
        if not (g.tag.endswith("g") and (g.get("id") or "").startswith("layer.Stipples")):
            continue
        for el in list(g):
            data = el.get("points") or el.get("d")
            if not data:
                continue
            nums = [float(x) for x in _NUM.findall(data)]
            xy = np.array(nums[:len(nums) // 2 * 2]).reshape(-1, 2)
            c = xy.mean(axis=0)
            width = float(el.get("stroke-width") or 1.0)
            colour = el.get("stroke") or "#000000"
            g.remove(el)
            ET.SubElement(g, f"{{{SVG_NS}}}circle", {"cx": f"{c[0]:.4f}", "cy": f"{c[1]:.4f}",
                                                     "r": f"{max(width / 2, 0.25):.4f}", "fill": colour,
                                                     "stroke": "none"})
            n += 1
    tree.write(path, xml_declaration=True, encoding="UTF-8")
    return n
