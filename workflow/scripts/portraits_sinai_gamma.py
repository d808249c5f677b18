"""Dataset of Figure 12 (portraits): the no-slip Sinai torus for several gammas, each orbit with its exponent."""
import sys

sys.stderr = open(snakemake.log[0], "w", buffering=1)

from noslipsim import write_dataset
from noslipsim.cluster import ensemble_options
from noslipsim.experiments import sinai_gamma_portraits

run = snakemake.params.run
with ensemble_options(snakemake.config.get("runtime"), snakemake.threads) as how:
    ds = sinai_gamma_portraits(**run, **how)
write_dataset(ds, snakemake.output.portraits,
              config={"portraits": {"sinai_gamma": run}},
              history=f"snakemake rule {snakemake.rule} (workflow/scripts/portraits_sinai_gamma.py)")
