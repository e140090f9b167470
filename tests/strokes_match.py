"""Compare drawings stroke by stroke within a tolerance (every tier uses it: the golden
tests, the command line against the operators, the modal run against the background
run). A drawing is plain data: {layer: [(points (k,3), radius (k,), opacity (k,)), ...]}.

Two drawings match when they have strokes on the same layers, every layer the same
number of strokes within ``count`` (a fraction of the larger count: exactly the same
number on a layer of fewer than 1/count strokes), each drawing's points lie within
``dist`` of the other's (all of them on the outline layers, the ``q`` quantile of the
nearest-point distances on the stroke layers, both ways) and the layers' median radius
and opacity agree within ``rel``. Bit-for-bit equal drawings match at any tolerance; a
change that alters a drawing (strokes moved, added, lost, thicker) does not.
"""
import numpy as np


def from_stroke_set(stroke_set):
    return {name: [(np.asarray(s.points, float), np.asarray(s.radius, float), np.asarray(s.opacity, float))
                   for s in strokes] for name, strokes in stroke_set.layers.items() if strokes}


def from_grease_pencil(obj, frame=None):
    """The drawing of a Grease Pencil object's layers on a frame (default: each layer's first)."""
    out = {}
    for layer in obj.data.layers:
        frames = [f for f in layer.frames if frame is None or f.frame_number == frame]
        if not frames or not len(frames[0].drawing.strokes):
            continue
        d = frames[0].drawing
        strokes = []
        for s in d.strokes:
            pts = s.points
            strokes.append((np.array([p.position for p in pts], float), np.array([p.radius for p in pts], float),
                            np.array([p.opacity for p in pts], float)))
        out[layer.name] = strokes
    return out


def to_npz(drawing):
    """Flat arrays for np.savez: per layer the points, radii, opacities and stroke sizes."""
    arrays = {}
    for name, strokes in drawing.items():
        arrays[f"{name}/points"] = np.concatenate([s[0] for s in strokes]).reshape(-1, 3)
        arrays[f"{name}/radius"] = np.concatenate([s[1] for s in strokes])
        arrays[f"{name}/opacity"] = np.concatenate([s[2] for s in strokes])
        arrays[f"{name}/sizes"] = np.array([len(s[0]) for s in strokes], np.int64)
    return arrays


def from_npz(data):
    out = {}
    names = sorted({k.split("/")[0] for k in data.files})
    for name in names:
        cut = np.cumsum(data[f"{name}/sizes"])[:-1]
        out[name] = list(zip(np.split(data[f"{name}/points"], cut), np.split(data[f"{name}/radius"], cut),
                             np.split(data[f"{name}/opacity"], cut)))
    return out


def _nearest(A, B, block=2048):
    out = np.empty(len(A))
    for i in range(0, len(A), block):
        a = A[i:i + block]
        d2 = (a * a).sum(1)[:, None] + (B * B).sum(1)[None] - 2 * a @ B.T
        out[i:i + block] = np.sqrt(np.maximum(d2.min(axis=1), 0.0))
    return out


OUTLINE_LAYERS = ("Silhouette", "Crease", "Curvature")


def differences(a, b, dist, count=0.03, rel=0.05, q=0.98):
    """What differs between drawings a and b beyond the tolerances (an empty list: they match)."""
    out = []
    for name in sorted(set(a) | set(b)):
        sa, sb = a.get(name, []), b.get(name, [])
        if abs(len(sa) - len(sb)) > int(count * max(len(sa), len(sb))) or not sa or not sb:
            out.append(f"{name}: {len(sa)} strokes against {len(sb)}")
            continue
        A = np.concatenate([s[0] for s in sa])
        B = np.concatenate([s[0] for s in sb])
        for what, x, y in (("a->b", A, B), ("b->a", B, A)):
            d = np.quantile(_nearest(x, y), 1.0 if name in OUTLINE_LAYERS else q)
            if d > dist:
                out.append(f"{name}: {100 * q:.0f} % of points within {d:.3g} ({what}), tolerance {dist:.3g}")
        for i, what in ((1, "radius"), (2, "opacity")):
            ma, mb = (np.median(np.concatenate([s[i] for s in ss])) for ss in (sa, sb))
            if abs(ma - mb) > rel * max(abs(ma), abs(mb), 1e-12):
                out.append(f"{name}: median {what} {ma:.4g} against {mb:.4g}")
    return out
