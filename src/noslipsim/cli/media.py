"""``noslipsim animate`` (a GIF or MP4 of orbits) and ``noslipsim explore`` (the explorer in the browser)."""
from __future__ import annotations

import math


def add_commands(sub, debug):
    """Register ``animate`` and ``explore`` on ``sub``."""
    a = sub.add_parser("animate", help="animate orbits of a scene file to a GIF or MP4",
                       description="Orbits drawn as disks with a spin marker and a trail; frames evaluate the exact "
                                   "flights, and the frame nearest each collision is drawn at its exact time. "
                                   "Repeat --position/--velocity (and --spin) for several orbits. GIF needs "
                                   "nothing more; MP4 needs ffmpeg (imageio-ffmpeg, the 'animate' extra, or the "
                                   "system's).")
    a.add_argument("scene", help="scene file (YAML; format in docs/scenes.md)")
    a.add_argument("--position", nargs=2, type=float, action="append", required=True, metavar=("X", "Y"),
                   help="start point, strictly inside the table (repeat for more orbits)")
    a.add_argument("--velocity", nargs=2, type=float, action="append", required=True, metavar=("VX", "VY"),
                   help="initial velocity (one per --position)")
    a.add_argument("--spin", type=float, action="append", default=None,
                   help="scaled spin w = gamma R omega, CCW positive (one per --position; default 0)")
    a.add_argument("-n", "--max-collisions", type=int, default=30, help="collisions per orbit (default 30)")
    a.add_argument("--max-time", type=float, default=None,
                   help="simulated time shown (default: until the last collision)")
    a.add_argument("--duration", type=float, default=8.0, help="seconds of playback (default 8)")
    a.add_argument("--fps", type=int, default=20, help="frames per second (default 20)")
    a.add_argument("--portrait", action="store_true",
                   help="add the phase portrait filling in (velocity for no-slip, Birkhoff for specular)")
    a.add_argument("--trail", type=float, default=None, help="show the last T time units of path only")
    a.add_argument("--window", nargs=4, type=float, metavar=("X0", "X1", "Y0", "Y1"),
                   help="region shown (default: the table and every orbit)")
    a.add_argument("--radius", type=float, default=None,
                   help="drawn radius of the particle (default: 2.5%% of the view)")
    a.add_argument("--dpi", type=int, default=100, help="frame resolution (default 100)")
    a.add_argument("-o", "--output", required=True, help="file to write: .gif or .mp4")
    a.add_argument("--debug", **debug)

    e = sub.add_parser("explore", help="the explorer: the table and its portrait in the browser",
                       description="Serves the explorer of one scene file on this machine: the table with the "
                                   "particles moving, the phase portrait filling in, controls; click in the "
                                   "portrait or drag in the table to launch orbits. Needs the 'explore' extra "
                                   "(pip install 'noslipsim[explore]'). Stop with Ctrl-C.")
    e.add_argument("scene", help="scene file (YAML; the only file the server reads, anew for each page)")
    e.add_argument("--address", default=None,
                   help="interface to listen on (default 127.0.0.1: this machine only; any other needs "
                        "--allow-host; an SSH tunnel is safer, docs/explorer.md)")
    e.add_argument("--allow-host", action="append", default=[], metavar="NAME[:PORT]",
                   help="a host name or address the pages use to reach the server (repeat for more); "
                        "requests naming any other host are refused")
    e.add_argument("--port", type=int, default=5006, help="TCP port (default 5006; 0 picks a free one)")
    e.add_argument("--no-browser", action="store_true", help="do not open a browser")
    e.add_argument("--max-orbits", type=int, default=None, help="orbits one page may run at once (default 200)")
    e.add_argument("--max-collisions", type=int, default=None,
                   help="collisions computed per orbit (default 20000)")
    e.add_argument("--debug", **debug)
    return {"animate": animate, "explore": explore}


def animate(args):
    """``noslipsim animate``: write the animation."""
    from ..animation import animate as write_animation
    from ..scenes import Scene
    from .options import _start_errors

    scene = Scene.from_yaml(args.scene)
    n = len(args.position)
    if len(args.velocity) != n:
        raise ValueError(f"--velocity: give one per --position ({n}), got {len(args.velocity)}")
    spins = args.spin or [0.0] * n
    if len(spins) != n:
        raise ValueError(f"--spin: give one per --position ({n}) or none, got {len(spins)}")
    starts = list(zip(args.position, args.velocity, spins, strict=True))
    out = _start_errors(write_animation, scene, starts, args.output, max_collisions=args.max_collisions,
                        max_time=args.max_time, duration=args.duration, fps=args.fps, portrait=args.portrait,
                        trail=args.trail, window=args.window, radius=args.radius, dpi=args.dpi)
    hits = sum(len(h) for h in out["collision_frames"])
    print(f"wrote {args.output} ({out['frames']} frames, {n} orbit{'s' * (n > 1)}, "
          f"{hits} frames drawn at a collision)" + _stopped(out))


def _stopped(out):
    """``; orbit 2 stopped at t = ... (reason) and is drawn there from then on`` for each orbit that ended early."""
    t_show = out["times"][-1]
    notes = [f"orbit {j + 1} stopped at t = {float(o.t_final):.4g} ({o.attrs['stop_reason']})"
             for j, o in enumerate(out["orbits"]) if out["orbit_times"][j][-1] < t_show]
    return f"; {', '.join(notes)}, drawn where it stopped from then on" if notes else ""


def explore(args):
    """``noslipsim explore``: serve the explorer until interrupted."""
    try:
        from ..explorer.server import DEFAULT_ADDRESS, load_scene, serve
        from ..explorer.session import Limits
    except ImportError as err:
        raise ValueError(f"the explorer needs Panel and Bokeh ({err}): pip install 'noslipsim[explore]'") from None
    _, error = load_scene(args.scene)
    if error is not None:
        import sys

        print(error, file=sys.stderr)  # and the page shows the same line
    limits = {}
    if args.max_orbits is not None:
        limits["max_orbits"] = _count(args.max_orbits, "--max-orbits")
    if args.max_collisions is not None:
        limits["max_collisions"] = _count(args.max_collisions, "--max-collisions")
    if not 0 <= args.port < 65536:
        raise ValueError(f"--port: expected 0 to 65535, got {args.port}")
    serve(args.scene, address=args.address or DEFAULT_ADDRESS, port=args.port, show=not args.no_browser,
          limits=Limits(**limits), allow_hosts=args.allow_host, say=lambda line: print(line, flush=True))


def _count(value, option):
    if not (1 <= value < math.inf):
        raise ValueError(f"{option}: must be >= 1, got {value}")
    return value
