"""Helper for UI scripts: ask the harness for a screenshot or key presses from inside
Blender without blocking its event loop (generator steps driven by a bpy timer)."""
import json
import os

import addon_utils
import bpy

OUT = os.environ["BTI_UI_OUT"]
EXT = "bl_ext.user_default.blobtree_ink"
REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))))


def started(keep_cube=False):
    """A generator step: past the splash, the extension enabled (and, unless
    ``keep_cube``, the default cube gone [Python]). Returns the window, the largest 3D
    viewport and its main region (``yield from`` it)."""
    yield 1.0
    yield {"action": "key", "keys": ["Escape"]}          # the splash takes the first Escape
    addon_utils.enable(EXT, default_set=True)
    win = bpy.context.window_manager.windows[0]
    for obj in [] if keep_cube else list(bpy.data.objects):
        if obj.type == "MESH":
            bpy.data.objects.remove(obj)
    view3d = max((a for a in win.screen.areas if a.type == "VIEW_3D"), key=lambda a: a.width * a.height)
    region = [r for r in view3d.regions if r.type == "WINDOW"][0]
    return win, view3d, region


def start_with_example(name, preview=False):
    """:func:`started`, then an example imported in the 3D viewport (with its preview
    mesh when ``preview``)."""
    win, view3d, region = yield from started()
    with bpy.context.temp_override(window=win, area=view3d, region=region):
        bpy.ops.blobtree_ink.import_json(filepath=os.path.join(REPO, "examples", f"{name}.json"), preview=preview)
    return win, view3d, region


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
