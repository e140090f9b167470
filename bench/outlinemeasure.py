"""The outline benchmarks' measure (bench/outlines.py, bench/missed.py): a camera, the
ground truth of a dense polygonisation seen from it, the traced outlines rasterised at
1024 px, and the figures (coverage, precision, gaps, dangling ends; bench/README.md)."""
import functools

import numpy as np
from blobtree_ink.agents.surface import Surface
from blobtree_ink.agents.tracer import refine_seeds
from blobtree_ink.blackboard.board import KIND_ID
from blobtree_ink.blackboard.edges import DEFAULT_CREASE_ANGLE, process_edges
from blobtree_ink.blackboard.polygonise import polygonise, surface_box
from blobtree_ink.model.vectors import cross

PX = 1024
THREE_QUARTER = (1.0, -1.4, 0.8)                   # from the model's centre towards the eye
ELEVATIONS = (-30.0, 0.0, 30.0, 60.0)              # --views cycles through these
GAP = 3             # a run of missed ground-truth pixels wider or taller than this is a gap
NEAR = 2            # an outline end this close to another outline's pixels, or the border, is joined
ALONG = 6           # an outline's own pixels count as another outline this far along it from the end


class Camera:
    def __init__(self, ev, towards=THREE_QUARTER):
        lo, hi = surface_box(ev)
        self.c = 0.5 * (lo + hi)
        r = 0.5 * np.linalg.norm(hi - lo)
        d = np.asarray(towards, float)
        d = d / np.linalg.norm(d)
        self.eye = self.c + 3.0 * r * d
        self.f = -d
        self.right = cross(self.f, [0, 0, 1.0])
        self.right /= np.linalg.norm(self.right)
        self.up = cross(self.right, self.f)
        self.half = r / (3.0 * r) * 1.05             # tan of the half field of view

    def pixels(self, P):
        v = P - self.eye
        z = v @ self.f
        x = (v @ self.right) / z / self.half
        y = (v @ self.up) / z / self.half
        return np.stack([(x + 1) * PX / 2, (1 - y) * PX / 2], axis=1)


def towards(azimuth, elevation):
    """The unit vector from the centre towards an eye at that azimuth (degrees from +x
    towards +y) and elevation (degrees above the xy plane; z is up)."""
    az, el = np.radians(azimuth), np.radians(elevation)
    return np.array([np.cos(el) * np.cos(az), np.cos(el) * np.sin(az), np.sin(el)])


def views(n):
    return [(360.0 * k / n, ELEVATIONS[k % len(ELEVATIONS)]) for k in range(n)]


def samples(cam, polylines):
    """Points along the polylines' projections, each segment sampled every quarter pixel
    (vectorised): their pixels (n, 2) as (x, y), the polyline each lies on and its arc
    length from that polyline's start, in pixels."""
    segs, owner = [], []
    for i, P in enumerate(polylines):
        q = cam.pixels(np.vstack([P, P]) if len(P) == 1 else P)
        segs.append(np.stack([q[:-1], q[1:]], axis=1))
        owner.append(np.full(len(segs[-1]), i))
    if not segs:
        return np.zeros((0, 2), int), np.zeros(0, int), np.zeros(0)
    S = np.concatenate(segs)                                    # (m, 2, 2)
    owner = np.concatenate(owner)
    L = np.linalg.norm(S[:, 1] - S[:, 0], axis=1)
    before = np.cumsum(L) - L
    before -= before[np.searchsorted(owner, owner)]             # arc length at each segment's start
    k = np.maximum(2, (4 * L).astype(int) + 2)
    seg = np.repeat(np.arange(len(S)), k)
    t = (np.arange(k.sum()) - np.repeat(np.cumsum(k) - k, k)) / np.repeat(k - 1, k)
    pts = S[seg, 0] + t[:, None] * (S[seg, 1] - S[seg, 0])
    return np.round(pts).astype(int), owner[seg], before[seg] + t * L[seg]


def image(ij):
    """The pixels ij (n, 2) as (x, y) that fall in the picture, as a PX x PX mask."""
    img = np.zeros((PX, PX), bool)
    ok = (ij[:, 0] >= 0) & (ij[:, 0] < PX) & (ij[:, 1] >= 0) & (ij[:, 1] < PX)
    img[ij[ok, 1], ij[ok, 0]] = True
    return img


def raster(cam, polylines):
    """Pixels the polylines pass through."""
    return image(samples(cam, polylines)[0])


def points_image(cam, P):
    return image(np.round(cam.pixels(P)).astype(int))


def dilate(img):
    out = img.copy()
    for dx in (-1, 0, 1):
        for dy in (-1, 0, 1):
            out |= np.roll(np.roll(img, dx, 0), dy, 1)
    return out


@functools.lru_cache(maxsize=1)
def dense(ev, res):
    """The dense polygonisation of the ground truth and its vertices' unit normals."""
    mesh = polygonise(ev, res)
    _, g = ev.field_grad(mesh.vertices)
    return mesh, -g / np.maximum(np.linalg.norm(g, axis=1, keepdims=True), 1e-300)


def feature_points(ev, view, res):
    """The dense mesh's silhouette points and its crease points (the candidates that refine
    to creases), and the crease edges (:func:`edge_keys`). A mesh edge across a crease
    whose one sheet faces the eye and the other away changes the sign of n.v and so
    gives a silhouette point too, interpolated along the edge up to a cell off the crease
    where there is no smooth silhouette: those are left out. The crease edges come as a
    set of :func:`edge_keys`."""
    mesh, n = dense(ev, res)
    feats = process_edges(mesh, n, np.ones(len(n)), view)
    _, a, b = feats["crease"]
    surf = Surface(ev, view)
    crease = np.full(len(a), KIND_ID["crease"], np.int64)
    X, _, _, _, _, _, real, _, _ = refine_seeds(surf, crease, a, b, 1e-8 * ev.scale, DEFAULT_CREASE_ANGLE)
    creases = set(edge_keys(a[real], b[real]))
    sil, sa, sb = feats["silhouette"]
    smooth = np.array([k not in creases for k in edge_keys(sa, sb)], bool)
    print(f"  ground truth: {int(smooth.sum())} silhouette points ({int((~smooth).sum())} on crease edges left "
          f"out), {int(real.sum())} of {len(a)} crease candidates are creases", flush=True)
    return sil[smooth], X[real], creases


def edge_keys(a, b):
    """The mesh edges from points a to b (n, 3), each as one hashable key whichever way
    round they are given."""
    d = a - b
    first = np.argmax(d != 0, axis=1)
    less = d[np.arange(len(d)), first] < 0
    lo, hi = np.where(less[:, None], a, b), np.where(less[:, None], b, a)
    return [x.tobytes() + y.tobytes() for x, y in zip(lo, hi)]


def ground_truth(ev, view, cam, res):
    sil, crease, _ = feature_points(ev, view, res)
    return points_image(cam, np.concatenate([sil, crease]))


def silhouette_segments(mesh, n, view, creases=frozenset()):
    """The silhouette across each dense-mesh quad it crosses, (m, 2, 3): segments between
    the crossings of the quad's sides (process_edges' points), paired in order round the
    quad where all four sides cross; a side that is one of the ``creases`` (edge keys)
    is not crossed by a smooth silhouette (a quad left with one or three crossings is
    not joined across)."""
    V = mesh.vertices
    s = np.einsum("ij,ij->i", n, view.towards_eye(V))
    a, b = mesh.quads, np.roll(mesh.quads, -1, axis=1)
    cut = (s[a] > 0) != (s[b] > 0)
    if creases:
        q, side = np.nonzero(cut)
        on = np.array([k in creases for k in edge_keys(V[a[q, side]], V[b[q, side]])], bool)
        cut[q[on], side[on]] = False
    hit = np.isin(cut.sum(axis=1), (2, 4))
    a, b, cut = a[hit], b[hit], cut[hit]
    t = s[a] / np.where(cut, s[a] - s[b], 1.0)
    X = V[a] + t[..., None] * (V[b] - V[a])                     # (q, 4, 3) a point on each side
    X = np.take_along_axis(X, np.argsort(~cut, axis=1, kind="stable")[..., None], axis=1)
    return np.concatenate([X[:, :2], X[cut.sum(axis=1) == 4, 2:]])


def view_truth(ev, view, cam, res):
    """The ground truth from one view as three masks: its points (for coverage); the same
    joined up, silhouette points by the segments between them across the mesh's quads,
    crease points as they are (for gaps); and that with the crease points dilated by one
    pixel (for precision)."""
    sil, crease, creases = feature_points(ev, view, res)
    line = raster(cam, list(silhouette_segments(*dense(ev, res), view, creases)))
    points = points_image(cam, crease)
    return points_image(cam, np.concatenate([sil, crease])), line | points, line | dilate(points)


def coverage(gt, traced):
    """The share of ground-truth pixels within 1 pixel of the traced ones."""
    return (dilate(traced) & gt).sum() / max(gt.sum(), 1)


def precision(truth, traced):
    """The share of traced pixels within 1 pixel of the ground truth."""
    return (dilate(truth) & traced).sum() / max(traced.sum(), 1)


def components(mask):
    """The 8-connected components of a mask: its pixels' rows, columns and labels (the
    lowest index in the component of a pixel in nonzero order)."""
    ys, xs = np.nonzero(mask)
    idx = np.full(mask.shape, -1)
    idx[ys, xs] = np.arange(len(ys))
    I, J = [], []
    for dy, dx in ((0, 1), (1, -1), (1, 0), (1, 1)):
        y, x = ys + dy, xs + dx
        ok = (y < mask.shape[0]) & (x >= 0) & (x < mask.shape[1])
        j = idx[y[ok], x[ok]]
        I.append(np.flatnonzero(ok)[j >= 0])
        J.append(j[j >= 0])
    I, J = np.concatenate(I), np.concatenate(J)
    lab = np.arange(len(ys))
    while True:
        new = lab.copy()
        np.minimum.at(new, I, lab[J])
        np.minimum.at(new, J, lab[I])
        new = new[new]
        if np.array_equal(new, lab):
            return ys, xs, lab
        lab = new


def gaps(truth, traced):
    """Runs of ground-truth pixels not within 1 pixel of the traced ones (8-connected)
    wider or taller than GAP pixels."""
    ys, xs, lab = components(truth & ~dilate(traced))
    _, lab = np.unique(lab, return_inverse=True)
    n = lab.max() + 1 if len(lab) else 0

    def extent(v):
        lo, hi = np.full(n, PX), np.full(n, -1)
        np.minimum.at(lo, lab, v)
        np.maximum.at(hi, lab, v)
        return hi - lo + 1
    return int((np.maximum(extent(xs), extent(ys)) > GAP).sum())


def drawn(outlines):
    """The outlines' points, a closed one's first point repeated at its end."""
    return [np.vstack([o.points, o.points[:1]]) if o.closed else o.points for o in outlines]


def dangling_ends(cam, outlines):
    """Ends of the open outlines (first and last points, in pixels) with no pixel of another
    outline, nor of their own more than ALONG pixels along it, within NEAR pixels, and more
    than NEAR pixels inside the picture."""
    ij, owner, arc = samples(cam, drawn(outlines))
    inside = (ij >= 0).all(axis=1) & (ij < PX).all(axis=1)
    ij, owner, arc = ij[inside], owner[inside], arc[inside]
    key = ij[:, 1] * PX + ij[:, 0]
    order = np.argsort(key, kind="stable")
    key = key[order]
    count = 0
    for i, o in enumerate(outlines):
        if o.closed:
            continue
        q = cam.pixels(o.points)
        length = np.linalg.norm(np.diff(q, axis=0), axis=1).sum()
        for (x, y), at in zip(np.round(q[[0, -1]]).astype(int), (0.0, length)):
            if min(x, y, PX - 1 - x, PX - 1 - y) <= NEAR:
                continue
            rows = [(y + dy) * PX + x for dy in range(-NEAR, NEAR + 1)]
            near = np.concatenate([order[np.searchsorted(key, r - NEAR):np.searchsorted(key, r + NEAR, "right")]
                                   for r in rows])
            count += not np.any((owner[near] != i) | (np.abs(arc[near] - at) > ALONG))
    return count
