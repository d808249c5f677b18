"""Long names and units of every dataset variable and coordinate, declared once (docs/datasets.md).

:data:`VARIABLES` is the one table of every variable and coordinate name a
noslipsim dataset writes (:func:`noslipsim.simulate`, :func:`noslipsim.simulate_many`,
reference orbits, :mod:`noslipsim.sphere3d` and every function of
:mod:`noslipsim.experiments`), and :func:`annotate` the one function that
attaches it; no other module spells out a ``long_name`` or ``units``.  The
variable list of docs/datasets.md is generated from it (:func:`markdown_table`).

Lengths, times and speeds are in the units of the scene (nondimensional:
``"1"``); angles are ``"rad"``, or ``"degree"`` where the code computes degrees.
Spin is the scaled spin ``w = gamma R omega`` (a speed).  One name, one
meaning: a name written by several functions means the same thing in all of
them.  Long names do not embed run parameters: where a quantity depends on
one (the collisions of a finite-time exponent), the long name names the
dataset attribute that holds it.

Two rules cover the names the table does not list one by one:

* :data:`ALIASES`: a name that means exactly what another entry means
  (``kind`` is ``linear_kind``) takes that entry.
* The case dimension of :func:`noslipsim.experiments.portrait_set` is named by
  the caller (``dim=``): its coordinate takes the table's entry for that name
  if there is one (``gamma``, ``force``, ``table``), else the entry of
  ``case`` (:func:`annotate` with ``case_dim``).
"""

VARIABLES = {
    # ------------------------------------------------ one orbit: simulate, reference orbits, simulate_many log
    "collision": ("collision index, from 0 (sphere3d: the bounce)", "1"),
    "t": ("time of the collision", "1"),
    "x": ("x position at the collision", "1"),
    "y": ("y position at the collision", "1"),
    "vx": ("x velocity just after the collision", "1"),
    "vy": ("y velocity just after the collision", "1"),
    "spin": ("scaled spin gamma R omega just after the collision (CCW positive; sphere3d: the vector W)", "1"),
    "vx_in": ("x velocity just before the collision", "1"),
    "vy_in": ("y velocity just before the collision", "1"),
    "spin_in": ("scaled spin gamma R omega just before the collision (CCW positive; sphere3d: the vector W)", "1"),
    "element": ("index of the element hit, in scene order", "1"),
    "s": ("arclength coordinate of the collision on its element", "1"),
    "corner": ("1 if the collision was resolved by the corner rule, else 0", "1"),
    "energy": ("energy (|v|^2 + w^2)/2 - a.q just after the collision", "1"),
    "cell_a1": ("lattice cell index along a1 at the collision", "1"),
    "cell_a2": ("lattice cell index along a2 at the collision", "1"),
    "t_final": ("time at the end of the orbit", "1"),
    "x_final": ("x position at the end of the orbit", "1"),
    "y_final": ("y position at the end of the orbit", "1"),
    "vx_final": ("x velocity at the end of the orbit", "1"),
    "vy_final": ("y velocity at the end of the orbit", "1"),
    "spin_final": ("scaled spin at the end of the orbit", "1"),
    "cell_a1_final": ("lattice cell index along a1 at the end of the orbit", "1"),
    "cell_a2_final": ("lattice cell index along a2 at the end of the orbit", "1"),
    "n_collisions": ("number of collisions", "1"),
    # ------------------------------------------------ many orbits: simulate_many, orbit_set
    "orbit": ("orbit index", "1"),
    "stop_reason": ("why the orbit ended", "1"),
    "n_corner": ("number of collisions resolved by the corner rule", "1"),
    "n_points": ("number of phase-portrait points recorded", "1"),
    "w_unit": ("post-collision scaled spin over |(w, v_t, v_n)|", "1"),
    "vt_unit": ("post-collision tangential velocity over |(w, v_t, v_n)| (t = J n)", "1"),
    "vn_unit": ("post-collision normal velocity over |(w, v_t, v_n)| (n outward, so <= 0)", "1"),
    "x_start": ("x position at the start", "1"),
    "y_start": ("y position at the start", "1"),
    "vx_start": ("x velocity at the start", "1"),
    "vy_start": ("y velocity at the start", "1"),
    "spin_start": ("scaled spin at the start (CCW positive)", "1"),
    "scene": ("the scene as JSON (docs/scenes.md)", "1"),
    "law": ("collision law", "1"),
    "gamma": ("mass-distribution constant gamma (NaN: specular, where it plays no part)", "1"),
    # ------------------------------------------------ sphere3d
    "component": ("Cartesian component (z up, plane z = 0)", "1"),
    "time": ("time since the start (sphere3d: of the bounce)", "1"),
    "position": ("position of the sphere's centre at the bounce (z = 0)", "1"),
    "velocity": ("velocity just after the bounce", "1"),
    "velocity_in": ("velocity just before the bounce", "1"),
    # ------------------------------------------------ experiments.galton
    "x_terminal": ("horizontal displacement at the terminal depth", "1"),
    "t_terminal": ("time of arrival at the terminal depth", "1"),
    "arrived": ("1 if the particle reached the terminal depth by max_time", "1"),
    "x_end": ("horizontal displacement where the orbit ended (terminal depth or max_time)", "1"),
    "y_end": ("vertical displacement where the orbit ended (terminal depth or max_time)", "1"),
    "share_not_arrived": ("share of particles not at the terminal depth by max_time (along time: by that time)",
                          "1"),
    "radius": ("disk radius (Galton pegs; Sinai disks on the unit torus; the two disks of a stability grid, "
               "centres 2 apart)", "1"),
    "group": ("the setting a Galton evidence case varies (drop, point, spread, speed, radius, rows, width)", "1"),
    "board": ("Galton board: 'bounded' (a top row with nothing above it) or 'unbounded' (the lattice continues up)",
              "1"),
    "start_x": ("x of the release point (the centre of the release spread)", "1"),
    "start_y": ("y of the release point (the centre of the release spread)", "1"),
    "spread": ("half-width of the square of release points around the release point", "1"),
    "speed": ("release speed (uniformly random direction)", "1"),
    "rows": ("peg rows to the terminal depth", "1"),
    "width": ("half-width of a walled Galton board, side walls at x = -width and x = width (0: no walls)", "1"),
    "wall_law": ("collision law of a Galton board's side walls ('none': no walls, 'pegs': the pegs' law)", "1"),
    "max_time": ("time limit of the case's run", "1"),
    # ------------------------------------------------ experiments.portraits
    "case": ("the experiment case of the entry (its name, label or index)", "1"),
    "table": ("name of the table", "1"),
    "force": ("force strength g: the force is (0, -g) per unit mass", "1"),
    "force_x": ("force per unit mass, x component", "1"),
    "force_y": ("force per unit mass, y component", "1"),
    "sides": ("number of sides of the polygon", "1"),
    "cell": ("closed: hexagonal cell with no-slip walls; periodic: the hexagonal Lorentz gas (both free fall)",
             "1"),
    "reading_table": ("the table, collision law and flight of the reading", "1"),
    "s_boundary": ("arclength along the boundary (chosen elements end to end, scene order)", "1"),
    "sin_angle": ("Birkhoff p: sine of the exit angle to the inward normal, positive along increasing s "
                  "(NaN: not specular)", "1"),
    "boundary_length": ("length of the recorded boundary", "1"),
    "ftle": ("finite-time Lyapunov exponent per collision over lyapunov_collisions collisions "
             "(a dataset attribute; NaN: corner)", "1"),
    "kinetic_final": ("kinetic energy (|v|^2 + w^2)/2 after energy_collisions collisions (a dataset attribute) "
                      "from the same starts on the disk (start: 1/2)", "1"),
    "head_on_onset": ("gamma above which the head-on 2-periodic orbit between neighbouring disks is elliptic, "
                      "sqrt(1/(2R) - 1)", "1"),
    # ------------------------------------------------ experiments.orbits
    "role": ("what the orbit shows in the figure", "1"),
    "scatterer_collision": ("index of the first collision with the scatterer (-1: none)", "1"),
    "exit_from_vertical": ("angle of the velocity leaving the scatterer from the vertical", "degree"),
    "exit_to_corner": ("angle between the velocity leaving the scatterer and the direction of the upper left "
                       "corner", "degree"),
    "periodic_iterations": ("Newton steps of the periodic-orbit finder", "1"),
    "rotation_angle": ("argument of the complex eigenvalue pair of the periodic orbit's monodromy", "rad"),
    "corridor_width": ("largest distance of a corridor-orbit collision from the periodic orbit's collision points",
                       "1"),
    "spin_ratio": ("gamma w / v_x at the start", "1"),
    "drift": ("mean displacement of the bounce point per two bounces", "1"),
    "drift_spread": ("largest deviation of one two-bounce displacement from their mean (drift)", "1"),
    "drift_theory": ("drift per two bounces, 4 u (v_T - gamma n x W_T)/(g (1+gamma^2))", "1"),
    "drift_error": ("largest deviation of one two-bounce displacement from the formula (drift_theory)", "1"),
    "back_and_forth": ("1 if consecutive flights move in opposite horizontal directions", "1"),
    "q0_x": ("x of the launch point q0", "1"),
    "q0_y": ("y of the launch point q0", "1"),
    "q1_x": ("x of the far point q1", "1"),
    "q1_y": ("y of the far point q1", "1"),
    "vertex_x": ("x of the (tangential) wedge's vertex", "1"),
    "vertex_y": ("y of the (tangential) wedge's vertex", "1"),
    "box_collisions": ("collisions with the box walls", "1"),
    "eigen_sum_theory": ("lambda + 1/lambda from the closed form (Cox, Feres & Zhang 2018)", "1"),
    "e1": ("unit drift direction e1 = D/|D|", "1"),
    "e2": ("tangential direction e2 = n x e1 (2-periodic motion)", "1"),
    "along_e1": ("bounce point along e1", "1"),
    "along_e2": ("bounce point along e2", "1"),
    # ------------------------------------------------ experiments.stability (and the wedges of experiments.orbits)
    "phi": ("wedge half-angle, wall to bisector (two disks: of the tangential wedge)", "rad"),
    "theta": ("launch angle at q0 above the chord q0 q1, horizontal in a wedge (NaN: not a path-reversing launch)",
              "rad"),
    "ell": ("distance of the launch point q0 from the wedge's vertex (NaN: not a path-reversing launch)", "1"),
    "opening": ("which way the wedge opens (force (0, -g) in both)", "1"),
    "period": ("collisions per period", "1"),
    "minimal_period": ("smallest number of collisions after which the run's state repeats", "1"),
    "residual": ("periodicity residual max(|ds|/L, |dw|/V, |dv_t|/V) after one period", "1"),
    "linear_kind": ("linear class of the periodic orbit's monodromy over one period (elliptic, hyperbolic, "
                    "parabolic; '' where the orbit does not exist)", "1"),
    "eigen_sum": ("lambda + 1/lambda of the periodic orbit's monodromy over one period (trace minus the "
                  "eigenvalue closest to 1)", "1"),
    "lambda_max": ("largest |eigenvalue| of the periodic orbit's monodromy over one period", "1"),
    "eigenvalue_real": ("real part of the eigenvalues of the periodic orbit's monodromy over one period, by "
                        "decreasing modulus", "1"),
    "eigenvalue_imag": ("imaginary part of the eigenvalues of the periodic orbit's monodromy over one period, by "
                        "decreasing modulus", "1"),
    "unit_count": ("eigenvalues equal to 1 (a family direction at fixed energy)", "1"),
    "identity_distance": ("max |M - I| (0 for a persistently periodic neighbourhood)", "1"),
    "reversal_mismatch": ("max over one period of |v_t - gamma w| / speed just before an impact "
                          "(0: every impact reverses the path)", "1"),
    "path_reversing": ("1 if every impact of a period reverses the path", "1"),
    "family_distance": ("distance (scaled like the residual) of the periodic orbit found from family_step "
                        "along the eigenvalue-1 direction (NaN: no eigenvalue 1)", "1"),
    "family_rotation": ("largest eigenvalue argument of that neighbouring orbit's monodromy", "rad"),
    "deviation": ("distance from the periodic orbit's impact on the same wall, max(|ds|/ell, |dw|/V, |dv_t|/V)",
                  "1"),
    "theta_transition": ("launch angle where the linear class first changes from elliptic to hyperbolic "
                         "(lambda + 1/lambda = 2)", "rad"),
    "theta_parallel": ("pi/2 - phi: launch parallel to the far wall", "rad"),
    # ------------------------------------------------ noslipsim lyapunov (a scene file's orbit)
    "lyapunov_exponent": ("largest Lyapunov exponent of the orbit per unit time (Benettin; the lyapunov_method "
                          "attribute says how: tangent, the exact tangent map, or twin, a twin orbit)", "1"),
    "lyapunov_per_collision": ("largest Lyapunov exponent of the collision map, per collision", "1"),
    "lyapunov_running": ("running estimate of the largest Lyapunov exponent per unit time after each block", "1"),
    "elapsed_time": ("time from the first collision to the end of each block of the Lyapunov run", "1"),
    "mean_free_time": ("mean time between collisions of the Lyapunov run", "1"),
    # ------------------------------------------------ analysis: Galton arrival curves (analysis.galton)
    "share_not_arrived_stderr": ("binomial standard error of share_not_arrived", "1"),
    "n_particles": ("number of particles", "1"),
    "share_not_arrived_final": ("share of particles not at the terminal depth by max_time", "1"),
    "arrivals_early": ("arrivals in the earlier tail window [t1, t2)", "1"),
    "arrivals_late": ("arrivals in the later tail window [t2, t3]", "1"),
    "tail_ratio": ("ratio q of late to early tail-window arrivals", "1"),
    "tail_exponent": ("power-law exponent alpha of the arrival tail, S - P ~ t^-alpha", "1"),
    "trapped_share": ("estimated share of particles that never arrive (plateau of S)", "1"),
    "trapped_share_stderr": ("standard error of trapped_share (Poisson counts, delta method)", "1"),
    "slow_share": ("share not arrived by max_time that the tail extrapolation expects to arrive", "1"),
    # ------------------------------------------------ analysis: two-disk stability grids (analysis.stability)
    "curvature": ("disk curvature kappa = 1/R", "1"),
    "survived": ("1 if the perturbed orbit reached max_collisions, else 0", "1"),
    "chord_length": ("distance d = |q0 q1| = 2 - 2 R cos(phi)", "1"),
    "radius_threshold": ("force-free ellipticity threshold R*(phi): elliptic iff R > R* (closed form; a reference "
                         "only under gravity)", "1"),
    # ------------------------------------------------ experiments.readings: Figure 15 under other readings
    "reading": ("name of a reading of one of the paper's experiments (Figure 15: experiments.readings.READINGS; "
                "Figure 13's table: experiments.HEX_READINGS)", "1"),
    "reading_description": ("what the reading changes from ours, in words", "1"),
    "reading_options": ("the reading's options as JSON (keys of experiments.readings.BASE)", "1"),
    "collision_cap": ("collisions a run may reach (survived: reached it)", "1"),
    "launched": ("1 if the reading launches an orbit at this theta, else 0 (elevation outside (0, pi/2))", "1"),
    "theta_read": ("the paper's launch angle theta, as each reading reads it (launch_elevation: the elevation it "
                   "gives)", "rad"),
    "launch_elevation": ("elevation of the launch at q0 above the chord q0 q1", "rad"),
    "position_angle": ("angle of q0 above the horizontal, seen from the left disk's centre", "rad"),
    "lambda_at_paper_theta": ("largest eigenvalue modulus |lambda| of the two-disk 2-periodic orbit's monodromy at "
                              "the paper's launch angle theta = 1.3 (experiments.readings.lambda_at)", "1"),
    # ------------------------------------------------ analysis: regular orbits (analysis.islands)
    "regular": ("1 if ftle < the dataset's regular_threshold (an orbit on an invariant torus), else 0", "1"),
    "share_regular": ("share of orbits with ftle < regular_threshold (regular)", "1"),
    "share_regular_stderr": ("binomial standard error of share_regular", "1"),
    "n_regular": ("orbits with ftle below regular_threshold", "1"),
    "n_valid": ("orbits with an exponent", "1"),
    # ------------------------------------------------ analysis: attracting cycles (analysis.attractors)
    "attractor_period": ("recorded collisions per cycle of the attracting periodic orbit the orbit ends on "
                         "(0: none within the dataset's attractor_tolerance)", "1"),
    "attractor": ("which attracting periodic orbit the orbit ends on, numbered by the orbits it holds, most "
                  "first (-1: none)", "1"),
    "onset_gamma": ("smallest gamma with share_regular >= the dataset's visible_share (linear interpolation)", "1"),
    "onset_gamma_stderr": ("bootstrap standard deviation of onset_gamma", "1"),
    "onset_gamma_low": ("16th percentile of the bootstrap onsets", "1"),
    "onset_gamma_high": ("84th percentile of the bootstrap onsets", "1"),
    # ------------------------------------------------ experiments.conjectures (Figures S4, S5)
    "n_classes": ("distinct linear classes of the orbit along the launch angle", "1"),
    "class_changes": ("1 if the linear class changes with the launch angle alone", "1"),
    "elliptic_hyperbolic": ("1 if the orbit is elliptic at one launch angle and hyperbolic at another", "1"),
    "elliptic_hyperbolic_below": ("1 if elliptic and hyperbolic both occur at launch angles below the parabolic line "
                                  "theta < pi/2 - phi - margin", "1"),
    "boundary": ("measured elliptic boundary R_e(phi): largest radius where lambda + 1/lambda falls through 2 "
                 "(NaN: none, or phi + theta near pi/2)", "1"),
    "radius_shift": ("R*(phi) - R_e(phi): how far the force moves the elliptic boundary (positive: to smaller "
                     "disks)", "1"),
    "search": ("search of the periodic-orbit finder, from one random start", "1"),
    "force_angle": ("direction of the force, counter-clockwise from straight down", "rad"),
    "outcome": ("how the search ended (found, not converged, no return), the pair (found, not found, not "
                "periodic, not minimal, unbalanced, inaccessible) or the start (invariant, attracted, escaped, "
                "stopped)", "1"),
    "isolated": ("1 if the orbit found has no eigenvalue 1 over its minimal period, 0 if it has, -1 if none "
                 "found", "1"),
    "itinerary": ("walls hit over one minimal period (L left, R right)", "1"),
    "distinct": ("1 on the first search that found its orbit (up to the wedge's scaling), else 0", "1"),
    # ------------------------------------------------ experiments.accessible (Figure S6)
    "pair": ("pair of boundary points", "1"),
    "sample": ("how the pair was drawn: random (both points at random) or balanced (q1 solves beta = 0)", "1"),
    "element0": ("element of q0", "1"),
    "element1": ("element of q1", "1"),
    "s0": ("arclength coordinate of q0 on its element", "1"),
    "s1": ("arclength coordinate of q1 on its element", "1"),
    "balance": ("beta = ((d.n1)(a.n0) + (d.n0)(a.n1)) / (|d| |a|): 0 on a pair that can carry a non-path-reversing "
                "2-periodic orbit", "1"),
    "mirror": ("1 if q0 and q1 are mirror images about a line along the force (points and normals)", "1"),
    "reason": ("why the pair is inaccessible or no orbit was found ('' otherwise)", "1"),
    "family": ("1 if the two-flight equations hold for every flight time (a one-parameter family)", "1"),
    "n_candidates": ("flight-time pairs solving the two-flight equations (family: the members tried)", "1"),
    "n_found": ("candidates the engine and the finder confirm as 2-periodic between q0 and q1", "1"),
    "n_elliptic": ("confirmed orbits that are elliptic", "1"),
    "n_hyperbolic": ("confirmed orbits that are hyperbolic", "1"),
    "n_parabolic": ("confirmed orbits that are parabolic", "1"),
    "flight_time": ("flight time T from q0 to q1 of the orbit kept (the pair's with the most even flights)", "1"),
    "flight_time_back": ("flight time T' from q1 back to q0 of the orbit kept", "1"),
    # ------------------------------------------------ experiments.invariant (Figure S7)
    "flight": ("flight between collisions: free fall (energy conserved) or isokinetic (the thermostat)", "1"),
    "branch": ("which orbit of the flight: low or high launch angle (free fall), apex (isokinetic)", "1"),
    "ring": ("ring of starts around the orbit, numbered outwards", "1"),
    "ring_radius": ("radius of the ring in the (turn angle, spin / speed) plane of the orbit's apex state", "1"),
    "start": ("start on its ring, at evenly spaced angles", "1"),
    "start_outcome": ("what became of the start: index into the outcome axis (0 invariant, 1 attracted, "
                      "2 escaped, 3 stopped for another reason; -1 no orbit)", "1"),
    "tail_distance": ("largest max-norm distance of a survivor's last collisions (element, s, unit v_t, unit w) "
                      "from the orbit's own collision states (NaN: escaped)", "1"),
    "exists": ("1 if the flight has this orbit at this force, else 0", "1"),
    "orbit_period": ("period of the unperturbed orbit's last collisions (2: it stayed on its cycle; 0: none)", "1"),
    "region_radius": ("largest ring radius out to which every start neither escapes nor converges", "1"),
    "region_area": ("pi region_radius^2, in the (turn angle, spin / speed) plane", "1"),
    "staying_area": ("sum over rings of the share of starts that stay times the ring's annulus", "1"),
    "starts_by_outcome": ("starts of the ring by outcome", "1"),
}

#: Names that mean exactly what another entry means, and take its entry.
ALIASES = {
    "kind": "linear_kind",              # two_disk_box_orbits: the class of the periodic start
    "periodic_kind": "linear_kind",     # pentagon_orbits: the class of the periodic orbit found
    "periodic_residual": "residual",    # pentagon_orbits: the finder's residual
}

VARIABLES.update({alias: VARIABLES[name] for alias, name in ALIASES.items()})


def entry(name, case_dim=None):
    """``(long_name, units)`` of a variable or coordinate name, ``None`` if it has none (module rules)."""
    if name in VARIABLES:
        return VARIABLES[name]
    if case_dim is not None and name == case_dim:
        return VARIABLES["case"]
    return None


def annotate(ds, case_dim=None):
    """Attach ``long_name`` and ``units`` to every known variable and coordinate of ``ds`` (in place); return it.

    Attributes a variable already has are kept (``setdefault``).  ``case_dim``
    names a case dimension chosen by the caller (``portrait_set``'s ``dim``):
    without an entry of its own it is described as ``case``.
    """
    for name, var in ds.variables.items():
        meta = entry(name, case_dim)
        if meta is not None:
            var.attrs.setdefault("long_name", meta[0])
            var.attrs.setdefault("units", meta[1])
    return ds


def long_name(var, default=""):
    """The ``long_name`` of a dataset variable (for axis labels), ``default`` if it has none."""
    return var.attrs.get("long_name", default)


def markdown_table():
    """The table as the Markdown list of docs/datasets.md (name, long name, units; aliases marked)."""
    rows = ["| name | long_name | units |", "|---|---|---|"]
    for name, (long_name, units) in VARIABLES.items():
        text = long_name.replace("|", "\\|")
        if name in ALIASES:
            text = f"as `{ALIASES[name]}`: {text}"
        rows.append(f"| `{name}` | {text} | `{units}` |")
    return "\n".join(rows) + "\n"
