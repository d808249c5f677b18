"""What orbits do: periodic orbits, linear stability, stability grids, Lyapunov exponents, portraits.

Above :mod:`noslipsim.simulate` and :mod:`noslipsim.ensemble`, below
:mod:`noslipsim.experiments`.  Coordinates and derivations: docs/analysis.md.
"""
# -- theorem orbits, monodromy, periodic-orbit finder, Lyapunov exponents (one block per owner) --

# -- stability grids, boundary portraits, Galton arrival curve --

__all__ = []
