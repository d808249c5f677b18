"""Dataset of Figure S5: periodic orbits of no-slip wedges under a force, from seeded random starts."""
import sys

sys.stderr = open(snakemake.log[0], "w", buffering=1)

from noslipsim import write_dataset
from noslipsim.cluster import ensemble_options
from noslipsim.experiments import census_counts, wedge_periodic_census

common, run = snakemake.params.common, snakemake.params.run
with ensemble_options(snakemake.config.get("runtime"), snakemake.threads) as how:
    ds = wedge_periodic_census(run["phis"], run["force_angles"], run["periods"], common["gamma"],
                               gravity=common["gravity"], starts=run["starts"], seed=run["seed"], tol=run["tol"],
                               max_iter=run["max_iter"], scheduler=how["scheduler"], num_workers=how["num_workers"],
                               progress=how["progress"])
counts = census_counts(ds)
print(counts.searches.to_pandas().to_string(), file=sys.stderr)
print(counts[["distinct", "isolated", "family"]].to_dataframe().to_string(), file=sys.stderr)
write_dataset(ds, snakemake.output.census, config={"stability": common, "conjectures": {"census": run}},
              history=f"snakemake rule {snakemake.rule} (workflow/scripts/conjecture_census.py)")
