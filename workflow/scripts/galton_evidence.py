"""Dataset of Figure S2: the not-arrived share of the gap drop and of the bounded board, one setting changed at a time.

Cases (all to time_factor x T, both laws): ``board`` (the config's board and release), ``gap``
(the unbounded lattice, one drop point in the gap between two pegs: the reading before the bounded
board) and ``gap-bounded`` (that drop on the bounded board: its top row's gap); the bounded board
with another release point, spread or speed; both drops with another peg radius or number of rows;
the bounded board between side walls at x = +-width (``board-width-<w>``, walls of the pegs' law, and
``board-width-<w>-specular-walls``).
"""
import sys

sys.stderr = open(snakemake.log[0], "w", buffering=1)

from noslipsim import write_dataset
from noslipsim.cluster import ensemble_options
from noslipsim.experiments import galton_evidence

board, run = dict(snakemake.params.board), snakemake.params.run
termination = board.pop("max_time")
gap = dict(run["gap_drop"])
# the drops: the bounded board as configured, the gap drop on the unbounded lattice, and the gap drop's
# release on the bounded board (the drop point alone, without the lattice above it)
cases = [{"name": "board", "group": "drop"}, {"name": "gap", "group": "drop", **gap},
         {"name": "gap-bounded", "group": "drop", **{k: v for k, v in gap.items() if k != "top_row"}}]
cases += [{"name": f"point-{x:g},{y:g}", "group": "point", "start": [x, y]} for x, y in run["points"]]
cases += [{"name": f"spread-{s:g}", "group": "spread", "spread": s} for s in run["spreads"]]
cases += [{"name": f"speed-{v:g}", "group": "speed", "speed": v} for v in run["speeds"]]
for key, values in (("radius", run["radii"]), ("rows", run["rows"])):
    for value in values:
        cases.append({"name": f"board-{key}-{value:g}", "group": key, key: value})
        cases.append({"name": f"gap-{key}-{value:g}", "group": key, key: value, **gap})
cases += [{"name": f"board-width-{w:g}", "group": "width", "width": w} for w in run["widths"]]
cases += [{"name": f"board-width-{w:g}-specular-walls", "group": "width", "width": w, "wall_law": "specular"}
          for w in run["specular_walls"]]
with ensemble_options(snakemake.config.get("runtime"), snakemake.threads, name=snakemake.rule,
                      params={"board": snakemake.params.board, "run": run}) as how:
    ds = galton_evidence(cases, run["n_particles"], laws=("specular", "no-slip"), gamma=run["gamma"],
                         seed=run["seed"], max_time=run["time_factor"] * termination, termination_time=termination,
                         **board, **how)
    ds.attrs.update(time_factor=run["time_factor"], board_radius=board["radius"], board_rows=board["rows"])
    write_dataset(ds, snakemake.output.evidence, config={"galton": {"board": snakemake.params.board, "evidence": run}},
                  history=f"snakemake rule {snakemake.rule} (workflow/scripts/galton_evidence.py)")
