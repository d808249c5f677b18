"""Command line.

``noslipsim simulate SCENE.yaml --position X Y --velocity VX VY [--spin W] -n N [-o orbit.nc]``
``noslipsim run CONFIG.yaml -o dataset.nc``
"""
from __future__ import annotations

import argparse
import math
import sys

from ._version import __version__


def _parser():
    p = argparse.ArgumentParser(prog="noslipsim", description="noslipsim: no-slip billiards under a force")
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
    r = sub.add_parser("run", help="run an experiment from a YAML config and write its dataset")
    r.add_argument("config", help="YAML: {experiment: NAME, parameters: {...}}")
    r.add_argument("-o", "--output", required=True, help="netCDF file to write")
    return p


def _run_experiment(args):
    import yaml

    from .experiments import EXPERIMENTS
    from .io import write_dataset

    with open(args.config, encoding="utf-8") as fh:
        cfg = yaml.safe_load(fh)
    if not isinstance(cfg, dict) or set(cfg) - {"experiment", "parameters"} or "experiment" not in cfg:
        raise ValueError("config: expected a mapping with keys 'experiment' and 'parameters'")
    name = cfg["experiment"]
    if name not in EXPERIMENTS:
        raise ValueError(f"config.experiment: unknown experiment {name!r}; expected one of {sorted(EXPERIMENTS)}")
    params = cfg.get("parameters") or {}
    try:
        ds = EXPERIMENTS[name](**params)
    except TypeError as err:
        raise ValueError(f"config.parameters: {err}") from None
    write_dataset(ds, args.output, config=cfg)
    print(f"wrote {name} to {args.output}")


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

    if args.command == "run":
        try:
            _run_experiment(args)
        except (ValueError, OSError) as err:
            print(f"noslipsim: error: {err}", file=sys.stderr)
            return 2
        return 0
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
