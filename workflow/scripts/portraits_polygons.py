"""Dataset of Figure 11: velocity portraits of no-slip polygons (rectangle, hexagon, dodecagon, icosagon)."""
import sys

sys.stderr = open(snakemake.log[0], "w", buffering=1)

from noslipsim import write_dataset
from noslipsim.cluster import ensemble_options
from noslipsim.experiments import polygon_portraits

run = snakemake.params.run
with ensemble_options(snakemake.config.get("runtime"), snakemake.threads) as how:
    ds = polygon_portraits(**run, **how)
write_dataset(ds, snakemake.output.portraits, config={"portraits": {"polygons": run}},
              history=f"snakemake rule {snakemake.rule} (workflow/scripts/portraits_polygons.py)")
