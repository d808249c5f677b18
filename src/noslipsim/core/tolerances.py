"""Named tolerances of the event engine (all relative, nondimensional; docs/algorithm.md, "Tolerances").

Each is multiplied by a length scale (the scene's size or the current position's magnitude, whichever
is larger) before use, so the engine is scale invariant.
"""

#: A hit is inside a segment or arc if its extent coordinate lies within ``EXTENT_TOL * scale`` of the
#: nominal range: ends are inclusive, so a flight aimed at a shared vertex cannot pass between the pieces.
EXTENT_TOL = 1e-11

#: At a reflex junction or a free end the band beyond the end shrinks to ``NONCONVEX_END_FACTOR * EXTENT_TOL``
#: (1e-14: rounding of a hit point): a flight passing just beside such an end is not hit, one through the exact
#: vertex of a reflex corner still cannot slip between the pieces.  A flight starting within this band of such
#: an end, on the element's line or circle, has the element's root ``t = 0`` deflated
#: (:func:`events.starts_at_open_end`): no double hit at a reflex vertex.
NONCONVEX_END_FACTOR = 1e-3

#: After a collision, another element whose signed distance at the new position lies in
#: ``[-CONTACT_TOL, CONTACT_GAP] * scale`` and which the velocity leaves through is hit at once (the corner
#: rule).  One-sided: a particle rounding has put on or past the other element's line has no positive root
#: left to find, while a real gap, however small, is an ordinary root the solver finds (a short flight, not a snap).
CONTACT_TOL = 1e-11
CONTACT_GAP = 1e-14

#: Safeguarded Newton iterations per root (the bisection fallback halves the bracket at every failed step,
#: so 200 steps exhaust float64).
ROOT_MAX_ITER = 200

#: Consecutive zero-time corner collisions before the orbit stops with ``corner`` (angle pi/k needs k).
MAX_CORNER_BOUNCES = 64

#: Cells one flight may cross in a periodic scene before it counts as an endless corridor flight (``escape``).
MAX_CELLS_PER_FLIGHT = 10_000_000

#: The corner pass runs only for hits within ``JUNCTION_GATE * scale`` of a point where two elements meet
#: (:mod:`noslipsim.junctions`: why this radius is safe).
JUNCTION_GATE = 1e-5
