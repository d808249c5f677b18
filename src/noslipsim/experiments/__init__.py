"""The paper's experiments as functions that return self-describing datasets.

One module per subject of the figure pipeline: :mod:`.galton` (Figures 2, 3, S1),
:mod:`.orbits` (Figures 1, 4, 5, 6, 8, 16), :mod:`.stability` (Figures 7, 9, 14, 15) and
:mod:`.portraits` (Figures 10-13), :mod:`.readings` (Figure 15 under every reading),
:mod:`.conjectures` (Figures S4, S5), :mod:`.accessible` (Figure S6) and :mod:`.invariant`
(Figure S7): the paper's conjectures, counted, over :mod:`.orbit_sets` (several orbits as one dataset).
``EXPERIMENTS`` names those a config file can run (``noslipsim run``).
"""
from .accessible import accessible_pair_census, pair_counts
from .conjectures import census_counts, launch_angle_classes, wedge_periodic_census
from .galton import galton_cases, galton_distribution, galton_evidence, galton_orbits, galton_radius_sweep
from .invariant import invariant_regions, region_counts
from .orbit_sets import orbit_set, phase_portrait
from .orbits import (
    bounce_orbits,
    newwedge_orbits,
    pentagon_orbits,
    specular_noslip_orbits,
    sphere_bounce,
    two_disk_box_orbits,
)
from .portraits import (
    DISSIPATIVE_READINGS,
    HEX_READINGS,
    hex_force_portraits,
    hex_force_readings,
    hex_reading_scene,
    lemon_sinai_portraits,
    polygon_portraits,
    portrait_set,
    sinai_gamma_portraits,
    sinai_islands_sweep,
)
from .readings import readings_table, stability_readings
from .stability import perturbed_wedge_orbits, survival_pattern, wedge_launch_scan, wedge_periodic_orbits

EXPERIMENTS = {f.__name__: f for f in (
    galton_distribution, galton_radius_sweep, galton_orbits, galton_evidence,
    specular_noslip_orbits, pentagon_orbits, bounce_orbits, newwedge_orbits, two_disk_box_orbits, sphere_bounce,
    wedge_periodic_orbits, perturbed_wedge_orbits, wedge_launch_scan,
    sinai_gamma_portraits, sinai_islands_sweep, hex_force_portraits, hex_force_readings, polygon_portraits,
    lemon_sinai_portraits,
)}

__all__ = [
    "DISSIPATIVE_READINGS",
    "EXPERIMENTS",
    "HEX_READINGS",
    "accessible_pair_census",
    "bounce_orbits",
    "census_counts",
    "galton_cases",
    "galton_distribution",
    "galton_evidence",
    "galton_orbits",
    "galton_radius_sweep",
    "hex_force_portraits",
    "hex_force_readings",
    "hex_reading_scene",
    "invariant_regions",
    "launch_angle_classes",
    "lemon_sinai_portraits",
    "newwedge_orbits",
    "orbit_set",
    "pair_counts",
    "pentagon_orbits",
    "perturbed_wedge_orbits",
    "phase_portrait",
    "polygon_portraits",
    "portrait_set",
    "readings_table",
    "region_counts",
    "sinai_gamma_portraits",
    "sinai_islands_sweep",
    "specular_noslip_orbits",
    "sphere_bounce",
    "stability_readings",
    "survival_pattern",
    "two_disk_box_orbits",
    "wedge_launch_scan",
    "wedge_periodic_census",
    "wedge_periodic_orbits",
]
