"""The `render` subcommand of the command line (Blender layer: it needs bpy)."""
from ..model import ModelError, load


def add_parser(sub):
    p = sub.add_parser("render", help="illustrate a model: DIR/NAME.png, .blend and .svg")
    p.add_argument("model", help="blobtree-1 JSON file")
    p.add_argument("--out", required=True, help="output directory (must exist)")
    p.add_argument("--size", type=int, default=1024, help="image size in pixels (default 1024)")
    p.add_argument("--grid", type=int, default=20, help="blackboard grid resolution, 8-128 (default 20)")
    p.add_argument("--agents", type=int, default=32, help="number of agents, stepped together (default 32)")
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--azimuth", type=float, default=35.0, help="camera azimuth in degrees from the front")
    p.add_argument("--elevation", type=float, default=25.0, help="camera elevation in degrees")
    p.add_argument("--requests", default="outlines",
                   help="what to draw, comma-separated: outlines, hatching, stipples (default outlines)")
    p.add_argument("--seconds", type=float, default=None, help="time budget for the agents")
    p.set_defaults(func=run)


def run(args, out):
    from .render import RenderError, illustrate
    from ..cli.main import CliError
    try:
        model = load(args.model)
    except ModelError as e:
        raise CliError(str(e)) from None
    try:
        illustrate(model, args.out, size=args.size, grid=args.grid, agents=args.agents, seed=args.seed,
                   azimuth=args.azimuth, elevation=args.elevation, seconds=args.seconds,
                   requests=tuple(r.strip() for r in args.requests.split(",") if r.strip()),
                   log=lambda m: (out.write(m + "\n"), out.flush()))
    except RenderError as e:
        raise CliError(str(e)) from None
    return 0


def register():
    from ..cli.main import register_command
    register_command("render", add_parser)


def unregister():
    from ..cli.main import unregister_command
    unregister_command("render")

