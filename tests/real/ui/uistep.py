"""Helper for UI scripts: ask the harness for a screenshot or key presses from inside
Blender without blocking its event loop (generator steps driven by a bpy timer)."""
import json
import os

import bpy

OUT = os.environ["BTI_UI_OUT"]


class Steps:
    """Run a generator as a sequence of timer ticks. The generator yields either a
    number (seconds to wait) or a request dict for the harness (waits for the reply)."""

    def __init__(self, gen):
        self.gen = gen
        self.n = 0
        self.waiting = None
        bpy.app.timers.register(self.tick, first_interval=0.5, persistent=True)

    def request(self, **req):
        path = os.path.join(OUT, f"request-{self.n}.json")
        with open(path + ".tmp", "w") as fh:
            json.dump(req, fh)
        os.replace(path + ".tmp", path)
        self.waiting = os.path.join(OUT, f"reply-{self.n}.json")
        self.n += 1

    def tick(self):
        if self.waiting and not os.path.exists(self.waiting):
            return 0.05
        self.waiting = None
        try:
            item = next(self.gen)
        except StopIteration:
            self.request(action="done")
            bpy.ops.wm.quit_blender()
            return None
        except Exception as e:   # report, then let the harness finish
            record(error=f"{type(e).__name__}: {e}")
            self.request(action="done")
            bpy.ops.wm.quit_blender()
            raise
        if isinstance(item, dict):
            self.request(**item)
            return 0.05
        return float(item)


def record(**facts):
    """Merge facts into OUT/facts.json for the test to check."""
    path = os.path.join(OUT, "facts.json")
    data = json.load(open(path)) if os.path.exists(path) else {}
    data.update(facts)
    with open(path + ".tmp", "w") as fh:
        json.dump(data, fh, indent=1)
    os.replace(path + ".tmp", path)
