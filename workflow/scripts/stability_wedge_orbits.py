"""Dataset of Figure 7: path-reversing 2-periodic wedge orbits (both openings) and two searched periodic orbits."""
import sys

sys.stderr = open(snakemake.log[0], "w", buffering=1)

from noslipsim import write_dataset
from noslipsim.experiments import wedge_periodic_orbits

common, run = snakemake.params.common, snakemake.params.run
ds = wedge_periodic_orbits(run["phi"], common["gamma"], gravity=common["gravity"], reversing=run["reversing"],
                           searches=run["searches"], periods=run["periods"], family_step=run["family_step"])
for i in range(ds.sizes["orbit"]):
    print(f"{ds.case.values[i]}: period {int(ds.period[i])}, residual {float(ds.residual[i]):.2e}, "
          f"{ds.linear_kind.values[i]}, reversal mismatch {float(ds.reversal_mismatch[i]):.3g}", file=sys.stderr)
write_dataset(ds, snakemake.output.orbits, config={"stability": {**common, "wedge": run}},
              history=f"snakemake rule {snakemake.rule} (workflow/scripts/stability_wedge_orbits.py)")
