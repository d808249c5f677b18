"""High-precision reference orbits: the slow, obviously-correct twin of :func:`noslipsim.simulate`.

The same event-driven algorithm as the compiled engine, written again from
the definitions in mpmath at ``dps`` significant digits, on any
:class:`~noslipsim.scenes.Scene` (lines, segments, circles, arcs; with or
without force; no-slip or specular; plain or periodic).  It shares no
numerical code with :mod:`noslipsim.core`; the float64 engine is judged
against it.  The engine's algorithm is described in ``docs/algorithm.md``.

Algorithm (one collision)
-------------------------
1. *Crossing polynomials.*  Along the flight ``q(t) = q + v t + a t^2/2`` each
   element has a polynomial that is positive on the table side:
   ``(q(t) - p) . n_in`` for lines and segments (degree <= 2) and
   ``sigma (|q(t) - c|^2 - r^2)`` for circles and arcs (degree <= 4,
   ``sigma = +1`` when the table lies outside the circle).  Exact zero leading
   coefficients are dropped; for the element just hit the exact root ``t = 0``
   is removed by dividing by ``t``, and so it is for the other piece of a
   reflex junction whose vertex was just hit (the start on its line within
   ``tol``, the junction reflex as in step 6): that root is no collision (the
   particle, having entered the union of the two table sides, is inside), and
   at ``dps`` digits it rounds to either side of zero, so kept it could be a
   hit ``10^-dps`` later and the particle would reverse (``docs/algorithm.md``,
   step 4; the float64 engine has the same rule).
2. *All real roots.*  Degree 1 and 2 in closed form (the cancellation-free
   quadratic formula), degree 3 and 4 by :func:`mpmath.polyroots`
   (Durand-Kerner on all complex roots, iterated at three times the working
   precision); the roots it returns as real (imaginary part below the working
   epsilon) are the real roots.  A polynomial whose coefficients show no sign
   change has no positive root (Descartes' rule) and is skipped.
3. *Exit roots.*  A root ``t > 0`` is a hit if the polynomial decreases there
   (the orbit leaves the table: ``p'(t) < 0`` beyond a noise floor
   ``10^(-2 dps / 5)`` relative to the size of the terms of ``p'``, so an exact
   tangency is not a hit) and the point lies in the element's extent
   (segment: ``0 <= u <= L``; arc: CCW angle past ``theta0`` within the span),
   ends inclusive within ``tol``.
4. *Earliest hit.*  The smallest hit time over all elements (on a lattice:
   over the element copies met along the cell walk below); times equal to a
   relative ``10^(-dps/2)`` go to the element met first (lower index, then
   earlier cell).
5. *Relocate and resolve.*  The particle is placed on the element
   (orthogonal projection onto a line, radial onto a circle) and the collision
   law is applied in the frame of ``docs/algorithm.md`` (step 3): ``n`` the
   outward unit normal, ``t = J n = (-n_y, n_x)``,

   .. math::

       w^+ = -c w - s v_t, \\quad v_t^+ = -s w + c v_t, \\quad v_n^+ = -v_n,
       \\qquad c = \\frac{1-\\gamma^2}{1+\\gamma^2}, \\; s = \\frac{2\\gamma}{1+\\gamma^2}

   (no-slip); specular keeps ``v_t`` and ``w`` and reverses ``v_n``.  The law
   is the element's own where it sets one (a mixed table), else the scene's.
6. *Corner rule* (as documented in :mod:`noslipsim.core.loop`): every other
   element touched at the hit point (signed distance within ``tol``, in its
   extent within ``tol``: ends inclusive) whose supporting line or circle the
   new velocity leaves (distance rate ``< 0``, or ``= 0`` with a negative
   second coefficient) is hit at once, in index order, as a separate
   collision with ``corner = 1``, except across a reflex junction (one
   piece's end leads off to the other's wall side: the table is locally the
   union of their table sides, and the particle, having just entered one,
   is inside; ``docs/algorithm.md``, step 4); more than
   ``MAX_CORNER_BOUNCES`` in a row stop the orbit (``corner``).  If the element hit last would be left
   through at once the orbit stops (``grazing``).  The kernel's junction gate
   (corner pass only near points where two elements meet) is a shortcut that
   cannot change this rule's outcome, so it has no twin here.

``tol = 10^(-floor(dps/2)) * max(scene scale, |x|, |y|)`` is the only length
tolerance (on a lattice ``x, y`` are measured from the centre of the
particle's cell).  The stop rules follow
:data:`noslipsim.core.layout.STOP_REASONS`: crossing ``stop_below`` downwards
(before or at the next hit), escape (no hit ahead: the state of the last
collision is final, whatever the time limit), the time limit (the state
advanced to it) and the collision budget.

Periodic scenes
---------------
A scene with a ``lattice`` repeats its elements at every ``n1 a1 + n2 a2``.
Positions are kept unfolded (absolute) at full precision; cell ``(n1, n2)`` is
the closed parallelogram of lattice coordinates ``|alpha - n1|, |beta - n2| <= 1/2``
(``q = alpha a1 + beta a2``, by Cramer's rule), and a point's cell is its
nearest lattice site (``nint``, ties to even), as :func:`noslipsim.simulate`
reports ``cell_a1, cell_a2``.  A flight walks the cells it crosses:

* the exit time of a cell is the first time ``>= t_in`` (the entry time) at
  which a lattice coordinate, a polynomial of degree <= 2 in ``t``, crosses a
  face of its strip outwards (which root is the exit follows from the shape of
  the quadratic, never from the sign of a rounded slope, so the entry root is
  never an exit and a tangency is no crossing); a face reached by both
  coordinates at the same time (a lattice corner) steps both indices;
* in each cell the element copies that reach it
  (:func:`noslipsim._engine.lattice.reaching_copies`, a conservative box test) are
  solved on the whole flight from the last collision (step 3; the first hit of
  a copy is remembered for the rest of the flight);
* the walk ends when the earliest hit found so far comes no later than the
  exit time of the current cell: a copy not yet met lies in a later cell, which
  the flight enters only after that exit.

A flight whose path is a straight line along a lattice vector
``P = p a1 + q a2`` (no force and ``v`` parallel to ``P``, or ``v`` parallel to
the force and the force to ``P``; tested in exact rational arithmetic,
``|p|, |q| <= PERIOD_MAX``) repeats its geometry after every ``P``: once it has
covered ``|P|`` (beyond its turning point, under a force) without meeting
anything it never will.  Such an endless flight, or a walk past
``MAX_CELLS_PER_FLIGHT`` cells, ends the orbit as the engine's does: escape,
unless ``stop_below`` or ``max_time`` comes first; an endless flight's time
limit counts as reached first when the engine's walk would reach it within
``MAX_CELLS_PER_FLIGHT`` cells (counted from the face crossings up to the limit).
The copy hit is reported by its element index, with ``s`` measured on that copy.

Magnetic flights
----------------
A scene with ``magnetic = W != 0`` flies cyclotron arcs (:mod:`.magnetic`):
every crossing function is ``g0 + a sin(W t)/W + b (1 - cos(W t))/W``, whose
roots solve ``A cos + B sin = C`` in closed form; the element just hit has its
root ``t = 0`` removed analytically.  The path is closed, so the search covers
one period (on a lattice: the cells of one turn, walked face by face); an
orbit whose circle meets no element stops with ``pinned``.  The corner and
grazing rules read the local expansion ``a = W J v``.

Inputs are taken at the exact values of their Python floats (``mpf(float)``
is exact).  Element geometry is read from the element objects: segments from
their end points ``p0, p1`` (so adjacent polygon edges share their vertex
exactly), lines from ``point`` and the stored float unit ``normal`` (taken as
an exact direction and renormalised), circles and arcs from ``center``,
``radius``, ``theta0``, ``theta1``; lattice vectors from the scene's floats.  An
arc ends at its float angles, so where it meets a segment (a stadium's
``theta0 = -pi/2`` rounded) the two touch only to about ``1e-16``; orbits aimed
that close to such a junction are beyond what either engine resolves.
"""
from __future__ import annotations

# One module per job: elements (the elements in mpmath, steps 1, 3, 5, 6),
# roots (steps 2-3), walk (the periodic-scene cell walk), orbit (the result)
# and engine (the event loop and the entry points below).
from .engine import MIN_DPS, RESUME_TOL, resume_reference, simulate_reference
from .orbit import FINAL, RECORDED, ReferenceOrbit
from .walk import PERIOD_MAX

__all__ = [
    "FINAL", "MIN_DPS", "PERIOD_MAX", "RECORDED", "RESUME_TOL", "ReferenceOrbit", "resume_reference",
    "simulate_reference",
]
