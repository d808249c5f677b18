"""What orbits do: periodic orbits, linear stability, stability grids, Lyapunov exponents, portraits.

Above :mod:`noslipsim.simulate` and :mod:`noslipsim.ensemble`, below
:mod:`noslipsim.experiments`.  Coordinates and derivations: docs/analysis.md.
"""
# -- theorem orbits, monodromy, periodic-orbit finder, Lyapunov exponents (one block per owner) --
from .lyapunov import lyapunov
from .monodromy import Monodromy, monodromy
from .orbits import bounce_orbit, two_disk_orbit, wedge_noforce_orbit, wedge_orbit
from .periodic import PeriodicOrbit, find_periodic_orbit
from .tangent import CornerError

# the first block starts __all__; each later block extends it with +=
__all__ = ["two_disk_orbit", "wedge_orbit", "wedge_noforce_orbit", "bounce_orbit",
           "monodromy", "Monodromy", "CornerError", "find_periodic_orbit", "PeriodicOrbit", "lyapunov"]

# -- stability grids, boundary portraits, Galton arrival curve --
from .galton import arrival_curve
from .portraits import (
    birkhoff_coordinates, birkhoff_states, boundary_coordinate, reduced_portrait, reduced_states, velocity_portrait,
)
from .stability import agreement_share, stability_grid, stability_grid_theta

__all__ += ["arrival_curve", "boundary_coordinate", "birkhoff_coordinates", "velocity_portrait",
            "reduced_portrait", "birkhoff_states", "reduced_states", "stability_grid", "stability_grid_theta",
            "agreement_share"]

# -- regular share of a phase space and the onset of islands --
from .islands import (
    classify_regular, finite_time_lyapunov, head_on_onset_gamma, interior_starts, islands_onsets, onset_gamma,
    regular_share, uniform_reduced_states,
)

__all__ += ["uniform_reduced_states", "interior_starts", "finite_time_lyapunov", "regular_share", "onset_gamma",
            "head_on_onset_gamma", "classify_regular", "islands_onsets"]
