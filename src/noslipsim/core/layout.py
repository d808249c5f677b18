"""How scenes are passed to kernels: an int kind per element and a row of floats.

``kinds[i]`` is one of the codes below and ``params[i, :]`` holds, by kind:

=========  ======================================================================
LINE       px, py, nx, ny                  (point; unit normal INTO the table)
SEGMENT    p0x, p0y, nx, ny, dx, dy, L, k  (start; inward unit normal; unit direction; length;
                                           k = -side / L) and p1x, p1y in SEG_P1X, SEG_P1Y
CIRCLE     cx, cy, r, sigma                (sigma = +1: table outside (scatterer), -1: inside)
ARC        cx, cy, r, sigma, theta0, span  (theta0 in [0, 2pi); CCW span in (0, 2pi])
=========  ======================================================================

Segments and arcs also carry, in columns ``END_START`` and ``END_END``, the
factor by which ``EXTENT_TOL`` extends each end.  Every element carries its
collision law in column ``ELEMENT_LAW`` (``SPECULAR`` or ``NOSLIP``, as a
float): the scene's law unless the element sets its own; a kernel reads it
only in a scene whose elements do not all share one law (``PER_ELEMENT``).
"""

LINE = 0
SEGMENT = 1
CIRCLE = 2
ARC = 3

N_PARAMS = 14

#: Lines and segments: 1.0 where a hit can lie far from the wall's ``p0`` compared with the table's smallest
#: feature, so its plain distance can cancel and the loop checks it (:func:`events.exact_line_hit`); 0.0 on a
#: compact table's walls, which skip the check (a wall at most ``LONG_WALL_RATIO`` times the smallest feature:
#: the plain form's error, ``eps`` times the wall's length, is a few ulps of that feature).  Set by
#: ``Scene.arrays``; 0.0 on circles and arcs, so the loop tests the flag alone.
LONG_WALL = 12
#: A segment longer than this many times the table's smallest feature (shortest segment,
#: smallest radius) is a long wall; a line always is (it has no end).
LONG_WALL_RATIO = 16.0

#: Segments: ``-side / L`` (side +1 left, -1 right), which turns ``(q - p0) x (p1 - p0)`` into the signed
#: distance, and ``p1`` itself, so a distance far along the segment is formed from its own end points
#: (:func:`geometry.line_value`).
SEG_CROSS_SCALE = 7
SEG_P1X = 10
SEG_P1Y = 11

#: Segments and arcs: the end-band factors of their start and end (1 at a convex junction,
#: ``NONCONVEX_END_FACTOR`` at a reflex junction or a free end; :mod:`noslipsim.junctions`).
END_START = 8
END_END = 9

#: Collision laws.
SPECULAR = 0
NOSLIP = 1
#: The kernels' ``law`` argument of a scene whose elements do not all share one law: each
#: collision takes the law of the element hit, ``params[e, ELEMENT_LAW]``.
PER_ELEMENT = 2
#: Every element: its own collision law (``SPECULAR`` or ``NOSLIP``, as a float).
ELEMENT_LAW = 13

#: Stop codes returned by the event loop (see ``STOP_REASONS``).
STOP_MAX_COLLISIONS = 0
STOP_MAX_TIME = 1
STOP_ESCAPE = 2
STOP_LEVEL = 3
STOP_CORNER = 4
STOP_GRAZING = 5
#: A thermostatted flight's circle search took ``thermo_events.MAX_STEPS`` conservative steps without
#: deciding whether the circle is hit: the orbit stops there rather than fly on past a possible hit.
STOP_SEARCH_LIMIT = 6
#: A magnetic orbit whose closed cyclotron path meets no element: it circles for ever (DynamicalBilliards.jl's
#: "pinned").
STOP_PINNED = 7
STOP_REASONS = ("max_collisions", "max_time", "escape", "stop_below", "corner", "grazing", "search_limit", "pinned")

#: What the event loop records per collision.
RECORD_NONE = 0      # nothing: the final state is returned anyway
RECORD_LOG = 1       # every collision, N_LOG columns
RECORD_PORTRAIT = 2  # collisions on masked elements, N_PORTRAIT columns

#: Columns of the collision log (positions unfolded; cell indices for lattices).
LOG_T, LOG_X, LOG_Y, LOG_VX, LOG_VY, LOG_W = 0, 1, 2, 3, 4, 5
LOG_VX_IN, LOG_VY_IN, LOG_W_IN, LOG_ELEMENT, LOG_S, LOG_CORNER = 6, 7, 8, 9, 10, 11
LOG_CELL_A1, LOG_CELL_A2 = 12, 13
N_LOG = 14

#: Columns of a phase-portrait record: element, arclength, and the post-collision
#: unit vector (w, v_t, v_n)/|(w, v_t, v_n)| in the frame (n outward, t = J n).
POR_ELEMENT, POR_S, POR_W, POR_VT, POR_VN = 0, 1, 2, 3, 4
N_PORTRAIT = 5
