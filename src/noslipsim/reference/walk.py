"""The periodic-scene cell walk of :mod:`noslipsim.reference` (its section *Periodic scenes*).

:class:`_Table` holds the scene's boundary as element copies per cell
(lattice coordinates, cells, length scale, the period of straight flights);
:func:`_face_exit`, :func:`_strip_exit` and :func:`_faces_crossed` follow one
lattice coordinate of a flight across the faces of its strips; :func:`_walk_cells`
walks a flight cell by cell until the earliest hit is known (step 4 on a
lattice), or gives up on an endless flight.

The walk reads ``MAX_CELLS_PER_FLIGHT``, ``_strip_exit`` and ``_Table`` from this
module's namespace at each call, so a test may lower the cap or mutate the walk
by patching them here.
"""
from __future__ import annotations

import itertools
from fractions import Fraction

from .._engine.lattice import reaching_copies
from ..core.tolerances import MAX_CELLS_PER_FLIGHT
from .elements import _Copy, _mp_elements
from .magnetic import MagneticPath, face_exit
from .roots import _flight
from .thermostat import line_first_exit

#: Largest ``|p|, |q|`` of a lattice vector ``P = p a1 + q a2`` along which a straight
#: flight is recognised as periodic (a period then walks about ``|p| + |q|`` cells).
PERIOD_MAX = 1000


def _exact(value):
    """The exact rational value of an mpf."""
    man, exp = value.man_exp
    return Fraction(man) * Fraction(2) ** exp


class _Table:
    """The scene's boundary in mpmath: one copy per element, or on a lattice the copies per cell.

    ``a = (a1x, a1y, a2x, a2y)`` are the lattice vectors; a point's lattice
    coordinates ``(alpha, beta)`` solve ``q = alpha a1 + beta a2`` (Cramer's
    rule), and its cell is the nearest lattice site.
    """

    def __init__(self, ctx, scene):
        self.ctx = ctx
        self.elements = _mp_elements(ctx, scene)
        self.periodic = scene.lattice is not None
        self.scale = ctx.mpf(scene.scale)
        self._copies = {}
        # a bounded lattice (Scene.top): copies whose centre lies above the top do not exist (circles only)
        self.top = None if getattr(scene, "top", None) is None else ctx.mpf(scene.top)
        self.centre_y = [ctx.mpf(e.center[1]) if self.top is not None else None for e in scene.elements]
        if self.periodic:
            lat = scene.lattice
            raw = (lat["a1"][0], lat["a1"][1], lat["a2"][0], lat["a2"][1])
            self.a = tuple(ctx.mpf(v) for v in raw)
            self.exact_a = tuple(Fraction(v) for v in raw)
            a1x, a1y, a2x, a2y = self.a
            self.det = a1x * a2y - a2x * a1y
            self.reach = [tuple(int(v) for v in row) for row in reaching_copies(scene.elements, lat)]
        else:
            self.reach = [(i, 0, 0) for i in range(len(self.elements))]

    def coordinates(self, x, y):
        """``(alpha, beta)`` with ``(x, y) = alpha a1 + beta a2`` (a point, a velocity or a force)."""
        a1x, a1y, a2x, a2y = self.a
        return (x * a2y - y * a2x) / self.det, (a1x * y - a1y * x) / self.det

    def shift(self, n1, n2):
        """``n1 a1 + n2 a2``."""
        a1x, a1y, a2x, a2y = self.a
        return n1 * a1x + n2 * a2x, n1 * a1y + n2 * a2y

    def cell(self, x, y):
        """Indices of the cell holding ``(x, y)``: the nearest lattice site ((0, 0) for plain scenes)."""
        if not self.periodic:
            return 0, 0
        alpha, beta = self.coordinates(x, y)
        return int(self.ctx.nint(alpha)), int(self.ctx.nint(beta))

    def length(self, x, y):
        """The length scale of tolerances at ``(x, y)``: ``max(scale, |x|, |y|)`` from the cell's centre."""
        if self.periodic:
            ox, oy = self.shift(*self.cell(x, y))
            x, y = x - ox, y - oy
        return max(self.scale, abs(x), abs(y))

    def copy(self, e, o1, o2):
        """Element ``e`` moved by ``o1 a1 + o2 a2`` (made once, then shared: its key marks it met)."""
        key = (e, o1, o2)
        c = self._copies.get(key)
        if c is None:
            sx, sy = self.shift(o1, o2) if self.periodic else (self.ctx.zero, self.ctx.zero)
            c = self._copies[key] = _Copy(self.elements[e], o1, o2, sx, sy)
        return c

    def copies_at(self, d1, d2):
        """The element copies that reach cell ``(d1, d2)``, in element order (plain scenes: every element).

        On a bounded lattice, none whose centre lies above the top."""
        copies = [self.copy(e, o1 + d1, o2 + d2) for e, o1, o2 in self.reach]
        if self.top is None:
            return copies
        return [c for (e, _, _), c in zip(self.reach, copies) if self.centre_y[e] + c.sy <= self.top]

    def period(self, vx, vy, ax, ay):
        """The length ``|P|`` of the lattice vector along which the flight's path is a straight line, or None.

        Exact: the path is straight when ``a = 0`` or ``v x a = 0``, and a
        lattice vector ``p a1 + q a2`` is parallel to its direction ``u`` when
        ``p (a1 x u) + q (a2 x u) = 0``, solved in rationals.
        """
        if not self.periodic:
            return None
        v = (_exact(vx), _exact(vy))
        a = (_exact(ax), _exact(ay))
        if a != (0, 0):
            if v[0] * a[1] - v[1] * a[0] != 0:
                return None
            u = a
        else:
            u = v
        a1x, a1y, a2x, a2y = self.exact_a
        ca = a1x * u[1] - a1y * u[0]
        cb = a2x * u[1] - a2y * u[0]
        if ca == 0:
            p, q = 1, 0
        elif cb == 0:
            p, q = 0, 1
        else:
            ratio = -cb / ca  # = p / q in lowest terms
            p, q = ratio.numerator, ratio.denominator
        if max(abs(p), abs(q)) > PERIOD_MAX:
            return None
        return self.ctx.hypot(*self.shift(p, q))


def _face_exit(ctx, coeffs, face, outward, t_in):
    """When a flight inside the strip at ``t_in`` leaves it through ``face`` (``inf``: never).

    ``alpha(t)`` has ascending ``coeffs`` (degree <= 2); ``outward = +1`` for the
    upper face, ``-1`` for the lower one.  With ``g = outward (alpha - face)``,
    the flight is on the strip's side of the face where ``g <= 0``: on an
    interval ``[lo, hi]`` between the roots of ``g`` (``g2 > 0``: it leaves at
    ``hi``), before ``lo`` or after ``hi`` (``g2 < 0``: it leaves at ``lo`` if it is
    in the first part, never if it entered at ``hi``), or before the root of a
    linear ``g`` that increases.  The walk asks only from inside, so which
    root is the exit follows from the shape of ``g``, never from the sign of a
    rounded slope (the root the flight entered through is never taken for an
    exit, a tangency is no crossing), and an exit computed a rounding before
    ``t_in`` is ``t_in``.
    """
    g0, g1, g2 = outward * (coeffs[0] - face), outward * coeffs[1], outward * coeffs[2]
    if g2 == 0:
        return max(-g0 / g1, t_in) if g1 > 0 else ctx.inf
    disc = g1 * g1 - 4 * g2 * g0
    if g2 < 0 and disc <= 0:  # g <= 0 at all times: never leaves through this face
        return ctx.inf
    if disc < 0:  # g > 0 at all times: the flight is not on this side (a rounding at a face): leave at once
        return t_in
    if disc == 0:  # inside only where g touches 0
        return max(-g1 / (2 * g2), t_in)
    qq = -(g1 + ctx.sqrt(disc)) / 2 if g1 >= 0 else -(g1 - ctx.sqrt(disc)) / 2
    lo, hi = sorted((qq / g2, g0 / qq))  # the roots, without cancellation
    if g2 > 0:
        return max(hi, t_in)
    return max(lo, t_in) if t_in < (lo + hi) / 2 else ctx.inf


def _strip_exit(ctx, coeffs, d, t_in):
    """Exit ``(t, step)`` of ``alpha(t)`` from the strip ``[d - 1/2, d + 1/2]`` after ``t_in``.

    ``step = +1`` through the upper face, ``-1`` through the lower one, 0 if it never leaves.
    """
    half = ctx.mpf(0.5)
    t_up = _face_exit(ctx, coeffs, d + half, 1, t_in)
    t_dn = _face_exit(ctx, coeffs, d - half, -1, t_in)
    if t_up <= t_dn and t_up < ctx.inf:
        return t_up, 1
    if t_dn < ctx.inf:
        return t_dn, -1
    return ctx.inf, 0


def _faces_crossed(ctx, coeffs, t_end):
    """Number of half-integers ``alpha(t)`` (degree <= 2) passes over ``(0, t_end)``."""
    c0, c1, c2 = coeffs
    cuts = [ctx.zero, t_end]
    if c2 != 0:
        t_turn = -c1 / (2 * c2)
        if 0 < t_turn < t_end:
            cuts.insert(1, t_turn)
    total = 0
    half = ctx.mpf(0.5)
    for t0, t1 in itertools.pairwise(cuts):
        u0 = c0 + t0 * (c1 + c2 * t0)
        u1 = c0 + t1 * (c1 + c2 * t1)
        total += abs(int(ctx.floor(u1 + half)) - int(ctx.floor(u0 + half)))
    return total


# ---------------------------------------------------------------------------- the walk
class _Strip:
    """One lattice coordinate of a flight (ascending coefficients in ``t``) and the strip it is in.

    ``exit, step``: when and which way it leaves the strip ``[d - 1/2, d + 1/2]`` (:func:`_strip_exit`).
    """

    __slots__ = ("coeffs", "ctx", "d", "exit", "step")

    def __init__(self, ctx, coeffs, d):
        self.ctx, self.coeffs, self.d = ctx, coeffs, d
        self.exit, self.step = _strip_exit(ctx, coeffs, d, ctx.zero)

    def cross(self, t_out):
        """Step into the next strip if the coordinate leaves its strip at ``t_out``, the current cell's exit."""
        if self.exit == t_out:  # both coordinates at once: a lattice corner steps both indices
            self.d += self.step
            self.exit, self.step = _strip_exit(self.ctx, self.coeffs, self.d, t_out)

    def faces_crossed(self, t_end):
        """Number of strip faces the coordinate passes over ``(0, t_end)``."""
        return _faces_crossed(self.ctx, self.coeffs, t_end)


class _Period:
    """A straight flight along a lattice vector of length ``length``: has it covered a period in vain?"""

    __slots__ = ("ctx", "flight", "length", "t_turn", "x_turn", "y_turn")

    def __init__(self, ctx, flight, length):
        x, y, vx, vy, ax, ay = flight
        self.ctx, self.flight, self.length = ctx, flight, length
        # the path repeats after `length` only where it is monotone: after its turning point
        acc = ctx.hypot(ax, ay)
        self.t_turn = ctx.zero if acc == 0 else max(ctx.zero, -(vx * ax + vy * ay) / (acc * acc))
        self.x_turn, self.y_turn = _flight(x, y, vx, vy, ax, ay, self.t_turn)

    def covered(self, t_out, tol):
        """The flight, past its turning point at ``t_out``, lies more than a period from it."""
        if not t_out > self.t_turn:
            return False
        xo, yo = _flight(*self.flight, t_out)
        return self.ctx.hypot(xo - self.x_turn, yo - self.y_turn) > self.length + tol


class _ThermoStrip(_Strip):
    """A lattice coordinate along a thermostatted path: a line functional ``alpha0 + grad . (q(t) - q(0))``.

    Its exits are found by the certified search of :mod:`.thermostat`; on or
    past a face at ``t_in`` and moving out, it leaves at once.  The polynomial
    ``coeffs`` (the local expansion) serve only :meth:`faces_crossed`, which the
    walk asks of straight flights alone, where they are exact.
    """

    __slots__ = ("alpha0", "grad", "path")

    def __init__(self, ctx, coeffs, d, path, grad):
        self.path, self.grad, self.alpha0 = path, grad, coeffs[0]
        self.ctx, self.coeffs, self.d = ctx, coeffs, d
        self.exit, self.step = self._exit(ctx.zero)

    def _face(self, f0, sign, t_in):
        ctx, path = self.ctx, self.path
        nx, ny = sign * self.grad[0], sign * self.grad[1]
        px, py = path.position(t_in)
        vx, vy = path.velocity(t_in)
        ft = f0 + nx * (px - path.x) + ny * (py - path.y)
        if ft <= 0 and nx * vx + ny * vy < 0:
            return t_in
        t = line_first_exit(ctx, path, nx, ny, f0, t_in)
        return ctx.inf if t is None else t

    def _exit(self, t_in):
        half = self.ctx.mpf(0.5)
        t_up = self._face(self.d + half - self.alpha0, -1, t_in)
        t_dn = self._face(self.alpha0 - (self.d - half), 1, t_in)
        if t_up <= t_dn and t_up < self.ctx.inf:
            return t_up, 1
        if t_dn < self.ctx.inf:
            return t_dn, -1
        return self.ctx.inf, 0

    def cross(self, t_out):
        if self.exit == t_out:
            self.d += self.step
            self.exit, self.step = self._exit(t_out)


class _MagneticStrip:
    """A lattice coordinate along a cyclotron path: ``alpha0 + grad . (x(t) - x_0)``, in the strip ``d``.

    Its exits are the closed-form face crossings of :mod:`.magnetic` within
    the first period (``inf`` beyond it): a path is closed, so a walk that has
    not met an element by then never will, and the cells it can reach are
    those of one turn.
    """

    __slots__ = ("alpha0", "ctx", "d", "exit", "floor", "grad", "path", "step")

    def __init__(self, ctx, alpha0, d, path, grad, floor):
        self.ctx, self.alpha0, self.d, self.path, self.grad, self.floor = ctx, alpha0, d, path, grad, floor
        self.exit, self.step = self._exit(ctx.zero)

    def _exit(self, t_in):
        ctx, (gx, gy) = self.ctx, self.grad
        half = ctx.mpf(0.5)
        t_up = face_exit(ctx, self.path, self.d + half - self.alpha0, -gx, -gy, t_in, self.floor)
        t_dn = face_exit(ctx, self.path, self.alpha0 - (self.d - half), gx, gy, t_in, self.floor)
        if t_up <= t_dn and t_up < ctx.inf:
            return t_up, 1
        if t_dn < ctx.inf:
            return t_dn, -1
        return ctx.inf, 0

    def cross(self, t_out):
        """Step into the next strip if the coordinate leaves its strip at ``t_out``, the current cell's exit."""
        if self.exit == t_out:
            self.d += self.step
            self.exit, self.step = self._exit(t_out)


def _gradients(table):
    """The gradients of the lattice coordinates ``alpha`` and ``beta`` (rows of the inverse lattice matrix)."""
    a1x, a1y, a2x, a2y = table.a
    return (a2y / table.det, -a2x / table.det), (-a1y / table.det, a1x / table.det)


def _strips(table, flight, path=None, floor=None):
    """The flight's lattice coordinates ``alpha(t), beta(t)``, each in the strip of the start's cell.

    ``path``: a thermostatted or magnetic path (``floor``: the magnetic exits' slope floor).
    """
    x, y, vx, vy, ax, ay = flight
    (p0, r0), (p1, r1), (p2, r2) = (table.coordinates(x, y), table.coordinates(vx, vy),
                                    table.coordinates(ax, ay))
    alpha, beta = [p0, p1, p2 / 2], [r0, r1, r2 / 2]
    d1, d2 = table.cell(x, y)
    if isinstance(path, MagneticPath):
        ga, gb = _gradients(table)
        return (_MagneticStrip(table.ctx, p0, d1, path, ga, floor),
                _MagneticStrip(table.ctx, r0, d2, path, gb, floor))
    if path is not None:
        ga, gb = _gradients(table)
        return _ThermoStrip(table.ctx, alpha, d1, path, ga), _ThermoStrip(table.ctx, beta, d2, path, gb)
    return _Strip(table.ctx, alpha, d1), _Strip(table.ctx, beta, d2)


def _endless_gives_up(ctx, alpha, beta, t_limit, max_cells):
    """Whether an endless flight escapes: no time limit, or the engine's walk passes ``max_cells`` first."""
    if t_limit == ctx.inf:
        return True
    cells = 1 + alpha.faces_crossed(t_limit) + beta.faces_crossed(t_limit)
    return cells > max_cells


def _walk_cells(table, flight, earliest, t_limit, tol, path=None, floor=None):
    """Step 4 on a lattice: walk the cells a flight crosses until its earliest hit is known.

    Parameters
    ----------
    table : _Table
        The periodic scene's copies and cells.
    flight : tuple of mpf
        ``(x, y, vx, vy, ax, ay)``: the unfolded start, velocity and force of the flight.
    earliest : object
        Keeps the earliest hit: ``earliest.offer(copies)`` solves each copy it has not met
        yet on the whole flight; ``earliest.t`` and ``earliest.copy`` are the best so far
        (None before any hit).
    t_limit : mpf
        The walk may stop once the current cell's exit comes at or after it.
    tol : mpf
        The length tolerance at the start of the flight.
    path : ThermoPath or MagneticPath, optional
        A thermostatted or magnetic flight's path (``flight`` then carries its acceleration at the start).
        A magnetic walk follows one period: a closed path meets nothing later that it did not meet then.
    floor : mpf, optional
        The slope floor of the magnetic face exits.

    Returns
    -------
    t, copy : mpf and copy, or None and None
        The earliest hit (it may lie beyond ``t_limit``), or none found.
    gave_up : bool
        No hit ahead: the flight is endless or the walk passed ``MAX_CELLS_PER_FLIGHT`` cells
        (an escape unless a limit comes first).
    """
    ctx = table.ctx
    max_cells = MAX_CELLS_PER_FLIGHT  # read at each call, so a test may lower it
    alpha, beta = _strips(table, flight, path, floor)
    period = table.period(*flight[2:])
    endless = None if period is None else _Period(ctx, flight, period)
    for _ in range(max_cells):
        t_out = min(alpha.exit, beta.exit)
        earliest.offer(table.copies_at(alpha.d, beta.d))
        if earliest.t is not None and earliest.t <= t_out:  # a copy not met yet lies beyond this exit
            return earliest.t, earliest.copy, False
        if t_out >= t_limit:  # the limit comes first (or the flight never leaves this cell: nothing ahead)
            return earliest.t, earliest.copy, earliest.t is None and t_out == ctx.inf
        if earliest.t is None and endless is not None and endless.covered(t_out, tol):
            return None, None, _endless_gives_up(ctx, alpha, beta, t_limit, max_cells)
        alpha.cross(t_out)
        beta.cross(t_out)
    return None, None, True
