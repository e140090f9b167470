"""The `render` subcommand's options, parsed into a plain :class:`RenderSpec` (pure: the
Blender layer sets up the scene, camera and render and drives the pipeline with it).

    render MODEL.json --out DIR [options]            a model, framed in a three-quarter view
    render SCENE.blend --tree NAME [--frames A-B] --out DIR
                                                     a tree of a saved scene, as its camera sees
                                                     it, with its own settings, frame by frame
"""
import math
from dataclasses import dataclass

from ..agents import Settings
from ..blackboard.board import FEATURE_KINDS
from ..strokes import layers as L
from ..strokes import smarticles as sm
from ..strokes import style as ST


class CliError(Exception):
    """A user-facing error: printed as one line, exit status 1."""


@dataclass(frozen=True)
class RenderSpec:
    model: str                  # a blobtree-1 JSON file, or a .blend scene
    out: str                    # the output directory
    tree: str = None            # the BlobTree of a scene
    frames: tuple = None        # (first, last) frames of a scene (None: its current frame)
    size: int = 1024
    grid: int = 20
    agents: int = Settings.agents
    seed: int = 0
    azimuth: float = 35.0
    elevation: float = 25.0
    light: tuple = None         # towards the light; None: the viewer's upper left
    seconds: float = None       # a time budget for the agents
    style: ST.Style = None
    lines: tuple = Settings.kinds   # the kinds of feature outlines traced


def add_parser(sub):
    p = sub.add_parser("render", help="illustrate a model or a scene's tree: PNG, .blend and SVG")
    p.add_argument("model", help="a blobtree-1 JSON file, or a .blend scene (with --tree)")
    p.add_argument("--out", required=True, help="output directory (created if its parent exists)")
    p.add_argument("--tree", default=None, help="the BlobTree of a .blend scene (its own settings and style)")
    p.add_argument("--frames", default=None, help="frames of a .blend scene, A-B (default: its current frame): "
                   "DIR/NAME_####.png and .svg each")
    p.add_argument("--size", type=int, default=None, help="image size in pixels, 64-8192 (default 1024; a "
                   "scene: its own resolution)")
    p.add_argument("--grid", type=int, default=None, help="blackboard grid resolution, 8-128 (default 20)")
    p.add_argument("--agents", type=int, default=None,
                   help=f"number of agents, stepped together (default {Settings.agents})")
    p.add_argument("--seed", type=int, default=None, help="seed of the random choices (default 0)")
    p.add_argument("--azimuth", type=float, default=None, help="camera azimuth in degrees from the front (default 35)")
    p.add_argument("--elevation", type=float, default=None, help="camera elevation in degrees (default 25)")
    p.add_argument("--light", default=None, help="direction towards the light, x,y,z (write --light=-1,0,1 "
                   "for a leading minus; default: the viewer's upper left)")
    p.add_argument("--seconds", type=float, default=None, help="time budget for the agents")
    p.add_argument("--lines", default=None, help="the feature outlines to trace, comma-separated: any of "
                   f"{', '.join(FEATURE_KINDS)} (default {','.join(Settings.kinds)})")
    g = p.add_argument_group("style")
    g.add_argument("--style", default=None, choices=tuple(ST.STYLES),
                   help="a look of the papers' figures (default outlines); the options below change it")
    g.add_argument("--requests", default=None,
                   help="layers to draw, comma-separated, replacing the style's: " + ", ".join(ST.LAYER_SWITCHES))
    g.add_argument("--field", choices=L.FIELDS, default=None, help="flow field of hatching and short strokes")
    g.add_argument("--cross-field", choices=L.FIELDS, default=None,
                   help="flow field of the cross-hatching (default diagonal)")
    g.add_argument("--no-cross", action="store_true", help="no cross-hatching")
    g.add_argument("--axis", default=None, help="x,y,z of the axis flow field")
    g.add_argument("--weights", default=None,
                   help=f"steering weights: a preset ({', '.join(sm.PRESETS)}) or name=value pairs, "
                   f"e.g. flow=1,separation=0.5 (behaviours: {', '.join(ST.WEIGHT_NAMES)})")
    g.add_argument("--flock-size", type=int, default=None, help="smarticles per flock (1: no flocks)")
    g.add_argument("--surface", choices=ST.SURFACES, default=None, help="hatch all, convex or concave regions")
    g.add_argument("--chain-step", type=int, default=None, help="every n-th feature chain point starts a stroke")
    g.add_argument("--chain-angle", type=float, default=None, help="degrees between a chain and its strokes")
    g.add_argument("--stipple-every", type=int, default=None, help="a stipple at every k-th wander step")
    g.add_argument("--line-width", type=float, default=None, help="line width factor (default 1)")
    g.add_argument("--contrast", type=float, default=None, help="0-1: how much of the tonal range the light spans (0: one flat tone)")
    return p


def floats(text, what):
    try:
        v = tuple(float(x) for x in text.split(","))
    except ValueError:
        v = ()
    if len(v) != 3 or not all(math.isfinite(x) for x in v):
        raise CliError(f"{what} must be three comma-separated finite numbers x,y,z, got {text!r}")
    return v


def weights(text):
    if "=" not in text:
        return text.strip()
    out = {}
    for pair in text.split(","):
        k, _, v = pair.partition("=")
        try:
            out[k.strip()] = float(v)
        except ValueError:
            raise CliError(f"--weights: {pair!r} is not name=number") from None
    return out


def style_from_args(args):
    ch = {}
    if args.requests is not None:
        req = [r.strip() for r in args.requests.split(",") if r.strip()]
        bad = [r for r in req if r not in ST.LAYER_SWITCHES]
        if bad or not req:
            raise CliError(f"requests must be some of {', '.join(ST.LAYER_SWITCHES)}, "
                           f"got {', '.join(req) or 'none'}")
        ch.update({k: k in req for k in ST.LAYER_SWITCHES})
    if args.field is not None:
        ch["hatch_field"] = args.field
    if args.cross_field is not None:
        ch["cross_field"] = args.cross_field
    if args.no_cross:
        ch["cross_hatching"] = False
    if args.axis is not None:
        ch["hatch_axis"] = floats(args.axis, "--axis")
    if args.weights is not None:
        ch["weights"] = weights(args.weights)
    for key in ("flock_size", "surface", "chain_step", "chain_angle", "stipple_every", "line_width", "contrast"):
        if getattr(args, key) is not None:
            ch[key] = getattr(args, key)
    try:
        return ST.style(args.style, **ch)
    except ValueError as e:
        raise CliError(f"style: {e}") from None


MODEL_ONLY = ("grid", "agents", "seed", "azimuth", "elevation", "light", "seconds", "lines", "style", "requests", "field",
              "no_cross",
              "cross_field", "axis", "weights", "flock_size", "surface", "chain_step", "chain_angle",
              "stipple_every", "line_width", "contrast")


def frames_of(text):
    """(first, last) from "A-B" or "A"; CliError for anything else or a reversed range."""
    try:
        a, _, b = text.partition("-") if not text.startswith("-") else ("", "", "")
        first, last = int(a), int(b) if b else int(a)
    except ValueError:
        raise CliError(f"--frames must be A-B (two whole frame numbers, A first), got {text!r}") from None
    if last < first:
        raise CliError(f"--frames {text}: the range is empty (it ends before it starts)")
    return first, last


def spec_from_args(args):
    """The render's plain spec; CliError naming the first bad option."""
    if args.model.lower().endswith(".blend"):
        return _scene_spec(args)
    if args.tree is not None or args.frames is not None:
        raise CliError("--tree and --frames are for a .blend scene; a JSON model is one still")
    defaults = dict(size=1024, grid=20, agents=Settings.agents, seed=0, azimuth=35.0, elevation=25.0,
                    style="outlines")
    for k, v in defaults.items():
        if getattr(args, k) is None:
            setattr(args, k, v)
    style = style_from_args(args)
    light = None if args.light is None else floats(args.light, "--light")
    if light is not None and not any(light):
        raise CliError(f"--light: the light direction must not be zero, got {args.light!r}")
    if not 64 <= args.size <= 8192:
        raise CliError(f"--size must be from 64 to 8192 pixels, got {args.size}")
    for name, v, lo, hi in (("--azimuth", args.azimuth, -360.0, 360.0), ("--elevation", args.elevation, -89.0, 89.0)):
        if not (math.isfinite(v) and lo <= v <= hi):
            raise CliError(f"{name} must be a number from {lo:g} to {hi:g} degrees, got {v!r}")
    if args.seconds is not None and not (math.isfinite(args.seconds) and args.seconds > 0):
        raise CliError(f"--seconds must be a positive number, got {args.seconds!r}")
    if args.seed < 0:
        raise CliError(f"--seed must be a whole number from 0, got {args.seed}")
    lines = Settings.kinds if args.lines is None else lines_of(args.lines)
    try:
        Settings(resolution=args.grid, agents=args.agents, seed=args.seed, kinds=lines).check()
    except ValueError as e:
        raise CliError(str(e)) from None
    return RenderSpec(model=args.model, out=args.out, size=args.size, grid=args.grid, agents=args.agents,
                      seed=args.seed, azimuth=args.azimuth, elevation=args.elevation, light=light,
                      seconds=args.seconds, style=style, lines=lines)


def lines_of(text):
    """The kinds of feature outlines of "--lines a,b", in FEATURE_KINDS order."""
    got = [k.strip() for k in text.split(",") if k.strip()]
    bad = [k for k in got if k not in FEATURE_KINDS]
    if bad or not got:
        raise CliError(f"--lines must be one or more of {', '.join(FEATURE_KINDS)}, got {', '.join(bad) or 'none'}")
    return tuple(k for k in FEATURE_KINDS if k in got)


def _scene_spec(args):
    """A .blend scene's render: its tree (settings and style its own), its frames."""
    if not args.tree:
        raise CliError("a .blend scene needs --tree NAME: the BlobTree to illustrate")
    given = [f"--{k.replace('_', '-')}" for k in MODEL_ONLY if getattr(args, k, None) not in (None, False)]
    if given:
        raise CliError(f"{', '.join(given)}: a scene's tree has its own settings and style (set them in Blender)")
    if args.size is not None and not 64 <= args.size <= 8192:
        raise CliError(f"--size must be from 64 to 8192 pixels, got {args.size}")
    frames = None if args.frames is None else frames_of(args.frames)
    return RenderSpec(model=args.model, out=args.out, size=args.size, tree=args.tree, frames=frames)
