"""Dataset of Figure S6: non-path-reversing 2-periodic orbits between pairs of boundary points, every pair counted."""
import sys

sys.stderr = open(snakemake.log[0], "w", buffering=1)

from noslipsim import write_dataset
from noslipsim.cluster import ensemble_options
from noslipsim.experiments import accessible_pair_census, pair_counts

common, run = snakemake.params.common, snakemake.params.run
with ensemble_options(snakemake.config.get("runtime"), snakemake.threads) as how:
    ds = accessible_pair_census(None, common["gamma"], gravity=common["gravity"], pairs=run["pairs"],
                                seed=run["seed"], scheduler=how["scheduler"], num_workers=how["num_workers"],
                                progress=how["progress"])
counts = pair_counts(ds)
print(counts.pairs.to_dataframe().unstack("outcome").to_string(), file=sys.stderr)
print(counts.orbits.to_pandas().to_string(), file=sys.stderr)
write_dataset(ds, snakemake.output.accessible, config={"stability": common, "conjectures": {"accessible": run}},
              history=f"snakemake rule {snakemake.rule} (workflow/scripts/conjecture_accessible.py)")
