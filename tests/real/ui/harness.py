"""Drive the real Blender UI under Xvfb (run where Blender lives: tools/blender-env).

    python3 harness.py --script UI_SCRIPT.py --out DIR [--user DIR] [--steps STEPS.json]

Starts Xvfb, starts Blender (full UI, factory settings, the extension enabled by the
UI script) and then follows the steps the UI script asks for: the script writes
requests into DIR/request-N.json ({"action": "screenshot"|"key"|"type"|"mouse"|"done", ...})
and the harness answers with DIR/reply-N.json after taking an `xwd -root` screenshot
(Blender's own screenshot operator gives a black image under Xvfb), or sending keys,
typed text, or a mouse move (and click) to screen pixels with xdotool.
"""
import argparse
import json
import os
import signal
import subprocess
import sys
import time


def wait_for(path, timeout, proc=None):
    end = time.time() + timeout
    while time.time() < end:
        if os.path.exists(path):
            time.sleep(0.05)
            return True
        if proc is not None and proc.poll() is not None:
            return False
        time.sleep(0.05)
    return False


def screenshot(display, png, tries=5):
    """The screen as a PNG; taken again when it is one flat colour (caught mid-redraw)."""
    for _ in range(tries):
        xwd = subprocess.run(["xwd", "-root", "-silent", "-display", display], check=True,
                             capture_output=True).stdout
        subprocess.run(["convert", "xwd:-", "png:" + png], input=xwd, check=True)
        colours = subprocess.run(["identify", "-format", "%k", png], check=True, capture_output=True,
                                 text=True).stdout
        if colours.strip() != "1":
            return
        time.sleep(0.5)


def start_xvfb(display, screen, tries=5):
    """Xvfb on ``display``, once it answers (under load it can take more than a second,
    and a display its previous server just left may refuse a new one for a moment)."""
    env = dict(os.environ, DISPLAY=display)
    for _ in range(tries):
        xvfb = subprocess.Popen(["Xvfb", display, "-screen", "0", f"{screen}x24", "-nolisten", "tcp"],
                                stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        for _ in range(100):
            if xvfb.poll() is not None:
                break
            if subprocess.run(["xdotool", "getdisplaygeometry"], env=env, capture_output=True).returncode == 0:
                return xvfb
            time.sleep(0.1)
        if xvfb.poll() is None:
            xvfb.terminate()
            xvfb.wait()
        time.sleep(1.0)
    sys.exit(f"Xvfb did not start on {display}")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--script", required=True)
    ap.add_argument("--out", required=True)
    ap.add_argument("--user", required=True)
    ap.add_argument("--display", default=None, help="the X display (default: the first free one from :77)")
    ap.add_argument("--timeout", type=float, default=120)
    ap.add_argument("--screen", default="1600x900", help="the virtual screen's size, WxH")
    a = ap.parse_args()
    if a.display is None:               # several UI tests may run at once (each its own Xvfb)
        a.display = next(f":{n}" for n in range(77, 200) if not os.path.exists(f"/tmp/.X{n}-lock"))
    os.makedirs(a.out, exist_ok=True)
    env = dict(os.environ, DISPLAY=a.display, BLENDER_USER_RESOURCES=a.user, BTI_UI_OUT=a.out)
    xvfb = start_xvfb(a.display, a.screen)
    log = open(os.path.join(a.out, "blender.log"), "w")
    blender = None
    try:
        blender = subprocess.Popen(["blender", "--factory-startup", "--python", a.script],
                                   env=env, stdout=log, stderr=subprocess.STDOUT)
        n = 0
        deadline = time.time() + a.timeout
        while True:
            req = os.path.join(a.out, f"request-{n}.json")
            if not wait_for(req, max(1.0, deadline - time.time()), blender):
                sys.exit(f"UI script stopped answering at step {n} (see {a.out}/blender.log)")
            r = json.load(open(req))
            reply = {"ok": True}
            if r["action"] == "screenshot":
                screenshot(a.display, os.path.join(a.out, r["name"]))
            elif r["action"] == "key":
                for k in r["keys"]:
                    subprocess.run(["xdotool", "key", k], env=env, check=True)
                    time.sleep(r.get("pause", 0.2))
            elif r["action"] == "type":
                subprocess.run(["xdotool", "type", "--delay", "120", "--", r["text"]], env=env, check=True)
                time.sleep(r.get("pause", 0.2))
            elif r["action"] == "mouse":
                subprocess.run(["xdotool", "mousemove", str(r["x"]), str(r["y"])], env=env, check=True)
                time.sleep(r.get("pause", 0.2))
                if r.get("click"):
                    subprocess.run(["xdotool", "click", str(r["click"])], env=env, check=True)
                    time.sleep(r.get("pause", 0.2))
            elif r["action"] == "done":
                break
            with open(os.path.join(a.out, f"reply-{n}.json.tmp"), "w") as fh:
                json.dump(reply, fh)
            os.replace(os.path.join(a.out, f"reply-{n}.json.tmp"), os.path.join(a.out, f"reply-{n}.json"))
            n += 1
        blender.wait(timeout=30)
    finally:
        if blender is not None and blender.poll() is None:
            blender.send_signal(signal.SIGTERM)
            try:
                blender.wait(timeout=10)
            except subprocess.TimeoutExpired:
                blender.kill()
        xvfb.terminate()
        xvfb.wait()
        log.close()


if __name__ == "__main__":
    main()
