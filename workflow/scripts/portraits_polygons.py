"""Dataset of Figure 11: velocity portraits of no-slip polygons (rectangle, hexagon, dodecagon, icosagon)."""
import sys

sys.stderr = open(snakemake.log[0], "w", buffering=1)

from noslipsim import write_dataset  # noqa: E402
from noslipsim.experiments import polygon_portraits  # noqa: E402

run = snakemake.params.run
ds = polygon_portraits(**run, scheduler=snakemake.config.get("runtime", {}).get("dask_scheduler"), num_workers=snakemake.threads, progress=True)
write_dataset(ds, snakemake.output.portraits, config={"portraits": {"polygons": run}},
              history=f"snakemake rule {snakemake.rule} (workflow/scripts/portraits_polygons.py)")
