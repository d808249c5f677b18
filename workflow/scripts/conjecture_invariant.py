"""Dataset of Figure S7: rings of starts around the two-disk path-reversing orbits, free fall and thermostat."""
import sys

sys.stderr = open(snakemake.log[0], "w", buffering=1)

from noslipsim import write_dataset
from noslipsim.cluster import ensemble_options
from noslipsim.experiments import invariant_regions, region_counts

common, run = snakemake.params.common, snakemake.params.run
with ensemble_options(snakemake.config.get("runtime"), snakemake.threads) as how:
    ds = invariant_regions(run["forces"], run["radius"], run["phi"], common["gamma"], rings=run["rings"],
                           starts=run["starts"], ring_step=run["ring_step"], max_collisions=run["max_collisions"],
                           tail=run["tail"], scheduler=how["scheduler"], num_workers=how["num_workers"])
print(region_counts(ds).starts.to_dataframe().unstack("outcome").to_string(), file=sys.stderr)
print(ds.region_radius.to_dataframe().dropna().to_string(), file=sys.stderr)
write_dataset(ds, snakemake.output.invariant, config={"stability": common, "conjectures": {"invariant": run}},
              history=f"snakemake rule {snakemake.rule} (workflow/scripts/conjecture_invariant.py)")
