"""blobtree-ink: the command line shared by `blender -c blobtree_ink` and ./blobtree-ink.

Subcommands:
  info MODEL.json                      node count, iso, bounds
  eval MODEL.json --points IN.npy --out OUT.npy [--gradient]
  render MODEL.json --out DIR [...]    the illustration as PNG, .blend and SVG (needs Blender:
                                       its options are parsed here, the Blender layer renders)

Bad input (an invalid model, unreadable or malformed arrays) exits 1 with one line
naming what is wrong; usage errors exit 2. Outputs are written atomically.
"""
import argparse
import os
import sys
import tempfile

import numpy as np

from .. import model as M
from ..blackboard.polygonise import surface_box
from . import render_args
from .render_args import CliError  # noqa: F401  (the one user-facing error of every subcommand)


def _parser():
    p = argparse.ArgumentParser(prog="blobtree-ink",
                                description="BlobTree Ink: skeletal implicit models in pen and ink")
    sub = p.add_subparsers(dest="command", required=True, metavar="COMMAND")
    pi = sub.add_parser("info", help="print a model's node count, iso value and bounds")
    pi.add_argument("model", help="blobtree-1 JSON file")
    pe = sub.add_parser("eval", help="evaluate the field (and gradient) at points")
    pe.add_argument("model", help="blobtree-1 JSON file")
    pe.add_argument("--points", required=True, help="input .npy, an (N,3) float array")
    pe.add_argument("--out", required=True, help="output .npy: (N,) field or (N,4) field+gradient")
    pe.add_argument("--gradient", action="store_true", help="also write the gradient")
    render_args.add_parser(sub)
    return p


_RENDERER = []    # the Blender layer's renderer, while the extension is registered: fn(spec, log) -> status


def register_renderer(fn):
    _RENDERER[:] = [fn]


def unregister_renderer():
    _RENDERER.clear()


def _load_model(path):
    try:
        return M.load(path)
    except M.ModelError as e:
        raise CliError(str(e)) from None


def cmd_info(args, out):
    model = _load_model(args.model)
    ev = M.Evaluator(model)
    lo, hi = ev.bounds
    out.write(f"name: {model.name}\n")
    out.write(f"nodes: {M.count_nodes(model)}\n")
    out.write(f"iso: {model.iso:g}\n")
    out.write(f"support bounds: {_fmt(lo)} .. {_fmt(hi)}\n")
    sb = surface_box(ev, res=64, pad_cells=1.0)
    if sb is None:
        out.write("surface bounds: none (the field never reaches iso)\n")
    else:
        out.write(f"surface bounds: {_fmt(sb[0])} .. {_fmt(sb[1])}\n")
    return 0


def _fmt(v):
    return "(" + ", ".join(f"{x:.4g}" for x in v) + ")"


def _load_points(path):
    try:
        arr = np.load(path, allow_pickle=False)
    except FileNotFoundError:
        raise CliError(f"{path}: no such file") from None
    except (ValueError, OSError) as e:
        raise CliError(f"{path}: not a readable .npy array ({e})") from None
    if not isinstance(arr, np.ndarray) or arr.ndim != 2 or arr.shape[1] != 3:
        raise CliError(f"{path}: must hold an (N,3) array, got shape {getattr(arr, 'shape', '?')}")
    if arr.dtype.kind not in "fiu":
        raise CliError(f"{path}: must hold numbers, got dtype {arr.dtype}")
    arr = arr.astype(np.float64)
    bad = ~np.isfinite(arr).all(axis=1)
    if bad.any():
        raise CliError(f"{path}: row {int(np.flatnonzero(bad)[0])} is not finite")
    return arr


def save_npy_atomic(path, arr):
    d = os.path.dirname(os.path.abspath(path))
    if not os.path.isdir(d):
        raise CliError(f"{path}: directory {d} does not exist")
    fd, tmp = tempfile.mkstemp(prefix=".blobtree-", suffix=".npy", dir=d)
    try:
        with os.fdopen(fd, "wb") as fh:
            np.save(fh, arr)
        os.replace(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.unlink(tmp)
        raise


def cmd_eval(args, out):
    model = _load_model(args.model)
    P = _load_points(args.points)
    ev = M.Evaluator(model)
    if args.gradient:
        f, g = ev.field_grad(P)
        res = np.concatenate([f[:, None], g], axis=1)
    else:
        res = ev.field(P)
    save_npy_atomic(args.out, res)
    out.write(f"wrote {args.out}: {res.shape[0]} points\n")
    return 0


def cmd_render(args, out):
    spec = render_args.spec_from_args(args)
    if not _RENDERER:
        raise CliError("render needs Blender: run it as ./blobtree-ink render ... or blender -c blobtree_ink render ...")
    return _RENDERER[0](spec, lambda m: (out.write(m + "\n"), out.flush()))


COMMANDS = {"info": cmd_info, "eval": cmd_eval, "render": cmd_render}


def main(argv=None, out=None):
    """Run the command line; returns the exit status (never raises for user errors)."""
    out = out or sys.stdout
    argv = list(sys.argv[1:] if argv is None else argv)
    try:
        args = _parser().parse_args(argv)
    except SystemExit as e:          # argparse: usage error or --help
        return int(e.code or 0)
    try:
        return COMMANDS[args.command](args, out)
    except CliError as e:
        sys.stderr.write(f"blobtree-ink: error: {e}\n")
        return 1
