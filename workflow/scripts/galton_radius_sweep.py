"""Dataset of Figure S1 (right): long runs for several peg radii, both laws."""
import sys

sys.stderr = open(snakemake.log[0], "w", buffering=1)

from noslipsim import write_dataset
from noslipsim.cluster import ensemble_options
from noslipsim.experiments import galton_radius_sweep

board, run = dict(snakemake.params.board), snakemake.params.run
termination = board.pop("max_time")
board.pop("radius")  # swept
with ensemble_options(snakemake.config.get("runtime"), snakemake.threads, name=snakemake.rule,
                      params={"board": snakemake.params.board, "run": run}) as how:
    ds = galton_radius_sweep(run["n_particles"], radii=run["radii"], gamma=run["gamma"], seed=run["seed"],
                             max_time=run["time_factor"] * termination, **board, **how)
    ds.attrs.update(termination_time=termination, time_factor=run["time_factor"],
                    board_radius=snakemake.params.board["radius"])
    write_dataset(ds, snakemake.output.sweep, config={"galton": {"board": snakemake.params.board, "radius_sweep": run}},
                  history=f"snakemake rule {snakemake.rule} (workflow/scripts/galton_radius_sweep.py)")
