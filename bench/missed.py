"""Where MASSRIS misses ground-truth outline pixels: a picture per model.

    python bench/missed.py [--models train,shell] [--grid 20] [--gt-res 256] [--limit 60] [--out DIR]

Runs a session to the end (or the time limit), then writes DIR/NAME-missed.png (1024 px,
the view of bench/outlines.py): ground-truth pixels covered within 1 pixel in green,
missed in red, traced outlines in grey. Prints the coverage and the time.
"""
import argparse
import os
import time

import outlines as O  # bench/outlines.py: the paths, the examples
import outlinemeasure as OM  # camera, ground truth, rasteriser
import numpy as np
from blobtree_ink import model as M
from blobtree_ink.agents import Session, Settings
from blobtree_ink.blackboard.view import View


def write_png(path, img):
    H, W, _ = img.shape
    raw = b"".join(b"\x00" + img[y].tobytes() for y in range(H))

    def chunk(t, d):
        return (O.struct.pack(">I", len(d)) + t + d + O.struct.pack(">I", O.zlib.crc32(t + d) & 0xffffffff))
    with open(path, "wb") as fh:
        fh.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", O.struct.pack(">IIBBBBB", W, H, 8, 2, 0, 0, 0)) +
                 chunk(b"IDAT", O.zlib.compress(raw)) + chunk(b"IEND", b""))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--models", default="train,shell")
    ap.add_argument("--grid", type=int, default=20)
    ap.add_argument("--gt-res", type=int, default=256)
    ap.add_argument("--limit", type=float, default=60.0)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--out", default="/tmp")
    a = ap.parse_args()
    for name in a.models.split(","):
        model = M.load(os.path.join(O.HERE, "..", "examples", f"{name}.json"))
        ev = M.Evaluator(model)
        cam = OM.Camera(ev)
        view = View(eye=cam.eye)
        gt = OM.ground_truth(ev, view, cam, a.gt_res)
        t0 = time.perf_counter()
        s = Session(model, view, Settings(resolution=a.grid, seed=a.seed))
        s.request("OUTLINES")
        s.run(seconds=a.limit)
        spent = time.perf_counter() - t0
        lines = OM.raster(cam, OM.drawn(s.outlines()))
        got = OM.dilate(lines) & gt
        img = np.full((OM.PX, OM.PX, 3), 255, np.uint8)
        img[lines] = (170, 170, 170)
        img[OM.dilate(gt & ~got)] = (230, 0, 0)
        img[got] = (0, 170, 0)
        path = os.path.join(a.out, f"{name}-missed.png")
        write_png(path, img)
        print(f"{name}: coverage {got.sum() / max(gt.sum(), 1):.3f} after {spent:.1f} s "
              f"({s.iteration} iterations, done={s.done}); {path}", flush=True)


if __name__ == "__main__":
    main()
