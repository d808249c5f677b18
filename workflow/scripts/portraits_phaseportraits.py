"""Dataset of Figure 10: the specular lemon (Birkhoff coordinates) and the no-slip Sinai torus (reduced portrait)."""
import sys

sys.stderr = open(snakemake.log[0], "w", buffering=1)

from noslipsim import write_dataset  # noqa: E402
from noslipsim.experiments import lemon_sinai_portraits  # noqa: E402

run, threshold = snakemake.params.run, snakemake.params.threshold
ds = lemon_sinai_portraits(**run, threshold=threshold, scheduler=snakemake.params.scheduler,
                           num_workers=snakemake.threads, progress=True)
write_dataset(ds, snakemake.output.portraits,
              config={"portraits": {"phaseportraits": run, "regular_threshold": threshold}},
              history=f"snakemake rule {snakemake.rule} (workflow/scripts/portraits_phaseportraits.py)")
