"""Polygon edge processing (paper section 4): every edge of the rough polygonisation
is tested for crossing a silhouette (n.v changes sign), a discontinuity or small-scale
detail (the angle between the end normals exceeds a threshold: CSG creases), a change
of sign of the mean curvature, and (given the vertices' radial curvature) a change of
its sign between two ends that face the eye (suggestive contours). Crossings are
located by linear interpolation and stored as approximate feature points, with the
edge's ends as a bracket for refining."""
import numpy as np

DEFAULT_CREASE_ANGLE = np.radians(35.0)


def process_edges(mesh, normals, mean_curv, view, crease_angle=DEFAULT_CREASE_ANGLE, curv_eps=1e-9, radial=None):
    """{kind: (points, a, b)} approximate feature points with their bracketing ends
    ("suggestive" given ``radial``, the vertices' radial curvature)."""
    E = mesh.edges()
    V = mesh.vertices
    i, j = E[:, 0], E[:, 1]
    out = {}
    s = np.einsum("ij,ij->i", normals, view.towards_eye(V))
    si, sj = s[i], s[j]
    m = (si > 0) != (sj > 0)
    t = si[m] / np.where(si[m] - sj[m] == 0, 1, si[m] - sj[m])
    out["silhouette"] = _lerp(V, i[m], j[m], t)
    dot = np.clip(np.einsum("ij,ij->i", normals[i], normals[j]), -1, 1)
    m = np.arccos(dot) > crease_angle
    out["crease"] = _lerp(V, i[m], j[m], np.full(m.sum(), 0.5))
    hi_, hj = mean_curv[i], mean_curv[j]
    m = (np.abs(hi_) > curv_eps) & (np.abs(hj) > curv_eps) & ((hi_ > 0) != (hj > 0))
    m &= np.isfinite(hi_) & np.isfinite(hj)
    t = hi_[m] / (hi_[m] - hj[m])
    out["curvature"] = _lerp(V, i[m], j[m], t)
    if radial is not None:
        ri, rj = radial[i], radial[j]
        m = (si > 0) & (sj > 0) & np.isfinite(ri) & np.isfinite(rj) & ((ri > 0) != (rj > 0))
        t = ri[m] / np.where(ri[m] == rj[m], 1.0, ri[m] - rj[m])
        out["suggestive"] = _lerp(V, i[m], j[m], t)
    return out


def _lerp(V, i, j, t):
    a, b = V[i], V[j]
    return a + t[:, None] * (b - a), a, b
