"""A sampling session's results (agents.session.Session's own methods, kept apart): its
outlines stitched into whole polylines, its progress figures and the plain
:class:`Sampling` value it hands out."""
import numpy as np

from .bridges import filled
from .outline import stitch_scales, total_length
from .sampling import Sampling


class Results:
    """What a :class:`agents.session.Session` has found so far (mixed into it: these
    read its traces, ridges, blackboard and mesh, and keep its last stitching)."""

    def outlines(self, include_active=True):
        """Feature outlines found so far, fragments stitched into whole polylines (once
        per state: a finished session's are stitched once)."""
        state = (self.iteration, len(self.traces.done), len(self.traces), len(self.ridges.done), len(self.ridges),
                 include_active)
        if self._stitched is not None and self._stitched[0] == state:
            return list(self._stitched[1])
        whole = self.carried.whole                 # the last frame's, as they were: stitched then
        mine = {id(o) for o in whole}
        out = [o for o in self.traces.done if id(o) not in mine] + self.ridges.done
        if include_active:
            out += self.traces.active_outlines() + self.ridges.active_outlines()
        out = whole + stitch_scales(out, fill=lambda outs, bridges: filled(self.surface, outs, bridges, self.tol,
                                                                             self.settings.crease_angle))
        self._stitched = (state, tuple(out))
        return out

    def progress(self, outlines=None):
        """Progress figures; ``outlines``: this session's :meth:`outlines` if the caller
        has them already (stitching them is not free)."""
        outs = self.outlines() if outlines is None else outlines
        used = self.bb.feat["used"]
        return {"iterations": self.iteration, "tasks_left": self.tasks_left,
                "outline_length": total_length(outs),
                "outlines": len(outs), "busy_agents": self.pool.busy,
                "seeds": len(used), "seeds_taken": int(np.count_nonzero(used)),
                "tasks_started": self.traces.serial + self.explorers.started + self.ridges.started,
                "tasks_ended": self.traces.serial - len(self.traces) + self.explorers.started - len(self.explorers)
                + self.ridges.started - len(self.ridges)}

    def snapshot(self, stitch=True):
        """What the session has found so far, as a plain :class:`Sampling` value (the
        stroke layers read it; nothing of the session's own state is shared: the arrays
        are the session's and are never changed in place once handed out). Without
        ``stitch`` the outlines are the traces' fragments as they are (a live view while
        tracing: stitching every iteration would cost more than the iteration)."""
        outs = self.outlines() if stitch else self.traces.done + self.traces.active_outlines() + \
            self.ridges.done + self.ridges.active_outlines()
        for a in (self.mesh.vertices, self.mesh.quads, self.vertex_normals, *self.vertex_curvature.values()):
            a.setflags(write=False)            # handed out: a reader cannot change the session's arrays
        return Sampling(outlines=outs, vertices=self.mesh.vertices, quads=self.mesh.quads,
                        vertex_normals=self.vertex_normals, vertex_curvature=dict(self.vertex_curvature),
                        cell=self.h, progress=self.progress(outs), done=self.done)
