"""Where a model is and how a view frames it (pure): its surface box's centre and
radius, a three-quarter eye that frames it; and the one rule for the line width and
the strokes' unit of length, from the model's size: the square root of its surface's
area (model.marks.surface_area), which moving or turning the model or a part of it does
not change, so lines do not swell and strokes do not swim from frame to frame; and
whether two eyes see the model alike."""
import math

import numpy as np

from ..blackboard.polygonise import surface_box
from ..model.marks import surface_measures
from ..model.owners import owners
from ..model.vectors import cross

LINE_RADIUS = 0.0014        # a line's radius, as a fraction of the model's size (about 1.1 px at 1024 px
                            # in a three-quarter view framing the model's bounding sphere)
STROKE_UNIT = 0.64          # the strokes' unit of length, as a fraction of the model's size over
UNIT_GRID = 20              # this grid resolution (about a cell of the default grid; the grid the agents
                            # use changes the outlines' detail, never the strokes' density)
LENS, SENSOR, MARGIN = 50.0, 36.0, 1.15     # the framing camera: focal length and sensor width (mm), margin
CROP_MOST = 4.0             # a picture cut close about its drawing is at most this many times closer
VIEW_ANGLE = 0.5            # degrees: eyes this close in direction from the model's centre ...
VIEW_DISTANCE = 0.02        # ... and in distance (a share of it) see the model alike


class NothingToDraw(ValueError):
    """The model has no surface (its field never reaches iso)."""


def inside(ev, p):
    """Whether a point lies inside the model (on its surface counts)."""
    return bool(ev.field(np.asarray(p, float).reshape(1, 3))[0] >= ev.iso)


def point_text(p):
    """A point as messages give it: (x, y, z) to three figures."""
    return f"({', '.join(f'{x:.3g}' for x in p)})"


def bounds(ev):
    """Centre and radius of the model's surface box (NothingToDraw where there is none)."""
    box = surface_box(ev)
    if box is None:
        raise NothingToDraw("the model has no surface to draw (its field never reaches iso)")
    lo, hi = box
    return 0.5 * (lo + hi), 0.5 * float(np.linalg.norm(hi - lo))


def size(ev):
    """The model's size: the square root of its surface's area (made once per evaluator)."""
    return float(np.sqrt(_surface(ev)[0]))


def surface_centre(ev):
    """The centre of the model's surface (model.marks.surface_measures; the box's centre
    where it has none): it moves and turns with the model, so the paper the marks are
    spaced on (strokes.paper) does too."""
    centre = _surface(ev)[1]
    return centre if centre is not None else 0.5 * (ev.bounds[0] + ev.bounds[1])


def _surface(ev):
    if "surface" not in ev.memo:
        ev.memo["surface"] = surface_measures(ev, owners(ev))
    return ev.memo["surface"]


def line_radius(ev):
    """The radius of a line of width 1 (strokes.style.Style.line_width scales it)."""
    return LINE_RADIUS * size(ev)


def stroke_unit(ev):
    """The strokes' unit of length (pipeline.layers)."""
    return STROKE_UNIT * size(ev) / UNIT_GRID


def three_quarter_eye(centre, radius, azimuth=35.0, elevation=25.0, lens=LENS, sensor=SENSOR, margin=MARGIN):
    """Eye position looking at the centre from the front-right (azimuth degrees from the
    front, -y, towards +x; elevation degrees up), far enough for the camera to frame a
    sphere of the given radius."""
    az, el = math.radians(azimuth), math.radians(elevation)
    d = np.array([math.sin(az) * math.cos(el), -math.cos(az) * math.cos(el), math.sin(el)])
    half_fov = math.atan(sensor / (2 * lens))
    dist = margin * radius / math.sin(half_fov)
    return np.asarray(centre, float) + dist * d


def image_plane(axes, eye, points, ortho=False):
    """Points as a camera at ``eye`` (its ``axes``: the columns right, up, backwards)
    sees them: their places on the image plane one unit ahead (an orthographic camera's
    at any depth), on its right and up, and their depths (1 for an orthographic one).
    Raises ValueError for a point not in front of a perspective camera."""
    rel = (np.asarray(points, float).reshape(-1, 3) - np.asarray(eye, float)) @ np.asarray(axes, float)
    depth = np.ones(len(rel)) if ortho else -rel[:, 2]
    if not (depth > 0).all():
        raise ValueError("a point lies behind the camera")
    return rel[:, :2] / depth[:, None], depth


def crop(axes, eye, points, aspect=1.0, margin=MARGIN, least=0.0):
    """The crop of a camera at ``eye`` (its ``axes``: the columns right, up, backwards)
    that holds ``points`` with ``margin`` about them, the same view cut closer: the
    tangent of the half-angle of the frame's longer side (a render ``aspect`` wide per
    unit of height), never under ``least`` (a drawing of a dot or two is not blown up
    to fill the frame), and the shift of the frame's centre in units of that side
    (Blender's lens shift), (tan_half, shift_x, shift_y)."""
    if not len(np.asarray(points).reshape(-1, 3)):
        raise ValueError("a crop frames points in front of the camera, and at least one")
    try:
        uv, _ = image_plane(axes, eye, points)
    except ValueError:
        raise ValueError("a crop frames points in front of the camera, and at least one") from None
    lo, hi = uv.min(0), uv.max(0)
    centre, half = 0.5 * (lo + hi), 0.5 * (hi - lo)
    wide = max(half[0], half[1] * aspect) if aspect >= 1 else max(half[1], half[0] / aspect)
    tan_half = max(margin * float(wide), least, 1e-9)
    return tan_half, float(centre[0]) / (2 * tan_half), float(centre[1]) / (2 * tan_half)


def perspective_fit(rel, half, offset=(0.0, 0.0), margin=MARGIN):
    """How far back a perspective camera stands from a centre point, on the line from it
    through the frame's centre, for its frame to hold points ``rel`` with ``margin``
    about them (``rel``: the points about the centre in the camera's axes, right, up and
    backwards; ``half``: the frame's half width and height one unit ahead; ``offset``:
    its centre there, a lens shift). A point ``d`` beyond the centre and ``s`` off the
    line is framed from ``t`` back when s <= (t + d) half / margin."""
    rel, half, offset = np.asarray(rel, float).reshape(-1, 3), np.asarray(half, float), np.asarray(offset, float)
    off = np.abs(rel[:, :2] + offset * rel[:, 2:])           # off the centre line, across it
    return float((rel[:, 2] + margin * (off / half).max(axis=1)).max())


def ortho_fit(rel, half, margin=MARGIN):
    """The zoom (a factor of its frame's size) that makes an orthographic camera's frame,
    of half width and height ``half``, hold points ``rel`` (about its centre, in the
    camera's axes) with ``margin`` about them."""
    rel = np.asarray(rel, float).reshape(-1, 3)
    return float(margin * (np.abs(rel[:, :2]) / np.asarray(half, float)).max())


def view_eye(view, centre, radius):
    """The eye a job's view gives (its own; without one, the three-quarter view)."""
    return np.asarray(view.eye if view is not None else three_quarter_eye(centre, radius), float)


def same_view(eye, other, centre):
    """Whether two eyes see the model (its ``centre``) alike: from directions within
    VIEW_ANGLE degrees and distances within VIEW_DISTANCE of each other (a drawing for
    one then holds for the other)."""
    a, b = np.asarray(eye, float) - centre, np.asarray(other, float) - centre
    la, lb = np.linalg.norm(a), np.linalg.norm(b)
    if not (la > 0 and lb > 0):
        return bool(la == lb)
    angle = math.degrees(math.acos(float(np.clip(np.dot(a, b) / (la * lb), -1.0, 1.0))))
    return angle <= VIEW_ANGLE and abs(la / lb - 1.0) <= VIEW_DISTANCE


def default_light(centre, eye):
    """Light from the upper left of the viewer, as illustrators draw it (a unit
    direction towards the light)."""
    d = np.asarray(eye, float) - np.asarray(centre, float)
    d /= np.linalg.norm(d)
    right = cross([0.0, 0.0, 1.0], d)          # the viewer's right (d points at the eye)
    right /= max(np.linalg.norm(right), 1e-12)
    light = 0.5 * d - 0.6 * right + 0.7 * np.array([0.0, 0.0, 1.0])
    return light / np.linalg.norm(light)
