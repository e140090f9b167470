"""Feature outlines as plain data: polylines by kind, each point with its normal, and
the step they were traced with."""
from dataclasses import dataclass

import numpy as np

from .stitch import SAME_SHEET, join_ends, stitch

MEET = 1.0          # a free end reaches into another piece up to this many of the coarse step ...
MEET_AHEAD = 0.5    # ... within 60 degrees of its direction


@dataclass
class Outline:
    kind: str
    points: np.ndarray
    normals: np.ndarray
    closed: bool
    step: float = 0.0           # the trace step it was traced with (0: not known)

    @property
    def length(self):
        p = np.vstack([self.points, self.points[:1]]) if self.closed else self.points
        return float(np.linalg.norm(np.diff(p, axis=0), axis=1).sum())


def total_length(outlines):
    """The summed length of outlines (their segments in one batch; a closed one's
    closing segment included)."""
    outlines = [o for o in outlines if len(o.points)]
    if not outlines:
        return 0.0
    P = np.concatenate([np.vstack([o.points, o.points[:1]]) if o.closed else o.points for o in outlines])
    seg = np.linalg.norm(np.diff(P, axis=0), axis=1)
    ends = np.cumsum([len(o.points) + bool(o.closed) for o in outlines])[:-1] - 1   # no segment across outlines
    seg[ends] = 0.0
    return float(seg.sum())


def stitch_scales(outlines, link=2.5, fill=None):
    """Fragments stitched into whole polylines with those traced at their own scale
    (within ``link`` of their step): a subdivided voxel's small outlines (a wheel's
    holes) lie closer together than the session's step. Then the open ones of one kind
    whose ends face each other are joined across scales, and fine pieces farther apart
    than their own stitching reaches (:func:`across_scales`), and ``fill`` (given the
    outlines and their bridges; agents.bridges) puts outline points on those joins."""
    out = []
    for step in sorted({o.step for o in outlines}):
        out += stitch([o for o in outlines if o.step == step], link * step,
                      lambda *a, step=step: Outline(*a, step=step))
    out, bridges = across_scales(out, link)
    return fill(out, bridges) if fill is not None and any(b is not None for b in bridges) else out


def across_scales(outlines, link):
    """Open outlines of one kind joined where their ends face each other (agents.stitch.
    join_ends) across up to REACH links of the coarsest step of that kind, when one of
    them at least was traced at a finer scale: a curve that runs through a subdivided
    voxel arrives in pieces of both scales (a train window's rim traced round at the
    fine scale but for one side, which a trace of the session's step found), or in
    fine pieces that stopped short of each other on a coarse line's points, and each
    scale's stitching sees only its own and its own reach. An end left free reaches the
    nearest point ahead of it of a piece of another scale within MEET of the coarse
    step (:func:`agents.stitch.join_ends`): a fine trace stops short where it meets a
    coarse one's point (a window's rim meeting the frame's crease), that much away;
    closed outlines are reached too, never joined. A crease's points carry one of its
    sheets' normals, which need not agree across the gap (a rounded corner of that
    rim): creases are joined whatever their normals. A joined outline takes the
    finer step; one whose ends so meet is closed. Returns the outlines and, for each
    joined one, (the step each of its segments is measured against, which joins must
    hold the line) (segment i runs from point i to the next; a closed outline's last, to
    its first): a join is measured against its outline's step, a piece's own segment
    against its piece's (other outlines: None), and which joins are kept only where the
    line is found along them (agents.bridges): those of two fine pieces, which their
    own stitching did not reach."""
    if len({o.step for o in outlines}) < 2:
        return outlines, [None] * len(outlines)
    out = [o for o in outlines if o.closed or len(o.points) < 2]
    bridges = [None] * len(out)
    for kind in sorted({o.kind for o in outlines}):
        mine = [o for o in outlines if o.kind == kind and not o.closed and len(o.points) >= 2]
        rings = [o for o in outlines if o.kind == kind and o.closed and len(o.points) > 3]   # reached, not joined
        coarse = max([o.step for o in mine + rings], default=0.0)
        if all(o.step == coarse for o in mine + rings):
            out += mine
            bridges += [None] * len(mine)
            continue
        sizes = [len(o.points) for o in mine + rings]
        P = np.concatenate([o.points for o in mine + rings])
        N = np.concatenate([o.normals for o in mine + rings])
        step = np.repeat([o.step for o in mine + rings], sizes)
        member = np.repeat(np.arange(len(mine) + len(rings)), sizes)
        group = np.where(step == coarse, -1, member)        # the coarse pieces are stitched together already
        first = np.cumsum(sizes) - sizes
        chains = [list(range(f, f + n)) for f, n in zip(first.tolist(), sizes)]
        for c in range(len(mine), len(chains)):
            chains[c].append(chains[c][0])               # a ring's ends meet: it has no free end
        for idx, closed in join_ends(P, N, chains, link * step, reach=MEET * coarse, ahead=MEET_AHEAD, group=group,
                                     apart=link * coarse, same_sheet=-1.0 if kind == "crease" else SAME_SHEET):
            m, st = member[idx], step[idx]
            if m[0] >= len(mine) and (m == m[0]).all():
                continue                                    # a closed outline, as it was
            nxt = np.r_[np.arange(1, len(idx)), 0][:len(idx) - (not closed)]
            joins = m[nxt] != m[:len(nxt)]
            fine = float(st.min())
            out.append(Outline(kind, P[idx], N[idx], bool(closed), fine))
            # (two fine pieces farther apart than their own stitching reaches: kept only where the line is found)
            farther = joins & (st[:len(nxt)] < coarse) & (st[nxt] < coarse)
            bridges.append((np.where(joins, fine, st[:len(nxt)]), farther) if joins.any() else None)
    return out, bridges
