"""Invariant checks shared by tests and stress runs (DynamicalBilliards.jl's testing habit).

- every collision point lies on the element it hit (within ``tol`` times the scene size);
- sampled points of every flight lie inside the table (depth >= -tol times the size);
- energy ``(|v|^2 + w^2)/2 - a.q`` is conserved.
"""
import math

import numpy as np

from noslipsim import Circle, Line, tables

FAMILIES = {
    # name: (scene factory, start, velocity, spin)
    "pentagon": (lambda: tables.regular_polygon(5), (0.1, 0.05), (0.83, 0.41), 0.2),
    "pentagon_gravity": (lambda: tables.regular_polygon(5, force=(0.0, -1.0)), (0.1, 0.05), (0.83, 0.41), 0.2),
    "L_shape_gravity": (lambda: tables.polygon([(0, 0), (2, 0), (2, 1), (1, 1), (1, 2), (0, 2)], force=(0.3, -1.0)),
                        (0.5, 0.5), (0.7, 0.3), -0.1),
    "sinai_box": (lambda: tables.rectangle(1.0, 1.0, disks=[(0.5, 0.5, 0.3)]), (0.1, 0.1), (0.6, 0.8), 0.0),
    "two_disks_box_gravity": (lambda: tables.two_disks(0.6, box=(4.0, 3.0), force=(0.0, -1.0)), (0.0, 0.9),
                              (0.5, 0.2), 0.3),
    "stadium_gravity": (lambda: tables.stadium(1.0, 1.0, force=(0.0, -1.0)), (0.0, 0.0), (0.6, 0.3), 0.1),
    "lemon_specular": (lambda: tables.lemon(1.0, 1.0), (0.0, 0.1), (0.9, 0.2), 0.0),
    "circle_container_gravity": (lambda: tables.Scene([Circle((0.0, 0.0), 1.0, "inside")], force=(0.2, -1.0)),
                                 (0.1, 0.2), (0.4, 0.1), 0.5),
    "wedge_gravity": (lambda: tables.wedge(0.6), (0.0, 1.0), (0.5, 0.4), 0.3),
    "galton_box": (lambda: tables.Scene(
        tables.rectangle(6.0, 6.0).elements
        + tuple(Circle((1.0 + 2.0 * i + (j % 2), 1.0 + 1.7320508075688772 * j / 1.0 * 0.7), 0.4)
                for j in range(4) for i in range(2 + (j + 1) % 2) if 1.0 + 2.0 * i + (j % 2) < 5.6),
        force=(0.0, -1.0)), (3.0, 5.5), (0.3, 0.1), 0.0),
    "ramp_channel": (lambda: tables.Scene([Line((0.0, 0.0), (-0.3, 1.0)), Line((0.0, 2.0), (0.3, -1.0)),
                                           Line((-3.0, 0.0), (1.0, 0.0)), Line((3.0, 0.0), (-1.0, 0.0))],
                                          force=(0.0, -1.0)), (0.0, 1.0), (0.4, 0.2), 0.0),
}


def on_element_error(scene, ds, corner=False):
    """Largest distance (relative to the scene size) from a collision point to the element it hit.

    ``corner=False`` measures ordinary hits (the particle is projected onto the
    element); ``corner=True`` measures corner-rule hits, which by the rule lie
    within ``CONTACT_TOL`` of the second element.
    """
    pts = np.c_[ds.x.values, ds.y.values]
    worst = 0.0
    for i, e in enumerate(scene.elements):
        sel = (ds.element.values == i) & ((ds.corner.values == 1) == corner)
        if not sel.any():
            continue
        d = e.distance(pts[sel]) if e.finite else np.abs(e.side_distance(pts[sel]))
        worst = max(worst, float(d.max()))
    return worst / max(scene.scale, 1.0)


def flight_samples(scene, ds, per_flight=3, seed=0):
    """Points sampled strictly inside every flight between consecutive collisions."""
    rng = np.random.default_rng(seed)
    t = ds.t.values
    dt = np.diff(t)
    frac = rng.uniform(0.0, 1.0, size=(len(dt), per_flight))
    tau = dt[:, None] * frac
    ax, ay = scene.force
    x = ds.x.values[:-1, None] + ds.vx.values[:-1, None] * tau + 0.5 * ax * tau ** 2
    y = ds.y.values[:-1, None] + ds.vy.values[:-1, None] * tau + 0.5 * ay * tau ** 2
    return np.stack([x.ravel(), y.ravel()], axis=-1)


def leak_depth(scene, ds, per_flight=3, seed=0):
    """Most negative table depth over sampled flight points, relative to the scene size (>= 0: no leak)."""
    pts = flight_samples(scene, ds, per_flight, seed)
    return float(scene.depth(pts).min()) / max(scene.scale, 1.0)


def relative_energy_drift(ds):
    e = ds.energy.values
    return float(np.abs(e - e[0]).max() / max(abs(e[0]), math.ulp(1.0)))


# ---------------------------------------------------------------------------- stress-suite helpers
# (appended for tests/test_stress.py and benchmarks/stress_run.py; lattice-aware and
# relative to the engine's own length scale ``max(scene.scale, |q|)``, |q| in the cell frame)

def scaled_scene(scene, L):
    """The scene with every length multiplied by ``L`` and the force by ``L`` (times unchanged)."""
    from noslipsim import Scene
    d = scene.to_dict()
    elements = []
    for e in d["elements"]:
        e = dict(e)
        for key in ("point", "p0", "p1", "center"):
            if key in e:
                e[key] = [L * c for c in e[key]]
        if "radius" in e:
            e["radius"] = L * e["radius"]
        elements.append(e)
    d["elements"] = elements
    d["force"] = [L * f for f in d["force"]]
    if "lattice" in d:
        d["lattice"] = {k: [L * c for c in vec] for k, vec in d["lattice"].items()}
    return Scene.from_dict(d)


def cell_frame(scene, ds):
    """Collision points relative to the centre of the lattice cell that holds them (plain scenes: as is).

    Returns ``(x, y, origins)``; the log stores unfolded positions, so each value
    carries the rounding of the unfolded coordinate (one ulp of ``|q|``).
    """
    x, y = ds.x.values, ds.y.values
    if scene.lattice is None:
        return x, y, np.zeros((len(x), 2))
    from noslipsim._engine.lattice import cell_origin
    origins = cell_origin(np.c_[ds.cell_a1.values, ds.cell_a2.values], scene.lattice)
    return x - origins[:, 0], y - origins[:, 1], origins


def _element_copies(scene):
    """``[(element index, element object in cell-0 coordinates)]``: every copy reaching cell 0."""
    if scene.lattice is None:
        return list(enumerate(scene.elements))
    from noslipsim._engine.lattice import lattice_matrix, reaching_copies
    A, _ = lattice_matrix(scene.lattice)
    out = []
    for e, o1, o2 in reaching_copies(scene.elements, scene.lattice):
        dx, dy = A @ np.array([o1, o2], float)
        out.append((int(e), scene.elements[e].shifted(dx, dy)))
    return out


def _piece_distance(e, pts):
    return e.distance(pts) if e.finite else np.abs(e.side_distance(pts))


def _overshoot(e, pts):
    """How far points lie beyond the ends of a segment or an arc, along it (0 for lines and circles)."""
    if e.type_name == "segment":
        ux, uy, _, _, L = e._frame()
        u = (pts[:, 0] - e.p0[0]) * ux + (pts[:, 1] - e.p0[1]) * uy
        return np.maximum(np.maximum(-u, u - L), 0.0)
    if e.type_name == "arc":
        rel = (np.arctan2(pts[:, 1] - e.center[1], pts[:, 0] - e.center[0]) - e.theta0) % (2 * math.pi)
        span = e.theta1 - e.theta0
        beyond = np.minimum(np.maximum(rel - span, 0.0), np.maximum(2 * math.pi - rel, 0.0))
        return np.where(rel <= span, 0.0, beyond) * e.radius
    return np.zeros(len(pts))


def element_error_rel(scene, ds, corner=False, part="support"):
    """Largest distance from a collision point to the element it hit, over ``max(scene.scale, |q|)``.

    ``part='support'``: distance to the element's line or circle (ordinary hits are
    projected onto it); ``part='extent'``: how far beyond a segment's or an arc's end
    (ends are inclusive within ``EXTENT_TOL``, corner contacts within ``CONTACT_TOL``).
    Lattice scenes: the point (in its cell's frame) against the nearest copy of its
    element.  ``corner`` as in :func:`on_element_error`.
    """
    x, y, _ = cell_frame(scene, ds)
    pts = np.c_[x, y]
    length = np.maximum(scene.scale, np.abs(pts).max(axis=1)) if len(pts) else np.zeros(0)
    el = ds.element.values
    sel_c = (ds.corner.values == 1) == corner
    copies = _element_copies(scene)
    worst = 0.0
    for i in range(len(scene.elements)):
        sel = np.flatnonzero((el == i) & sel_c)
        if not len(sel):
            continue
        mine = [e for k, e in copies if k == i]
        dist = np.stack([_piece_distance(e, pts[sel]) for e in mine])
        pick = np.argmin(dist, axis=0)
        d = np.empty(len(sel))
        for c, e in enumerate(mine):
            rows = pick == c
            if part == "support":
                d[rows] = np.abs(e.side_distance(pts[sel][rows]))
            else:
                d[rows] = _overshoot(e, pts[sel][rows])
        worst = max(worst, float((d / length[sel]).max()))
    return worst


def table_depth_rel(scene, pts):
    """Signed table depth of points (unfolded for lattices) over ``max(scene.scale, |q|)``."""
    pts = np.asarray(pts, float).reshape(-1, 2)
    if scene.lattice is not None:
        from noslipsim._engine.lattice import cell_of, cell_origin
        pts = pts - cell_origin(cell_of(pts, scene.lattice), scene.lattice)
        depth = scene.cell_scene((0, 0)).depth(pts)
    else:
        depth = scene.depth(pts)
    return depth / np.maximum(scene.scale, np.abs(pts).max(axis=1))


def leak_depth_rel(scene, ds, per_flight=3, seed=0, chunk=500_000):
    """Most negative relative depth over sampled flight points (>= 0: no leak); lattice-aware.

    Flights are sampled from their start in the cell frame, so the measurement
    keeps the cell's precision however far the orbit has gone.
    """
    if len(ds.t) < 2:
        return 0.0
    rng = np.random.default_rng(seed)
    x, y, vx, vy, dt = _flight_arrays(scene, ds)
    ax, ay = scene.force
    worst = np.inf
    for s in range(0, len(dt), chunk):
        sl = slice(s, s + chunk)
        tau = dt[sl, None] * rng.uniform(0.0, 1.0, size=(len(dt[sl]), per_flight))
        px = x[sl, None] + vx[sl, None] * tau + 0.5 * ax * tau ** 2
        py = y[sl, None] + vy[sl, None] * tau + 0.5 * ay * tau ** 2
        worst = min(worst, float(table_depth_rel(scene, np.stack([px.ravel(), py.ravel()], -1)).min()))
    return worst


def energy_error(scene, ds):
    """Largest ``|E - E_0|`` along the log over the size of the terms of ``E`` (the honest relative error).

    ``E = (|v|^2 + w^2)/2 - a.q`` is a difference of terms that grow without bound
    on a falling lattice orbit; its rounding is relative to the terms, not to ``E``.
    """
    e = ds.energy.values
    if not len(e):
        return 0.0
    ax, ay = scene.force
    kin = 0.5 * (ds.vx.values ** 2 + ds.vy.values ** 2 + ds.spin.values ** 2)
    pot = np.abs(ax * ds.x.values + ay * ds.y.values)
    size = max(abs(float(e[0])), float(kin.max()), float(pot.max()), math.ulp(1.0))
    return float(np.abs(e - e[0]).max() / size)


def _flight_arrays(scene, ds, refine=2):
    """Flights between consecutive collisions in the frame of their start cell: ``x, y, vx, vy, tau``.

    The log's ``t`` is a running sum, so ``diff(t)`` carries one ulp of the total
    time (1e-10 after 10^6 collisions); ``refine`` Newton steps on
    ``|q(tau) - q_end|^2`` recover each duration from the recorded end point.
    """
    x, y, origins = cell_frame(scene, ds)
    vx, vy = ds.vx.values[:-1], ds.vy.values[:-1]
    tau = np.diff(ds.t.values)
    x0, y0 = x[:-1], y[:-1]
    # end points in the frame of the start cell
    x1 = ds.x.values[1:] - origins[:-1, 0]
    y1 = ds.y.values[1:] - origins[:-1, 1]
    ax, ay = scene.force
    for _ in range(refine):
        ex = x0 + vx * tau + 0.5 * ax * tau * tau - x1
        ey = y0 + vy * tau + 0.5 * ay * tau * tau - y1
        wx, wy = vx + ax * tau, vy + ay * tau
        den = wx * wx + wy * wy + ex * ax + ey * ay
        tau = tau - (ex * wx + ey * wy) / np.where(den > 0.0, den, 1.0)
    return x0, y0, vx, vy, np.maximum(tau, 0.0)


def _reflex_ends(elements):
    """``{(element, end)}``: the ends (0: ``p0``, 1: ``p1``) of segments at a reflex junction.

    A junction is reflex when the neighbouring segment sharing the end runs into this segment's
    outer side (its other end lies strictly beyond this segment's line): the table is there the
    union of the two pieces' table sides.
    """
    segs = [(i, e) for i, e in enumerate(elements) if e.type_name == "segment"]
    out = set()
    for i, e in segs:
        _ux, _uy, nx, ny, _L = e._frame()
        for end, P in enumerate((e.p0, e.p1)):
            for j, f in segs:
                if j == i or P not in (f.p0, f.p1):
                    continue
                Q = f.p1 if P == f.p0 else f.p0
                if (Q[0] - e.p0[0]) * nx + (Q[1] - e.p0[1]) * ny < 0.0:
                    out.add((i, end))
    return out


def _straight_penetration(e, X, Y, VX, VY, T, ax, ay, tol, open_ends=(False, False)):
    """Per flight: deepest crossing of a line or segment inside the open flight (0 if none); absolute.

    ``open_ends``: whether the segment's ``p0`` and ``p1`` are reflex ends.  A flight that crosses
    the line at or beyond such an end within ``tol`` of the flight's start (a flight leaving the
    reflex vertex it was reflected at, beside the other piece) misses nothing: the engine
    divides that root out as the exact dynamics does (docs/algorithm.md, step 4).
    """
    if e.type_name == "line":
        (px, py), (nx, ny) = e.point, e.normal
        ux = uy = L = None
    else:
        ux, uy, nx, ny, L = e._frame()
        px, py = e.p0
    g0 = (X - px) * nx + (Y - py) * ny
    g1 = VX * nx + VY * ny
    g2 = 0.5 * (ax * nx + ay * ny)
    # exit root of g0 + g1 t + g2 t^2 (g decreasing through zero) in (0, T)
    with np.errstate(divide="ignore", invalid="ignore"):
        if g2 == 0.0:
            t_exit = np.where(g1 < 0.0, -g0 / g1, np.inf)
        else:
            disc = g1 * g1 - 4.0 * g2 * g0
            sq = np.sqrt(np.maximum(disc, 0.0))
            q = -0.5 * (g1 + np.copysign(sq, g1))
            r1, r2 = q / g2, g0 / q
            lo, hi = np.minimum(r1, r2), np.maximum(r1, r2)
            # g2 > 0: exit at the smaller root; g2 < 0: exit at the larger root
            t_exit = np.where(disc > 0.0, lo if g2 > 0.0 else hi, np.inf)
    out = np.zeros(len(T))
    hit = np.flatnonzero((t_exit > 0.0) & (t_exit < T))
    if not len(hit):
        return out
    X, Y, VX, VY, T, g0, g1, te = X[hit], Y[hit], VX[hit], VY[hit], T[hit], g0[hit], g1[hit], t_exit[hit]
    if ux is not None:
        hx = X + VX * te + 0.5 * ax * te ** 2
        hy = Y + VY * te + 0.5 * ay * te ** 2
        u = (hx - px) * ux + (hy - py) * uy
        tl = tol[hit] if np.ndim(tol) else tol
        within = (u >= -tl) & (u <= L + tl)
        at_start = np.hypot(VX, VY) * te <= tl  # crossed as the flight leaves its start
        if open_ends[0]:
            within &= ~((u <= 0.0) & at_start)
        if open_ends[1]:
            within &= ~((u >= L) & at_start)
        hit, T, g0, g1, te = hit[within], T[within], g0[within], g1[within], te[within]
        if not len(hit):
            return out
    # deepest point after the exit: the vertex of g (if within) or the end of the flight
    cand = [T]
    if g2 > 0.0:
        cand.append(np.clip(-g1 / (2.0 * g2), te, T))
    depth = np.min([g0 + g1 * t + g2 * t * t for t in cand], axis=0)
    out[hit] = np.minimum(depth, 0.0)
    return out


def _round_penetration(e, X, Y, VX, VY, T, ax, ay, tol, samples):
    """Per flight: deepest point beyond a circle (or an arc, within its span); absolute lengths.

    Candidates: ``samples + 1`` equally spaced times and the critical points of
    ``|q(t) - c|^2`` reached by Newton steps from each (exact for a flight without
    force); every candidate is a true point of the flight, so the result never
    overstates a penetration.
    """
    cx, cy = e.center
    r, sigma = e.radius, e.sigma
    dx, dy = X - cx, Y - cy
    ts = [T * (j / samples) for j in range(samples + 1)]
    if ax == 0.0 and ay == 0.0:
        vv = VX * VX + VY * VY
        ts.append(np.clip(-(dx * VX + dy * VY) / np.where(vv > 0, vv, 1.0), 0.0, T))
    else:
        for t0 in ts[1:-1]:
            t = t0
            for _ in range(4):
                qx, qy = dx + VX * t + 0.5 * ax * t * t, dy + VY * t + 0.5 * ay * t * t
                wx, wy = VX + ax * t, VY + ay * t
                f1 = qx * wx + qy * wy
                f2 = wx * wx + wy * wy + qx * ax + qy * ay
                t = np.clip(t - f1 / np.where(f2 != 0.0, f2, 1.0), 0.0, T)
            ts.append(t)
    worst = np.zeros(len(T))
    for t in ts:
        qx, qy = dx + VX * t + 0.5 * ax * t * t, dy + VY * t + 0.5 * ay * t * t
        g = sigma * (np.hypot(qx, qy) - r)
        if e.type_name == "arc":
            rel = (np.arctan2(qy, qx) - e.theta0) % (2.0 * math.pi)
            span = e.theta1 - e.theta0
            ang_tol = tol / r
            g = np.where((rel <= span + ang_tol) | (rel >= 2.0 * math.pi - ang_tol), g, 0.0)
        worst = np.minimum(worst, g)
    return worst


def _flight_boxes(X, Y, VX, VY, T, ax, ay):
    """Bounding boxes ``(x0, y0, x1, y1)`` of parabolic flights (ends and turning points)."""
    xs = [X, X + VX * T + 0.5 * ax * T * T]
    ys = [Y, Y + VY * T + 0.5 * ay * T * T]
    if ax != 0.0:
        tv = np.clip(-VX / ax, 0.0, T)
        xs.append(X + VX * tv + 0.5 * ax * tv * tv)
    if ay != 0.0:
        tv = np.clip(-VY / ay, 0.0, T)
        ys.append(Y + VY * tv + 0.5 * ay * tv * tv)
    return np.min(xs, axis=0), np.min(ys, axis=0), np.max(xs, axis=0), np.max(ys, axis=0)


def _lattice_pieces(scene, X, Y, VX, VY, T, batch=2_000_000):
    """Cut lattice flights into pieces spanning at most one cell, each in its own start cell's frame.

    Yields batches of at most ``batch`` pieces ``(x, y, vx, vy, tau)``.  Piece starts
    are evaluated in extended precision (``np.longdouble``) from the flight's start,
    so a piece of a long corridor flight keeps the cell's digits.
    """
    from noslipsim._engine.lattice import lattice_matrix
    A, B = lattice_matrix(scene.lattice)
    ax, ay = scene.force
    path = np.hypot(VX, VY) * T + 0.5 * math.hypot(ax, ay) * T * T
    m = np.maximum(np.ceil(path * np.linalg.norm(B, 2)), 1).astype(np.int64)
    ends = np.cumsum(m)
    ld = np.longdouble
    for p0 in range(0, int(ends[-1]), batch):
        piece = np.arange(p0, min(p0 + batch, int(ends[-1])))
        flight = np.searchsorted(ends, piece, side="right")
        j = piece - (ends[flight] - m[flight])
        tau = T[flight].astype(ld) * j / m[flight]
        px = X[flight].astype(ld) + VX[flight] * tau + ld(0.5) * ld(ax) * tau * tau
        py = Y[flight].astype(ld) + VY[flight] * tau + ld(0.5) * ld(ay) * tau * tau
        c1 = np.rint(ld(B[0, 0]) * px + ld(B[0, 1]) * py)
        c2 = np.rint(ld(B[1, 0]) * px + ld(B[1, 1]) * py)
        px = px - (c1 * ld(A[0, 0]) + c2 * ld(A[0, 1]))
        py = py - (c1 * ld(A[1, 0]) + c2 * ld(A[1, 1]))
        tau = tau.astype(float)
        yield (px.astype(float), py.astype(float), VX[flight] + ax * tau, VY[flight] + ay * tau,
               T[flight] / m[flight])


def flight_penetration(scene, ds, samples=6, chunk=500_000):
    """Deepest point of any flight beyond any element, over ``max(scene.scale, |q|)`` (0: none).

    The missed-collision check: a flight that crosses a line or a segment within
    its extent, or enters a scatterer, or leaves a container or an arc's disk
    within its span, between two recorded collisions has missed one.  Straight
    pieces: exact exit roots (closed form); circles and arcs: see
    :func:`_round_penetration`.  Flight ends count too (a corner contact is
    within ``CONTACT_TOL`` by the corner rule).  Arcs: valid for convex tables
    (stadium, lemon).  Lattices: flights are cut into pieces spanning at most one
    cell (:func:`_lattice_pieces`), each checked against every copy reaching the
    5 x 5 cells around its start cell.
    """
    if len(ds.t) < 2:
        return 0.0
    flights = _flight_arrays(scene, ds)
    ax, ay = scene.force
    reflex = _reflex_ends(scene.elements) if scene.lattice is None else set()
    if scene.lattice is None:
        copies = _element_copies(scene)
    else:
        from noslipsim._engine.lattice import lattice_matrix
        A, _ = lattice_matrix(scene.lattice)
        copies = [(k, e.shifted(*(A @ np.array([i, j], float))))
                  for i in range(-2, 3) for j in range(-2, 3) for k, e in _element_copies(scene)]
    worst = 0.0
    n = len(flights[-1])
    def batches():
        for s in range(0, n, chunk):
            part = tuple(a[s:s + chunk] for a in flights)
            if scene.lattice is None:
                yield part
            else:
                yield from _lattice_pieces(scene, *part, batch=2 * chunk)

    for X, Y, VX, VY, T in batches():
        x0, y0, x1, y1 = _flight_boxes(X, Y, VX, VY, T, ax, ay)
        # the flight's length scale: the scene's, or its farthest point's
        length = np.maximum(scene.scale, np.max(np.abs([x0, y0, x1, y1]), axis=0))
        margin = 1e-9 * length
        for k, e in copies:
            if e.type_name == "line":
                sel = slice(None)
            else:
                bx0, by0, bx1, by1 = e.bbox()
                near = (x0 <= bx1 + margin) & (x1 >= bx0 - margin) & (y0 <= by1 + margin) & (y1 >= by0 - margin)
                if e.type_name in ("circle", "arc") and e.side == "inside":
                    near = np.ones_like(near)  # a container is left by going outside its box
                sel = np.flatnonzero(near)
                if not len(sel):
                    continue
            args = (X[sel], Y[sel], VX[sel], VY[sel], T[sel], ax, ay)
            L = length[sel]
            tol = 1e-11 * L
            if e.type_name in ("line", "segment"):
                p = _straight_penetration(e, *args, tol, ((k, 0) in reflex, (k, 1) in reflex))
            else:
                p = _round_penetration(e, *args, tol, samples)
            worst = min(worst, float((p / L).min()))
    return worst


def outward_normals(scene, ds):
    """Outward unit normal (out of the table) of the element hit, at each collision point.

    Lattices: at the nearest copy of the element, in the cell frame.
    """
    x, y, _ = cell_frame(scene, ds)
    pts = np.c_[x, y]
    n = np.full((len(pts), 2), np.nan)
    el = ds.element.values
    copies = _element_copies(scene)
    for i in range(len(scene.elements)):
        sel = np.flatnonzero(el == i)
        if not len(sel):
            continue
        mine = [e for k, e in copies if k == i]
        d = np.stack([_piece_distance(e, pts[sel]) for e in mine])
        pick = np.argmin(d, axis=0)
        for c, e in enumerate(mine):
            rows = sel[pick == c]
            if e.type_name == "line":
                n[rows] = -np.array(e.normal)
            elif e.type_name == "segment":
                _, _, nx, ny, _ = e._frame()
                n[rows] = (-nx, -ny)
            else:
                r = pts[rows] - np.array(e.center)
                n[rows] = -e.sigma * r / np.hypot(r[:, 0], r[:, 1])[:, None]
    return n


def law_residual(scene, ds):
    """Largest violation of the collision law over the log, relative to ``|(v, w)|``.

    With ``n`` the outward normal at the logged point and ``t = J n``: specular
    keeps ``v_t`` and ``w`` and reverses ``v_n``; no-slip maps
    ``(w, v_t) -> (-c w - s v_t, -s w + c v_t)`` and reverses ``v_n``.  For
    ``gamma > 0`` this is the exact reversal of the contact velocity ``v_t + w / gamma``.
    """
    if not len(ds.t):
        return 0.0
    n = outward_normals(scene, ds)
    tx, ty = -n[:, 1], n[:, 0]
    vin = np.c_[ds.vx_in.values, ds.vy_in.values]
    vout = np.c_[ds.vx.values, ds.vy.values]
    win, wout = ds.spin_in.values, ds.spin.values
    vt0, vn0 = vin[:, 0] * tx + vin[:, 1] * ty, vin[:, 0] * n[:, 0] + vin[:, 1] * n[:, 1]
    vt1, vn1 = vout[:, 0] * tx + vout[:, 1] * ty, vout[:, 0] * n[:, 0] + vout[:, 1] * n[:, 1]
    if scene.law == "specular":
        res = [vt1 - vt0, wout - win, vn1 + vn0]
    else:
        g = scene.gamma
        c, s = (1 - g * g) / (1 + g * g), 2 * g / (1 + g * g)
        res = [wout - (-c * win - s * vt0), vt1 - (-s * win + c * vt0), vn1 + vn0]
    speed = np.sqrt(vin[:, 0] ** 2 + vin[:, 1] ** 2 + win ** 2)
    return float((np.max(np.abs(res), axis=0) / speed).max())


def incidence_sine(scene, ds):
    """``|v_in . n| / |v_in|`` at each collision: the sine of the angle between velocity and boundary."""
    n = outward_normals(scene, ds)
    vx, vy = ds.vx_in.values, ds.vy_in.values
    return np.abs(vx * n[:, 0] + vy * n[:, 1]) / np.hypot(vx, vy)


def log_floor(scene, ds):
    """Measurement floor of distances read from a log, relative to the scene's scale.

    Lattice logs store unfolded positions rounded to float64: a position in its
    cell's frame carries half an ulp of the unfolded coordinate per component.
    """
    if scene.lattice is None or not len(ds.t):
        return 0.0
    big = max(float(np.abs(ds.x.values).max()), float(np.abs(ds.y.values).max()))
    return 2.0 * np.finfo(float).eps * big / scene.scale


def cyclotron_miss(nodes, times, x, y, W):
    """Largest distance of the points ``(x, y)`` at ``times`` from the cyclotron circle of their flight.

    The flight from node ``k`` (``t, x, y, vx, vy``) in a field ``W`` runs on the circle of radius
    ``|v_k| / |W|`` about ``q_k + J v_k / W``, ``J(a, b) = (-b, a)`` (docs/scenes.md); a point drawn on
    the chord or a parabola instead misses it.  A point at a collision time belongs to the flight it ends
    or begins: both circles pass through it, so the later one is taken.
    """
    t0 = np.asarray(nodes["t"], dtype=float)
    k = np.searchsorted(t0, np.asarray(times, dtype=float), side="right") - 1
    qx, qy, vx, vy = (np.asarray(nodes[c], dtype=float)[k] for c in ("x", "y", "vx", "vy"))
    cx, cy = qx - vy / W, qy + vx / W
    return float(np.max(np.abs(np.hypot(np.asarray(x) - cx, np.asarray(y) - cy) - np.hypot(vx, vy) / abs(W))))
