"""What one frame's illustration leaves the next frame's (Illustration(job,
previous=...)): its compiled model, which the next frame takes as it is where its model
is the same (with what it made: its plan, its surface's size, its marks), its
sampling session's continuation (agents.continuation: the outlines where nothing
changed are kept, the others seeded from the last frame's), and the compiled models
that hid its lines, which the next frame takes where its occluders' models are the
same."""
from dataclasses import dataclass


@dataclass(frozen=True)
class Continuation:
    ev: object                  # model.Evaluator
    session: object = None      # agents.continuation.Continuation (None: the frame traced no outlines)
    occluders: tuple = ()       # model.Evaluator of each other model that hid its lines
