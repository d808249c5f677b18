r"""The explorer's state on the server: orbits, the clock, launches and limits (no browser code here).

An :class:`Explorer` holds the orbits launched into one scene and a clock.
The orbits are computed by the package's kernel through
:func:`noslipsim.simulate_many` (``record='log'``), a first budget of
:data:`FIRST_BUDGET` collisions each, and refilled as the clock reaches the end
of what was computed: the orbit is recomputed from its start with twice the
budget, which costs at most twice the collisions drawn and gives exactly the
orbit :func:`noslipsim.simulate` gives (no continuation error, nothing
time-stepped).  Each frame evaluates every orbit's current flight at the
clock (the scene's exact flight, :func:`noslipsim.plot.flight_states`: a
parabola under a force, a cyclotron arc in a magnetic field, the thermostat's
closed form) and hands the view what changed:
particle positions and spin markers, the last flights as fading trails, and
the collisions passed since the last frame as new portrait points (the
paper's portrait for the law, :mod:`noslipsim.analysis.log_portrait`).

Every request from a page is checked against :class:`Limits` (orbits alive,
particles per launch, collisions per orbit and per frame, speed), so a page
cannot exhaust the machine; a refused request raises ``ValueError`` with one
line the page shows.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from .._engine.lattice import cell_of, cell_origin
from .._validate import finite_float, finite_vector, positive
from ..analysis.log_portrait import boundary_length, log_portrait, paper_portrait, portrait_elements
from ..analysis.portraits import birkhoff_states, reduced_states
from ..core.layout import STOP_REASONS
from ..ensemble import simulate_many
from ..plot import flight_samples, orbit_colors, view_window
from ..scenes import Scene

__all__ = ["FIRST_BUDGET", "Explorer", "Limits", "palette"]

#: Collisions computed when an orbit is launched; each refill doubles the budget.
FIRST_BUDGET = 1000
#: Flights drawn in an orbit's trail, fading with age in TRAIL_BANDS steps.
TRAIL_FLIGHTS = 12
TRAIL_BANDS = 4
#: Samples per curved flight of a trail (force or field; straight flights need their ends).
TRAIL_POINTS = 12
#: Drawn particle radius, relative to the larger side of the view.
PARTICLE_SIZE = 0.018
#: Orbit colours cycle through this many (:func:`palette`).
PALETTE_SIZE = 60


def palette():
    """The orbit colours as hex strings: orbit ``i`` is drawn in ``palette()[i % PALETTE_SIZE]``."""
    return [_hex(c) for c in orbit_colors(PALETTE_SIZE)]


@dataclass(frozen=True)
class Limits:
    """What one page may ask of the server.

    Attributes
    ----------
    max_orbits : int
        Orbits alive at once in one session.
    max_beam : int
        Particles launched by one click or drag.
    max_collisions : int
        Collisions computed per orbit (an orbit stops there, reason ``limit``).
    frame_collisions : int
        Collisions computed per frame over all refills (orbits beyond it wait a frame).
    max_speed : float
        Simulated time per second of playback.
    max_gamma : float
        Largest gamma (moment of inertia) a page may set.
    max_force : float
        Largest force strength a page may set.
    """

    max_orbits: int = 200
    max_beam: int = 100
    max_collisions: int = 20_000
    frame_collisions: int = 400_000
    max_speed: float = 1.0e4
    max_gamma: float = 100.0
    max_force: float = 1.0e3


@dataclass
class Orbit:
    """One launched orbit: its start, the part computed so far, its portrait points."""

    index: int
    color: str
    start: dict
    born: float                      # explorer clock at launch (the orbit's time 0)
    nodes: dict = field(default_factory=dict)
    marks: tuple = ()                # portrait (x, y) per collision
    angles: np.ndarray = None        # spin-marker angle at each node
    energy: np.ndarray = None        # energy at each node
    stop_reason: str = ""
    budget: int = 0
    shown: int = 0                   # collisions already sent as portrait points

    @property
    def collisions(self):
        return len(self.nodes["t"]) - 1

    @property
    def complete(self):
        """The whole orbit is computed (it stopped for a reason of its own, or at the explorer's limit)."""
        return self.stop_reason != "max_collisions"


class Explorer:
    """Orbits of one scene under a clock: launch, advance, read out.

    Parameters
    ----------
    scene : Scene
        The table as loaded; law, gamma and force can be changed afterwards
        (:meth:`set_physics`), the geometry cannot.
    limits : Limits, optional
    """

    def __init__(self, scene: Scene, limits: Limits | None = None):
        if not isinstance(scene, Scene):
            raise ValueError(f"scene: expected a noslipsim.Scene, got {type(scene).__name__}")
        self.base = scene
        self.scene = scene
        self.limits = limits or Limits()
        self.window = _square(view_window(scene, margin=0.05))
        self.radius = PARTICLE_SIZE * max(self.window[1] - self.window[0], self.window[3] - self.window[2])
        # a scene without force gets its force control along gravity
        fx, fy = scene.force
        norm = math.hypot(fx, fy)
        self.force_direction = (fx / norm, fy / norm) if norm > 0 else (0.0, -1.0)
        self.force_strength = norm
        self.orbits: list[Orbit] = []
        self.clock = 0.0
        self.speed = 1.0
        self.launched = 0
        self.message = ""

    # ------------------------------------------------------------------ physics
    @property
    def portrait(self):
        """``'velocity'`` (no-slip) or ``'birkhoff'`` (specular): the paper's portrait for the law."""
        return paper_portrait(self.scene)

    def portrait_range(self):
        """``(x0, x1, y0, y1)`` of the portrait: the unit disk, or ``[0, L] x [-1, 1]``."""
        if self.portrait == "velocity":
            return -1.0, 1.0, -1.0, 1.0
        return 0.0, boundary_length(self.scene), -1.0, 1.0

    @property
    def force_allowed(self):
        """False for a table with a magnetic field: a scene refuses a force together with a field."""
        return self.scene.magnetic == 0.0

    def set_physics(self, law=None, gamma=None, force_strength=None):
        """Change the law, gamma or the force's strength (along its direction); every orbit is recomputed.

        The clock restarts at 0 and each orbit from its start, so the new
        physics is compared from the same starts.
        """
        strength = self.force_strength if force_strength is None else finite_float(force_strength, "force")
        if strength != 0.0 and not self.force_allowed:
            raise ValueError(f"force: this table has a magnetic field (magnetic = {self.scene.magnetic:g}), "
                             "which takes no force; the force stays 0")
        if not 0.0 <= strength <= self.limits.max_force:
            raise ValueError(f"force: the strength must be in [0, {self.limits.max_force:g}], got {strength:g}")
        if gamma is not None and finite_float(gamma, "gamma") > self.limits.max_gamma:
            raise ValueError(f"gamma: must be <= {self.limits.max_gamma:g} here, got {gamma:g}")
        scene = self._physics_scene(law, gamma, strength)
        starts = [o.start for o in self.orbits]
        self.scene, self.force_strength = scene, strength
        self.clock = 0.0
        self.orbits = []
        if starts:
            self._launch(starts)

    def _physics_scene(self, law, gamma, strength):
        """The scene with ``law`` and ``gamma`` (``None``: unchanged), the force of ``strength`` along its line."""
        law = self.scene.law if law is None else law
        gamma = self.scene.gamma if gamma is None else gamma
        force = (strength * self.force_direction[0], strength * self.force_direction[1])
        return self.scene.replace(law=law, gamma=gamma, force=force)

    def warm(self):
        """Compile (or load from numba's cache) every kernel variant the page's controls can reach.

        Each law, with and without force, runs one collision of one orbit from
        the deepest point of a grid over the view; a compile then never holds up
        a page (it takes 10 to 20 s per variant the first time).  A table with no
        grid point inside compiles at its first launch instead.
        """
        inside = self._deepest_point()
        if inside is None:
            return
        start = {"position": inside, "velocity": [0.6, 0.8], "spin": 0.0, "element": -1}
        for law in ("no-slip", "specular"):
            for strength in sorted({0.0, self.force_strength or 1.0}):
                try:
                    scene = self._physics_scene(law, None, strength)
                except ValueError:  # the page would be refused this physics too: nothing to compile
                    continue
                _run(scene, [start], 1)

    def _deepest_point(self, n=41):
        """The point of an ``n x n`` grid over the view deepest inside the table, or ``None``."""
        x0, x1, y0, y1 = self.window
        gx, gy = np.meshgrid(np.linspace(x0, x1, n), np.linspace(y0, y1, n))
        points = np.c_[gx.ravel(), gy.ravel()]
        depth = self.scene.depth(points)
        k = int(np.argmax(depth))
        return points[k].tolist() if depth[k] > 0.0 else None

    def set_speed(self, speed):
        """Simulated time per second of playback, ``0 < speed <= limits.max_speed``."""
        speed = finite_float(speed, "speed")
        if not 0.0 < speed <= self.limits.max_speed:
            raise ValueError(f"speed: must be in (0, {self.limits.max_speed:g}], got {speed:g}")
        self.speed = speed

    # ------------------------------------------------------------------ launches
    def launch(self, position, velocity, spin=0.0):
        """Launch one orbit from an interior point; returns it."""
        q = finite_vector(position, "position")
        v = finite_vector(velocity, "velocity")
        return self._launch([{"position": q.tolist(), "velocity": v.tolist(),
                              "spin": finite_float(spin, "spin"), "element": -1}])[0]

    def launch_beam(self, start, end, n=1, speed=1.0, width=None):
        """A beam of ``n`` parallel orbits from ``start`` towards ``end`` (a drag in the table).

        The particles move along ``end - start`` at ``speed``, spread over
        ``width`` (default 1 % of the view) across the direction, centred on
        ``start`` (as DynamicalBilliards' particle beam).  Starts outside the
        table are left out; returns the orbits launched.
        """
        p0 = finite_vector(start, "start")
        d = finite_vector(end, "end") - p0
        length = math.hypot(*d)
        if not length > 0.0:
            raise ValueError("drag: give the direction by dragging from the start point")
        n = self._count(n)
        speed = positive(speed, "launch speed")
        width = 0.01 * (self.window[1] - self.window[0]) if width is None else finite_float(width, "width")
        u = d / length
        normal = np.array([-u[1], u[0]])
        offsets = (np.arange(n) - 0.5 * (n - 1)) * (width / max(n - 1, 1))
        points = p0[None, :] + offsets[:, None] * normal[None, :]
        inside = self.scene.depth(points) > 0.0
        if not inside.any():
            raise ValueError(f"position: {p0.tolist()} is not inside the table; drag from a point inside it")
        starts = [{"position": p.tolist(), "velocity": (speed * u).tolist(), "spin": 0.0, "element": -1}
                  for p in points[inside]]
        out = self._launch(starts)
        left = int((~inside).sum())
        self.message = f"{left} of the beam's {n} starts lie outside the table and were left out" if left else ""
        return out

    def launch_from_portrait(self, x, y, speed=1.0, s_launch=None):
        """Launch an orbit from a point of the portrait (a click in it).

        Birkhoff (specular): ``(s, p)`` is the boundary point and the sine of
        the angle to the inward normal.  Velocity portrait (no-slip):
        ``(v_t, w)`` is the unit vector's projection, launched from the
        boundary point at ``s_launch`` (the projection forgets where), default
        the middle of the boundary.  The speed ``sqrt(|v|^2 + w^2)`` is ``speed``.
        """
        x, y = finite_float(x, "x"), finite_float(y, "y")
        speed = positive(speed, "launch speed")
        chosen = portrait_elements(self.scene)
        total = boundary_length(self.scene)
        if self.portrait == "birkhoff":
            if not (0.0 <= x <= total and abs(y) < 1.0):
                raise ValueError(f"portrait: ({x:.4g}, {y:.4g}) is outside [0, {total:.4g}] x (-1, 1)")
            st = birkhoff_states(self.scene, [x], [y], elements=chosen, speed=speed)
        else:
            if not x * x + y * y < 1.0:
                raise ValueError(f"portrait: ({x:.4g}, {y:.4g}) is outside the unit disk of (v_t, w)")
            s = 0.5 * total if s_launch is None else finite_float(s_launch, "launch point s")
            if not 0.0 <= s <= total:
                raise ValueError(f"launch point s: must lie in [0, {total:.4g}], got {s:.4g}")
            st = reduced_states(self.scene, [s], [x], [y], elements=chosen, speed=speed)
        start = {"position": st["positions"][0].tolist(), "velocity": st["velocities"][0].tolist(),
                 "spin": float(st["spins"][0]), "element": int(st["start_elements"][0]), "portrait": [x, y]}
        return self._launch([start])[0]

    def _count(self, n):
        if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or n < 1:
            raise ValueError(f"particles: expected a positive integer, got {n!r}")
        if n > self.limits.max_beam:
            raise ValueError(f"particles: at most {self.limits.max_beam} per launch, asked for {n}")
        return int(n)

    def _launch(self, starts):
        free = self.limits.max_orbits - len(self.orbits)
        if len(starts) > free:
            raise ValueError(f"particles: at most {self.limits.max_orbits} orbits at once ({len(self.orbits)} "
                             f"running, {len(starts)} asked for); press reset")
        new = []
        colors = palette()
        for st in starts:
            new.append(Orbit(index=self.launched, color=colors[self.launched % PALETTE_SIZE], start=st,
                             born=self.clock))
            self.launched += 1
        try:
            self._compute(new, FIRST_BUDGET)
        except ValueError:
            self.launched -= len(new)
            raise
        self.orbits += new
        return new

    # ------------------------------------------------------------------ computing
    def _compute(self, orbits, budget):
        """Compute (or recompute from the start) ``orbits`` with ``budget`` collisions each, in one kernel call."""
        budget = min(int(budget), self.limits.max_collisions)
        ds = _run(self.scene, [o.start for o in orbits], budget)
        ax, ay = self.scene.force
        kind = self.portrait
        for i, o in enumerate(orbits):
            n = int(ds.n_collisions[i])
            log = {k: ds[k].values[i, :n] for k in ("t", "x", "y", "vx", "vy", "spin")}
            st = o.start
            o.nodes = {k: np.concatenate([[v0], log[k]]) for k, v0 in
                       zip(("t", "x", "y", "vx", "vy", "spin"),
                           (0.0, *st["position"], *st["velocity"], st["spin"]), strict=True)}
            o.nodes["force"] = (ax, ay)
            o.nodes["scene"] = self.scene  # the flights between the nodes are this scene's (arcs in a field)
            o.nodes["t_end"] = float(ds.t_final[i])
            o.marks = log_portrait(self.scene, ds.element.values[i, :n], ds.s.values[i, :n], log["vx"], log["vy"],
                                   log["spin"], kind)
            nd = o.nodes
            o.energy = 0.5 * (nd["vx"] ** 2 + nd["vy"] ** 2 + nd["spin"] ** 2) - (ax * nd["x"] + ay * nd["y"])
            o.angles = _node_angles(nd, self.scene.gamma, self.radius)
            reason = STOP_REASONS[int(ds.stop_reason[i])]
            o.stop_reason = "limit" if reason == "max_collisions" and budget >= self.limits.max_collisions else reason
            o.budget = budget

    def _refill(self):
        """Recompute orbits the clock has run past, doubling their budget, within the frame's collision budget."""
        spent = 0
        for o in self.orbits:
            if o.complete or self.clock - o.born <= o.nodes["t"][-1]:
                continue
            budget = min(2 * o.budget, self.limits.max_collisions)
            if spent + budget > self.limits.frame_collisions:
                o.born = self.clock - o.nodes["t"][-1]  # wait at its last computed collision for a frame
                continue
            self._compute([o], budget)
            spent += budget
            if not o.complete and self.clock - o.born > o.nodes["t"][-1]:
                o.born = self.clock - o.nodes["t"][-1]

    # ------------------------------------------------------------------ the clock
    def advance(self, seconds):
        """Move the clock by ``speed * seconds`` and return the frame to draw (:meth:`frame`)."""
        self.clock += self.speed * max(float(seconds), 0.0)
        self._refill()
        return self.frame()

    def step(self):
        """Move the clock to the next collision of any orbit (the particle is drawn on the wall it hits)."""
        nxt = math.inf
        for o in self.orbits:
            t = o.nodes["t"]
            k = int(np.searchsorted(t, self.clock - o.born, side="right"))
            if k < len(t):
                nxt = min(nxt, o.born + t[k])
            elif not o.complete:
                self.clock = o.born + t[-1] + 1e-12 * max(1.0, abs(t[-1]))
                self._refill()
                return self.step()
        if math.isfinite(nxt):
            self.clock = nxt
        return self.frame()

    def reset(self):
        """Remove every orbit and restart the clock."""
        self.orbits = []
        self.clock = 0.0
        self.message = ""

    # ------------------------------------------------------------------ what the view draws
    def frame(self):
        """What to draw at the clock's time, as flat arrays (sent to the page as binary columns).

        Every position is the scene's exact flight (:func:`noslipsim.plot.flight_samples`),
        evaluated for all orbits at once; a trail samples each curved flight
        (force or magnetic field) at :data:`TRAIL_POINTS` points.

        Returns
        -------
        dict
            ``particles``: per orbit ``x, y`` (folded into the view for a
            lattice), spin-marker end ``mx, my`` and colour index ``ci``;
            ``trails``: segments ``x0, y0, x1, y1, ci, alpha`` along the
            last :data:`TRAIL_FLIGHTS` flights (older ones fainter);
            ``portrait``: ``x, y, ci`` of the collisions passed since the last
            frame.  ``ci`` is the orbit's index modulo :data:`PALETTE_SIZE`
            (its colour, :func:`palette`).
        """
        n = len(self.orbits)
        cols = {k: [] for k in ("t", "x", "y", "vx", "vy", "end", "age", "ci")}
        last = np.empty(n, dtype=np.int64)  # row of each orbit's current flight
        angle = np.empty(n)
        ci = np.empty(n, dtype=np.int64)
        new = []
        rows = 0
        for i, o in enumerate(self.orbits):
            nd = o.nodes
            tau = self.clock - o.born
            if o.complete and o.stop_reason != "escape":
                tau = min(tau, nd["t_end"])  # a stopped orbit rests where it stopped
            tau = max(tau, 0.0)
            k = int(np.searchsorted(nd["t"], tau, side="right")) - 1
            lo = max(0, k - TRAIL_FLIGHTS + 1)
            for name in ("t", "x", "y", "vx", "vy"):
                cols[name].append(nd[name][lo:k + 1])
            cols["end"].append(np.append(nd["t"][lo + 1:k + 1], tau))
            cols["age"].append(np.arange(k - lo, -1, -1))
            ci[i] = o.index % PALETTE_SIZE
            cols["ci"].append(np.full(k + 1 - lo, ci[i]))
            rows += k + 1 - lo
            last[i] = rows - 1
            angle[i] = o.angles[k] + _omega(nd["spin"][k], self.scene.gamma, self.radius) * (tau - nd["t"][k])
            seen = min(k, o.collisions)  # collisions 1..k are behind the clock
            if seen > o.shown:
                mx, my = (m[o.shown:seen] for m in o.marks)
                ok = np.isfinite(mx) & np.isfinite(my)
                new.append((mx[ok], my[ok], np.full(int(ok.sum()), ci[i])))
                o.shown = seen
        if n == 0:
            empty = np.empty(0)
            return {"particles": {k: empty for k in ("x", "y", "mx", "my", "ci")},
                    "trails": {k: empty for k in ("x0", "y0", "x1", "y1", "ci", "alpha")},
                    "portrait": {k: empty for k in ("x", "y", "ci")}}
        c = {k: np.concatenate(v) for k, v in cols.items()}
        _, x, y = flight_samples({**c, "scene": self.scene, "force": self.scene.force}, c["end"], TRAIL_POINTS)
        m = x.shape[1]
        px, py = self._fold(x[last, -1], y[last, -1])
        parts = {"x": px, "y": py, "mx": px + self.radius * np.cos(angle), "my": py + self.radius * np.sin(angle),
                 "ci": ci}
        x0, y0 = x[:, :-1].ravel(), y[:, :-1].ravel()
        f0, g0 = self._fold(x0, y0)  # a segment moves with its first point: no jump across a cell's edge
        segs = {"x0": f0, "y0": g0, "x1": x[:, 1:].ravel() - (x0 - f0), "y1": y[:, 1:].ravel() - (y0 - g0),
                "ci": np.repeat(c["ci"], m - 1), "alpha": np.repeat(0.9 - 0.8 * c["age"] / TRAIL_FLIGHTS, m - 1)}
        pts = {k: np.concatenate([p[j] for p in new]) if new else np.empty(0) for j, k in enumerate(("x", "y", "ci"))}
        return {"particles": parts, "trails": segs, "portrait": pts}

    def _fold(self, x, y):
        """Positions of a periodic scene folded into cell 0 (a segment is moved with its first point)."""
        if self.scene.lattice is None or len(x) == 0:
            return x, y
        q = np.c_[x, y]
        f = q - cell_origin(cell_of(q, self.scene.lattice), self.scene.lattice)
        return f[:, 0], f[:, 1]

    def readout(self):
        """Collisions drawn, the newest orbit's energy and every orbit's worst relative energy error, stop reasons.

        The energy is ``E = (|v|^2 + w^2)/2 - a . q`` (conserved exactly by
        the dynamics); its error at a collision is ``|E - E_0| / max(|E_0|, 1e-300)``.
        """
        drawn, worst, reasons = 0, 0.0, {}
        for o in self.orbits:
            k = int(np.searchsorted(o.nodes["t"], self.clock - o.born, side="right")) - 1
            drawn += min(k, o.collisions)
            e = o.energy[: k + 1]
            worst = max(worst, float(np.max(np.abs(e - e[0]))) / max(abs(float(e[0])), 1e-300))
            done = o.complete and (self.clock - o.born) >= o.nodes["t"][-1]
            reasons[o.stop_reason if done else "running"] = reasons.get(o.stop_reason if done else "running", 0) + 1
        last = self.orbits[-1] if self.orbits else None
        return {"orbits": len(self.orbits), "collisions": drawn, "clock": self.clock,
                "energy": float(last.energy[0]) if last is not None else math.nan,
                "energy_error": worst, "stop_reasons": reasons, "message": self.message}


def _run(scene, starts, budget):
    """The orbits of ``starts`` (launch dicts) with ``budget`` collisions each, logged, in one kernel call."""
    return simulate_many(scene, [s["position"] for s in starts], [s["velocity"] for s in starts],
                         [s["spin"] for s in starts], start_elements=[s["element"] for s in starts],
                         max_collisions=budget, record="log", scheduler="sync", progress=False)


def _square(box):
    """``box`` widened along its shorter side to a square (the page's figures are square: equal aspect)."""
    x0, x1, y0, y1 = box
    half = 0.5 * max(x1 - x0, y1 - y0)
    cx, cy = 0.5 * (x0 + x1), 0.5 * (y0 + y1)
    return cx - half, cx + half, cy - half, cy + half


def _omega(w, gamma, radius):
    """Angular velocity of the drawn disk, ``w / (gamma R)`` (0 for a point mass, gamma = 0)."""
    return 0.0 if gamma == 0.0 else w / (gamma * radius)


def _node_angles(nodes, gamma, radius):
    omega = np.array([_omega(w, gamma, radius) for w in nodes["spin"]])
    return math.pi / 2 + np.concatenate([[0.0], np.cumsum(omega[:-1] * np.diff(nodes["t"]))])


def _hex(rgba):
    r, g, b = (round(255 * c) for c in rgba[:3])
    return f"#{r:02x}{g:02x}{b:02x}"
