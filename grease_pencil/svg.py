"""The command line's SVG: the drawing's strokes projected through the scene camera
onto a page of the rendered picture's size, so that the SVG and the PNG show one
drawing, line on line. Each stroke is a path of its segments' mean width on the page
and mean opacity (round caps and joins, no fill), or, where its width or opacity
changes along it (a hatching stroke tapers with the shade), a path for each stretch
of like width and opacity (:func:`stretches`), the paths meeting end to end; each
stipple a filled circle; grouped by layer (``<g id="layer.NAME">``) in the drawing's
order. Widths stay stroke widths, so they can be changed in any SVG editor."""
from dataclasses import dataclass
from xml.sax.saxutils import quoteattr

import numpy as np

from ..pipeline.framing import image_plane

MIN_WIDTH = 0.05            # px: the thinnest line or dot written (a narrower one would not show)
LIKE_WIDTH = 0.15           # a stretch of a stroke keeps its segments' widths within this share of its first's
LIKE_OPACITY = 0.1          # ... and their opacities within this much of its first's


@dataclass(frozen=True)
class Lens:
    """A camera as the page sees through it: its position ``eye`` and ``axes`` (columns:
    right, up, backwards), and its frame, one unit ahead (perspective) or at any depth
    (``ortho``): its centre and half width and height, on the camera's right and up."""
    eye: np.ndarray
    axes: np.ndarray
    centre: tuple
    half: tuple
    ortho: bool = False

    def project(self, P):
        """Points (n, 3) on a page one unit wide and high (x right, y down, 0..1 in the
        frame), and how many page widths a scene unit across the view at each makes."""
        try:
            uv, depth = image_plane(self.axes, self.eye, P, self.ortho)
        except ValueError:
            raise ValueError("the drawing reaches behind the camera: the page cannot show it") from None
        uv = uv - np.asarray(self.centre, float)
        half = np.asarray(self.half, float)
        page = np.stack([0.5 + 0.5 * uv[:, 0] / half[0], 0.5 - 0.5 * uv[:, 1] / half[1]], axis=1)
        return page, 1.0 / (2 * half[0] * depth)


def stretches(widths, opacities):
    """A polyline's stretches of like width and opacity, from its points' (n >= 2):
    (first point, last point, mean width, mean opacity) of each, consecutive stretches
    sharing their end point."""
    w = 0.5 * (widths[1:] + widths[:-1])                   # each segment's
    a = 0.5 * (opacities[1:] + opacities[:-1])
    out, start = [], 0
    for k in range(1, len(w) + 1):
        if k == len(w) or abs(w[k] - w[start]) > LIKE_WIDTH * w[start] or abs(a[k] - a[start]) > LIKE_OPACITY:
            out.append((start, k, float(np.mean(w[start:k])), float(np.mean(a[start:k]))))
            start = k
    return out


def srgb(c):
    """A linear colour channel (0..1) in sRGB."""
    c = min(max(float(c), 0.0), 1.0)
    return 12.92 * c if c <= 0.0031308 else 1.055 * c ** (1 / 2.4) - 0.055


def write(path, layers, lens, size, colour):
    """Write ``layers`` ({name: [strokes.data.Stroke]} in scene coordinates) as an SVG
    page ``size`` = (width, height) pixels seen through ``lens``, in ``colour`` (linear
    RGB, 0..1, as Blender's materials hold it; written in sRGB, as the PNG shows it)."""
    width, height = (float(v) for v in size)
    ink = "#" + "".join(f"{int(round(255 * srgb(c))):02x}" for c in colour[:3])
    out = ['<?xml version="1.0" encoding="UTF-8"?>',
           f'<svg xmlns="http://www.w3.org/2000/svg" version="1.1" width="{width:g}px" height="{height:g}px" '
           f'viewBox="0 0 {width:g} {height:g}">']
    for name, strokes in layers.items():
        if not strokes:
            continue
        out.append(f'<g id={quoteattr("layer." + name)} fill="none" stroke={quoteattr(ink)} '
                   'stroke-linecap="round" stroke-linejoin="round">')
        for s in strokes:
            page, per_unit = lens.project(s.points)
            xy = page * (width, height)
            widths = 2 * np.broadcast_to(np.asarray(s.radius, float), len(xy)) * per_unit * width
            opacity = np.clip(np.broadcast_to(np.asarray(s.opacity, float), len(xy)), 0.0, 1.0)
            if s.dots or len(xy) == 1:
                for (x, y), w, alpha in zip(xy, widths, opacity):
                    out.append(f'<circle cx="{x:.3f}" cy="{y:.3f}" r="{max(w, MIN_WIDTH) / 2:.3f}" '
                               f'fill={quoteattr(ink)} stroke="none" fill-opacity="{alpha:.3f}"/>')
                continue
            if s.cyclic:                                   # the closing segment, as the others
                xy, widths, opacity = (np.concatenate([v, v[:1]]) for v in (xy, widths, opacity))
            parts = stretches(widths, opacity)
            # stretches meet end to end: flat ends, or see-through round ends would overlap in beads
            cap = '' if len(parts) == 1 else ' stroke-linecap="butt"'
            for a, b, w, alpha in parts:
                d = "M" + "L".join(f"{x:.3f},{y:.3f}" for x, y in xy[a:b + 1])
                if s.cyclic and len(parts) == 1:
                    d = "M" + "L".join(f"{x:.3f},{y:.3f}" for x, y in xy[:-1]) + "Z"
                out.append(f'<path d="{d}" stroke-width="{max(w, MIN_WIDTH):.3f}" stroke-opacity="{alpha:.3f}"{cap}/>')
        out.append("</g>")
    out.append("</svg>")
    with open(path, "w", encoding="utf-8") as fh:
        fh.write("\n".join(out) + "\n")
