"""Command line: ``noslipsim simulate SCENE.yaml --position X Y --velocity VX VY [--spin W] -n N [-o orbit.nc]``."""
from __future__ import annotations

import argparse
import math
import sys

from ._version import __version__


def _parser():
    p = argparse.ArgumentParser(prog="noslipsim", description=__doc__.split(":", 1)[0])
    p.add_argument("--version", action="version", version=f"noslipsim {__version__}")
    sub = p.add_subparsers(dest="command", required=True)
    s = sub.add_parser("simulate", help="simulate one orbit of a scene file")
    s.add_argument("scene", help="scene file (YAML, DESIGN section 4)")
    s.add_argument("--position", nargs=2, type=float, required=True, metavar=("X", "Y"))
    s.add_argument("--velocity", nargs=2, type=float, required=True, metavar=("VX", "VY"))
    s.add_argument("--spin", type=float, default=0.0, help="scaled spin w = gamma R omega (CCW positive)")
    s.add_argument("-n", "--max-collisions", type=int, default=20)
    s.add_argument("--max-time", type=float, default=math.inf)
    s.add_argument("--stop-below", type=float, default=None, help="stop when crossing this height downwards")
    s.add_argument("-o", "--output", help="write the orbit to this netCDF file instead of printing it")
    return p


def _print_table(ds, out):
    cols = ["t", "x", "y", "vx", "vy", "spin", "element", "s"]
    out.write("  ".join(f"{c:>12}" for c in ["collision"] + cols) + "\n")
    for i in range(ds.sizes["collision"]):
        vals = [f"{i:>12d}"] + [f"{int(ds[c][i]):>12d}" if c == "element" else f"{float(ds[c][i]):>12.6g}"
                               for c in cols]
        out.write("  ".join(vals) + "\n")
    out.write(f"stop_reason: {ds.attrs['stop_reason']}  collisions: {int(ds.n_collisions)}  "
              f"final t={float(ds.t_final):.6g} x={float(ds.x_final):.6g} y={float(ds.y_final):.6g}\n")


def main(argv=None):
    args = _parser().parse_args(argv)
    from .scenes import Scene
    from .simulate import simulate

    try:
        scene = Scene.from_yaml(args.scene)
        ds = simulate(scene, args.position, args.velocity, args.spin, max_collisions=args.max_collisions,
                      max_time=args.max_time, stop_below=args.stop_below)
    except (ValueError, OSError) as err:
        print(f"noslipsim: error: {err}", file=sys.stderr)
        return 2
    if args.output:
        ds.to_netcdf(args.output)
        print(f"wrote {int(ds.n_collisions)} collisions to {args.output} ({ds.attrs['stop_reason']})")
    else:
        _print_table(ds, sys.stdout)
    return 0


if __name__ == "__main__":
    sys.exit(main())
