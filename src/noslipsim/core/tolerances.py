"""Named tolerances of the event engine (all relative, nondimensional).

Each is multiplied by a length scale (the scene's size or the current
position's magnitude, whichever is larger) before use, so the engine is
scale invariant.
"""

#: A hit is inside a segment or arc if its extent coordinate lies within
#: ``EXTENT_TOL * scale`` of the nominal range: ends are inclusive, so two
#: pieces sharing a vertex overlap there and a flight aimed at the vertex
#: cannot pass between them.
EXTENT_TOL = 1e-11

#: At a reflex junction or a free end the band beyond the end shrinks to
#: ``NONCONVEX_END_FACTOR * EXTENT_TOL`` (1e-14: rounding of a hit point), so
#: a flight passing just beside such an end is not hit, while one through the
#: exact vertex of a reflex corner still cannot slip between the two pieces.
#: A flight that starts within this band of such an end, on the element's
#: line or circle, has the element's root ``t = 0`` deflated
#: (:func:`events.starts_at_open_end`): no double hit at a reflex vertex.
NONCONVEX_END_FACTOR = 1e-3

#: After a collision, another element whose signed distance at the new
#: position lies in ``[-CONTACT_TOL, CONTACT_GAP] * scale`` and which the
#: velocity leaves through is hit immediately (the corner rule).  The band is
#: one-sided: a particle rounding has put on or past the other element's line
#: has no positive root left to find, while a real gap, however small, is an
#: ordinary root the solver finds exactly (a short flight, not a snap).
CONTACT_TOL = 1e-11
CONTACT_GAP = 1e-14

#: Safeguarded Newton iterations per root (bisection fallback halves the
#: bracket at every failed step, so 200 steps exhaust float64).
ROOT_MAX_ITER = 200

#: Consecutive zero-time corner collisions allowed before the orbit stops
#: with stop reason ``corner`` (a corner of angle pi/k needs k of them).
MAX_CORNER_BOUNCES = 64

#: Cells one flight may cross in a periodic scene before it counts as an
#: endless free flight (an escape along a corridor).
MAX_CELLS_PER_FLIGHT = 10_000_000

#: The corner pass runs only for hits within ``JUNCTION_GATE * scale`` of a
#: point where two elements meet (see :mod:`noslipsim.junctions` for why this
#: radius is safe).
JUNCTION_GATE = 1e-5
