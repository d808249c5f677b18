"""Dataset of Figure 3: terminal positions and arrival times of many particles per law."""
import sys

sys.stderr = open(snakemake.log[0], "w", buffering=1)

from noslipsim import write_dataset
from noslipsim.cluster import ensemble_options
from noslipsim.experiments import galton_distribution

board, run = snakemake.params.board, snakemake.params.run
with ensemble_options(snakemake.config.get("runtime"), snakemake.threads, name=snakemake.rule,
                      params={"board": board, "run": run}) as how:
    ds = galton_distribution(run["n_particles"], gamma=run["gamma"], seed=run["seed"], **board, **how)
    write_dataset(ds, snakemake.output.distribution, config={"galton": {"board": board, "distribution": run}},
                  history=f"snakemake rule {snakemake.rule} (workflow/scripts/galton_distribution.py)")
