"""Dataset of Figure 3 (right): the terminal distribution against the number of rows, both laws.

Each board runs to T (rows up to the board's) or T (rows / board rows)^time_exponent (more rows): the
specular descent reaches the depth d at a time growing like d^(3/2) (Chernov & Dolgopyat 2009), so a
deeper board run to T alone keeps only its fastest particles.
"""
import sys

sys.stderr = open(snakemake.log[0], "w", buffering=1)

from noslipsim import write_dataset
from noslipsim.cluster import ensemble_options
from noslipsim.experiments import galton_evidence

board, run = dict(snakemake.params.board), snakemake.params.run
reference = board.pop("rows")  # swept
cases = [{"name": f"rows-{r}", "group": "rows", "rows": r,
          "max_time": board["max_time"] * max(1.0, r / reference) ** run["time_exponent"]} for r in run["rows"]]
with ensemble_options(snakemake.config.get("runtime"), snakemake.threads, name=snakemake.rule,
                      params={"board": snakemake.params.board, "run": run}) as how:
    ds = galton_evidence(cases, run["n_particles"], laws=("specular", "no-slip"), gamma=run["gamma"],
                         seed=run["seed"], **board, **how)
    ds.attrs["title"] = "Galton board: terminal distribution against the number of rows"
    write_dataset(ds, snakemake.output.rows, config={"galton": {"board": snakemake.params.board, "rows_sweep": run}},
                  history=f"snakemake rule {snakemake.rule} (workflow/scripts/galton_rows.py)")
