"""Dataset of Figure S1 (left): arrival times up to time_factor x the termination time, several gammas."""
import sys

sys.stderr = open(snakemake.log[0], "w", buffering=1)

from noslipsim import write_dataset
from noslipsim.cluster import ensemble_options
from noslipsim.experiments import galton_distribution

board, run = dict(snakemake.params.board), snakemake.params.run
termination = board.pop("max_time")
with ensemble_options(snakemake.config.get("runtime"), snakemake.threads, name=snakemake.rule,
                      params={"board": snakemake.params.board, "run": run}) as how:
    ds = galton_distribution(run["n_particles"], gamma=run["gammas"],
                             seed=run["seed"], max_time=run["time_factor"] * termination, **board, **how)
    ds.attrs.update(termination_time=termination, time_factor=run["time_factor"])
    write_dataset(ds, snakemake.output.arrivals, config={"galton": {"board": snakemake.params.board, "arrivals": run}},
                  history=f"snakemake rule {snakemake.rule} (workflow/scripts/galton_arrivals.py)")
