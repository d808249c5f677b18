"""What orbits do: periodic orbits, linear stability, stability grids, Lyapunov exponents, portraits, attractors.

Above :mod:`noslipsim.simulate` and :mod:`noslipsim.ensemble`, below
:mod:`noslipsim.experiments`.  Coordinates and derivations: docs/analysis.md.
"""
from .attractors import attractor_census, attractor_labels, orbit_period, portrait_attractors
from .galton import arrival_curve, excess_kurtosis, tail_share
from .islands import (
    classify_regular,
    finite_time_lyapunov,
    head_on_onset_gamma,
    interior_starts,
    islands_onsets,
    onset_gamma,
    regular_share,
    threshold_sensitivity,
    twin_lyapunov,
    uniform_reduced_states,
)
from .lyapunov import lyapunov
from .monodromy import Monodromy, monodromy
from .orbits import bounce_orbit, two_disk_orbit, wedge_noforce_orbit, wedge_orbit
from .periodic import PeriodicOrbit, find_periodic_orbit
from .portraits import (
    birkhoff_coordinates,
    birkhoff_states,
    boundary_coordinate,
    reduced_portrait,
    reduced_states,
    velocity_portrait,
)
from .stability import agreement_share, elliptic_boundary, stability_grid, stability_grid_theta, two_disk_classes
from .tangent import CornerError

__all__ = [
    "CornerError", "Monodromy", "PeriodicOrbit", "agreement_share", "arrival_curve", "attractor_census",
    "attractor_labels", "birkhoff_coordinates", "birkhoff_states", "bounce_orbit", "boundary_coordinate",
    "classify_regular", "elliptic_boundary", "excess_kurtosis", "find_periodic_orbit", "finite_time_lyapunov",
    "head_on_onset_gamma", "interior_starts", "islands_onsets", "lyapunov", "monodromy", "onset_gamma",
    "orbit_period", "portrait_attractors", "reduced_portrait", "reduced_states", "regular_share", "stability_grid",
    "stability_grid_theta", "tail_share", "threshold_sensitivity", "twin_lyapunov", "two_disk_classes",
    "two_disk_orbit", "uniform_reduced_states", "velocity_portrait", "wedge_noforce_orbit", "wedge_orbit",
]
