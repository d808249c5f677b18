"""Dataset of Figure 10: the specular lemon (Birkhoff coordinates) and the no-slip Sinai torus (reduced portrait)."""
import sys

sys.stderr = open(snakemake.log[0], "w", buffering=1)

from noslipsim import write_dataset  # noqa: E402
from noslipsim.experiments import lemon_sinai_portraits  # noqa: E402

run = snakemake.params.run
ds = lemon_sinai_portraits(**run, scheduler=snakemake.config.get("runtime", {}).get("dask_scheduler"),
                           num_workers=snakemake.threads, progress=True)
write_dataset(ds, snakemake.output.portraits,
              config={"portraits": {"phaseportraits": run}},
              history=f"snakemake rule {snakemake.rule} (workflow/scripts/portraits_phaseportraits.py)")
