"""How scenes are passed to kernels: an int kind per element and a row of floats.

``kinds[i]`` is one of the codes below and ``params[i, :]`` holds, by kind:

=========  ======================================================================
LINE       px, py, nx, ny                  (point; unit normal INTO the table)
SEGMENT    p0x, p0y, nx, ny, dx, dy, L     (start; inward unit normal; unit direction; length)
CIRCLE     cx, cy, r, sigma                (sigma = +1: table outside (scatterer), -1: inside)
ARC        cx, cy, r, sigma, theta0, span  (theta0 in [0, 2pi); CCW span in (0, 2pi])
=========  ======================================================================
"""

LINE = 0
SEGMENT = 1
CIRCLE = 2
ARC = 3

N_PARAMS = 8

#: Collision laws.
SPECULAR = 0
NOSLIP = 1

#: Stop codes returned by the event loop (see ``STOP_REASONS``).
STOP_MAX_COLLISIONS = 0
STOP_MAX_TIME = 1
STOP_ESCAPE = 2
STOP_LEVEL = 3
STOP_CORNER = 4
STOP_GRAZING = 5
STOP_REASONS = ("max_collisions", "max_time", "escape", "stop_below", "corner", "grazing")

#: Columns of the collision log written by the event loop.
LOG_T, LOG_X, LOG_Y, LOG_VX, LOG_VY, LOG_W = 0, 1, 2, 3, 4, 5
LOG_VX_IN, LOG_VY_IN, LOG_W_IN, LOG_ELEMENT, LOG_S, LOG_CORNER = 6, 7, 8, 9, 10, 11
N_LOG = 12
