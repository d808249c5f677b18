"""Dataset of Figure 2: Galton-board orbits from one start, one per gamma."""
import sys

sys.stderr = open(snakemake.log[0], "w", buffering=1)

from noslipsim import write_dataset
from noslipsim.experiments import galton_orbits

board, orbits = dict(snakemake.params.board), snakemake.params.orbits
board.pop("max_time")  # the orbits have their own time limit
board.pop("spread")  # one start and velocity, shared by the panels
board.pop("speed")
ds = galton_orbits(orbits["gammas"], velocity=orbits["velocity"], max_time=orbits["max_time"],
                   max_collisions=orbits["max_collisions"], **board)
write_dataset(ds, snakemake.output.orbits, config={"galton": {"board": snakemake.params.board, "orbits": orbits}},
              history=f"snakemake rule {snakemake.rule} (workflow/scripts/galton_orbits.py)")
