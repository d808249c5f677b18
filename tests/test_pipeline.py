"""The figure pipeline end to end: the reduced run (.test) in a temporary copy of the repository.

Every dataset opens with xarray and carries its provenance and sane values; every figure exists as
PDF and PNG and is byte-identical when redrawn; changing one config value reruns only what depends
on it; `snakemake --lint` is clean; the report builds.  Checks are generic over whatever the
workflow produces, so a new dataset or figure is covered without editing this file; a dataset
with properties of its own registers a check in DATASET_CHECKS.
"""
import hashlib
import json
import math
import re
from pathlib import Path

import numpy as np
import pytest
import xarray as xr
from pipeline_run import ROOT, snakemake, workflow_copy  # the fixture repo: conftest.py

from noslipsim.plot import numbers_markdown

GLOBAL_ATTRS = ("title", "source", "history", "references", "config")
#: Rounding slack for unit vectors and shares.
TOL = 1e-9


@pytest.fixture(scope="module")
def reruns(tmp_path_factory, repo):
    """The datasets again in a fresh copy, one job at a time and in reverse order, from the numba cache the
    first run filled (the session's): each job's process loads kernel variants that other processes
    compiled, in another order (the compile-cache issue's failure: a variant's physics depending on which
    process compiled what).

    Only the datasets: the figures are drawn from them (the first run checks the drawing).  A second
    run from another empty cache (-j2) was dropped: it repeated the first run's compiles for 4 CI
    minutes; tests/test_compile_cache.py compiles every variant in its own process and fresh cache and
    loads them in both orders.
    """
    datasets = sorted((p.relative_to(repo / ".test").as_posix() for p in (repo / ".test" / "results").rglob("*.nc")),
                      reverse=True)
    single = workflow_copy(tmp_path_factory, "pipeline-single")
    snakemake(single, "--cores", "1", *datasets)
    return {"-j1, reverse order, the cache the first run filled": single}


def summary(repo):
    """``{output file: rule}`` of every job of the workflow (snakemake --summary)."""
    lines = snakemake(repo, "--summary").stdout.splitlines()
    start = next(i for i, line in enumerate(lines) if line.startswith("output_file"))
    out = {}
    for line in lines[start + 1:]:
        cols = line.split("\t")
        if len(cols) >= 3:
            out[cols[0]] = cols[2]
    return out


def digests(folder):
    return {p.name: hashlib.sha256(p.read_bytes()).hexdigest() for p in sorted(folder.iterdir()) if p.is_file()}


# ---------------------------------------------------------------- dataset checks
def check_galton_distribution(ds):
    assert set(ds.x_terminal.dims) == {"law", "particle"} and set(ds.law.values) == {"specular", "no-slip"}
    arrived = ds.arrived.values.astype(bool)
    assert np.isfinite(ds.x_terminal.values[arrived]).all() and np.isnan(ds.x_terminal.values[~arrived]).all()
    assert (ds.t_terminal.values[arrived] <= ds.attrs["max_time"]).all()
    assert np.isnan(ds.gamma.sel(law="specular")).all() and np.isfinite(ds.gamma.sel(law="no-slip")).all()


def check_galton_orbits(ds):
    assert ds.sizes["orbit"] >= 1 and (ds.n_collisions > 0).all()
    assert (ds.stop_reason.values.astype(str) != "").all()
    for i in range(ds.sizes["orbit"]):
        n = int(ds.n_collisions[i])
        assert np.isfinite(ds.x.values[i, :n]).all() and np.isnan(ds.x.values[i, n:]).all()
    # orbits end at the terminal depth or above it
    assert (ds.y_final >= ds.attrs["stop_below"] - TOL).all()


def check_galton_sweep(ds):
    assert "radius" in ds.dims and (np.diff(ds.radius.values) > 0).all()
    assert (2 * ds.radius < ds.attrs["spacing"]).all()


def check_galton_evidence(ds):
    assert {"case", "law", "particle"} <= set(ds.t_terminal.dims) and set(ds.law.values) == {"specular", "no-slip"}
    t, x = ds.t_terminal.values, ds.x_terminal.values
    assert (np.isnan(t) == np.isnan(x)).all() and (t[np.isfinite(t)] <= ds.attrs["max_time"]).all()
    assert set(ds.board.values) <= {"bounded", "unbounded"}
    if "gap" in ds.case.values:  # energy keeps a particle dropped in a top gap below the row above: the same orbits
        assert str(ds.board.sel(case="gap").values) == "unbounded"
        assert str(ds.board.sel(case="gap-bounded").values) == "bounded"
        np.testing.assert_array_equal(ds.t_terminal.sel(case="gap").values,
                                      ds.t_terminal.sel(case="gap-bounded").values)


def _row(ds, role):
    return ds.isel(orbit=list(ds.role.values).index(role))


def check_orbits_specnoslip(ds):
    # the caption's claims: specular leaves the scatterer nearly vertically, no-slip heads to the upper left corner
    spec, noslip = _row(ds, "specular"), _row(ds, "no-slip")
    assert float(spec.exit_from_vertical) < 10.0 and float(noslip.exit_to_corner) < 10.0
    k = int(spec.scatterer_collision)
    assert k == int(noslip.scatterer_collision) >= 0
    np.testing.assert_array_equal(spec.x.values[:k + 1], noslip.x.values[:k + 1])   # identical until the disk
    assert (spec.spin.values[np.isfinite(spec.spin.values)] == float(spec.spin_start)).all()


def check_orbits_pentagons(ds):
    assert str(ds.periodic_kind.values) == "elliptic"
    assert float(ds.periodic_residual) <= ds.attrs["tol"] and int(ds.attrs["period"]) == 14
    assert 0.0 < float(ds.corridor_width) < 0.2                     # the perturbed orbit stays in a corridor
    assert int(_row(ds, "no-slip periodic").n_collisions) == 14


def check_orbits_bounce(ds):
    from noslipsim.theory import half_plane_drift

    g, gamma = ds.attrs["gravity"], ds.attrs["gamma"]
    u = np.sqrt(2 * g * ds.y_start.values)                          # each orbit starts at a flight's apex
    want = half_plane_drift(ds.vx_start.values, ds.spin_start.values, u, gamma, g)
    np.testing.assert_allclose(ds.drift.values, want, atol=1e-10)
    assert (ds.drift_spread < 1e-10).all()
    assert (np.abs(ds.drift.values) < 1e-10).tolist() == list(ds.spin_ratio.values == 1.0)


def check_orbits_newwedge(ds):
    np.testing.assert_allclose(ds.x.values[:, 2:4], ds.x.values[:, 0:2], atol=1e-10)   # 2-periodic
    np.testing.assert_allclose(ds.x.values[:, 1], ds.q0_x.values, atol=1e-10)


def check_orbits_twodisks(ds):
    assert str(ds.kind.values) == "elliptic"
    assert float(ds.eigen_sum) == pytest.approx(float(ds.eigen_sum_theory), abs=1e-8)
    assert int(_row(ds, "no-slip").box_collisions) == 0 and int(_row(ds, "specular").box_collisions) > 0


def check_orbits_sphere(ds):
    np.testing.assert_allclose(ds.drift.values, ds.drift_theory.values, atol=1e-10)
    np.testing.assert_allclose(ds.along_e2.values[2:], ds.along_e2.values[:-2], atol=1e-10)
    assert float(np.hypot(*ds.drift_theory.values[:2])) > 0


def check_stability_wedge_orbits(ds):
    assert (ds.residual < 1e-10).all() and (ds.minimal_period == ds.period).all()
    reversing = np.char.startswith(ds.case.values.astype(str), "path-reversing")
    assert (ds.path_reversing.values[reversing] == 1).all() and (ds.path_reversing.values[~reversing] == 0).all()
    assert set(ds.linear_kind.values.astype(str)) <= {"elliptic", "hyperbolic", "parabolic"}


def check_stability_perturbed(ds):
    n = ds.sizes["orbit"] // 2
    assert list(ds.role.values.astype(str)) == ["periodic"] * n + ["perturbed"] * n
    assert (ds.n_collisions.values[:n] == 3).all() and (ds.n_collisions.values[n:] >= 1).all()
    assert np.nanmax(ds.deviation.values[:n]) < 1e-9                  # the periodic orbits close
    assert (ds.lambda_max >= 1 - 1e-9).all() and np.isfinite(ds.eigen_sum).all()


def check_stability_launch_scan(ds):
    assert np.isfinite(ds.eigen_sum).all() and set(ds.dims) == {"phi", "theta"}
    assert np.isfinite(ds.theta_transition).all()
    np.testing.assert_allclose(ds.theta_transition, ds.theta_parallel, atol=1e-9)


def check_stability_grid(ds):
    assert ds.n_collisions.dims[0] == "radius" and ((ds.radius > 0) & (ds.radius < 1)).all()
    n = ds.n_collisions.values
    assert ((n >= 0) & (n <= ds.attrs["max_collisions"])).all()
    assert set(np.unique(ds.survived.values)) <= {0, 1}
    assert set(ds.linear_kind.values.astype(str).ravel()) <= {"elliptic", "hyperbolic", "parabolic"}
    assert np.isfinite(ds.eigen_sum).all() and ((ds.radius_threshold > 0) & (ds.radius_threshold < 1)).all()
    assert 0 <= ds.attrs["agreement_share"] <= 1


def check_portraits(ds):
    """A portrait_set dataset (case, orbit, point): points on the boundary, exponents per orbit."""
    assert ds.vt_unit.dims[-2:] == ("orbit", "point") and ds.boundary_length.dims == ds.vt_unit.dims[:-2]
    s, L = ds.s_boundary.values, ds.boundary_length.values[..., None, None]
    known = np.isfinite(s)
    assert known.any() and ((s >= -TOL) & (s <= L + TOL))[known].all()
    assert (np.isfinite(ds.vt_unit.values) == known).all()
    assert (known.sum(axis=-1) == ds.n_points.values).all()
    assert "regular" not in ds and "regular_threshold" not in ds.attrs  # a reading, made by the figures
    if "ftle" in ds:
        assert np.isfinite(ds.ftle.values).mean() > 0.9      # NaN only for the rare corner collision
    if "sin_angle" in ds:
        p = ds.sin_angle.values
        assert (np.abs(p[np.isfinite(p)]) <= 1 + TOL).all()


def check_portraits_sinai_gamma(ds):
    check_portraits(ds)
    if 0.0 in ds.gamma.values:                              # gamma = 0 keeps |w| on every collision
        w = np.abs(ds.w_unit.sel(gamma=0.0).values)
        np.testing.assert_allclose(np.nanmax(w, axis=1), np.nanmin(w, axis=1), atol=1e-12)


def check_portraits_hex_force(ds):
    check_portraits(ds)
    disk = 6.0 if ds.attrs["reading"] in ("closed", "specular_walls") else 0.0
    assert set(np.unique(ds.element.values[np.isfinite(ds.element.values)])) == {disk}   # the disk only
    assert ds.cell.values.tolist() == ["closed", "periodic"]
    bound = 0.5 + ds.force * 2 / np.sqrt(3)                # kinetic energy in the closed cell, from E
    assert (ds.kinetic_final.sel(cell="closed") <= bound + TOL).all()


def check_portraits_hex_readings(ds):
    assert ds.ftle.dims == ("reading", "gamma", "force", "orbit")
    assert set(ds.reading.values) <= {"closed", "specular_walls", "periodic", "thermostat", "specular_thermostat"}
    assert np.isfinite(ds.ftle).mean() > 0.9                # NaN only for an orbit that stopped (corner)
    if "attractor_period" in ds:                            # cycles only where the flow contracts phase volume
        free_fall = [r for r in ds.reading.values if r not in ("thermostat", "specular_thermostat")]
        assert (ds.attractor_period.sel(reading=free_fall) == 0).all()
        assert ((ds.attractor >= 0) == (ds.attractor_period > 0)).all()
    if "specular_thermostat" in ds.reading.values:          # a specular disk: gamma plays no part
        gas = ds.ftle.sel(reading="specular_thermostat")
        assert np.array_equal(gas.isel(gamma=0), gas.isel(gamma=-1), equal_nan=True)
    if "specular_walls" in ds.reading.values and ds.sizes["gamma"] > 1:   # the disk is no-slip: gamma matters
        walls = ds.ftle.sel(reading="specular_walls")
        assert not np.array_equal(walls.isel(gamma=0), walls.isel(gamma=-1))


def check_portraits_islands(ds):
    from noslipsim.analysis import islands_onsets

    assert ds.ftle.dims == ("radius", "gamma", "orbit") and (np.diff(ds.gamma.values) > 0).all()
    np.testing.assert_allclose(ds.head_on_onset, np.sqrt(1 / (2 * ds.radius) - 1), rtol=1e-12)
    summary = islands_onsets(ds, 0.03)
    assert (summary.n_regular <= summary.n_valid).all()
    onset = summary.onset_gamma.values
    assert ((onset >= ds.gamma.values[0]) & (onset <= ds.gamma.values[-1]))[np.isfinite(onset)].all()


def check_conjectures_launch(ds):
    kinds = ds.linear_kind.values.astype(str)
    assert set(kinds.ravel()) <= {"elliptic", "hyperbolic", "parabolic", ""}
    assert (np.isfinite(ds.eigen_sum.values) == (kinds != "")).all()
    changes = ds.class_changes.values
    assert ((ds.elliptic_hyperbolic.values <= changes) & ((changes == 1) <= (ds.n_classes.values > 1))).all()
    assert ds.attrs["n_changing"] == changes.sum() <= ds.attrs["n_columns"]
    assert ((ds.radius_threshold > 0) & (ds.radius_threshold < 1)).all()


def check_conjectures_census(ds):
    from noslipsim.experiments import census_counts

    found = ds.outcome.values.astype(str) == "found"
    assert set(ds.outcome.values.astype(str)) <= {"found", "not converged", "no return"}
    assert ((ds.minimal_period.values > 0) == found).all() and (ds.residual.values[found] <= ds.attrs["tol"]).all()
    assert (ds.period.values[found] % ds.minimal_period.values[found] == 0).all()
    counts = census_counts(ds)
    assert int(counts.searches.sum()) == ds.sizes["search"]
    assert (counts.isolated + counts.family == counts.distinct).all()


def check_conjectures_invariant(ds):
    from noslipsim.experiments import region_counts

    exists = ds.exists.values == 1
    outcome = ds.start_outcome.values
    assert ((outcome >= 0).all(axis=(-2, -1)) == exists).all() and (outcome[~exists] == -1).all()
    per_orbit = ds.sizes["ring"] * ds.sizes["start"]
    assert (region_counts(ds).total.values == exists * per_orbit).all()
    assert (np.isfinite(ds.tail_distance.values) == (outcome == 0) | (outcome == 1)).all()
    assert ((outcome == 2) == (ds.stop_reason.values == 2)).all()      # escaped: stop reason 'escape'
    assert ((outcome >= 0) & (outcome <= 1) <= (ds.n_collisions.values == ds.attrs["max_collisions"])).all()
    radius = ds.region_radius.values[exists]
    assert ((radius >= 0) & (radius <= ds.ring_radius.values[-1] + 1e-12)).all()


#: Specific checks of the datasets that have them (path under results/ -> check); every dataset
#: also gets the generic checks of test_every_dataset_opens_with_provenance_and_sane_values.
DATASET_CHECKS = {
    "galton/distribution.nc": check_galton_distribution,
    "galton/arrivals.nc": check_galton_distribution,
    "galton/orbits.nc": check_galton_orbits,
    "galton/radius_sweep.nc": check_galton_sweep,
    "galton/rows.nc": check_galton_evidence,
    "galton/evidence.nc": check_galton_evidence,
    "orbits/specnoslip.nc": check_orbits_specnoslip,
    "orbits/pentagons.nc": check_orbits_pentagons,
    "orbits/bounce.nc": check_orbits_bounce,
    "orbits/newwedge.nc": check_orbits_newwedge,
    "orbits/twodisks.nc": check_orbits_twodisks,
    "orbits/sphere.nc": check_orbits_sphere,
    "stability/wedge_orbits.nc": check_stability_wedge_orbits,
    "stability/wedge_perturbed.nc": check_stability_perturbed,
    "stability/launch_orbits.nc": check_stability_perturbed,
    "stability/launch_scan.nc": check_stability_launch_scan,
    "stability/grid_noforce.nc": check_stability_grid,
    "stability/grid_force.nc": check_stability_grid,
    "stability/grid_theta.nc": check_stability_grid,
    "portraits/phaseportraits.nc": check_portraits,
    "portraits/polygons.nc": check_portraits,
    "portraits/sinai_gamma.nc": check_portraits_sinai_gamma,
    "portraits/islands.nc": check_portraits_islands,
    "portraits/hex_force.nc": check_portraits_hex_force,
    "portraits/hex_readings.nc": check_portraits_hex_readings,
    "conjectures/launch.nc": check_conjectures_launch,
    "conjectures/census.nc": check_conjectures_census,
    "conjectures/invariant.nc": check_conjectures_invariant,
}


def generic_checks(name, ds):
    for key in GLOBAL_ATTRS:
        assert ds.attrs.get(key), f"{name}: no global attribute {key!r}"
    assert ds.attrs["source"].startswith("noslipsim ")
    json.loads(ds.attrs["config"])
    for var_name, var in ds.variables.items():
        if var_name not in ds.dims:
            assert "long_name" in var.attrs and "units" in var.attrs, f"{name}: {var_name} lacks long_name/units"
        if var.dtype.kind != "f":
            continue
        values = var.values
        if var_name.startswith("share") and not var_name.endswith("stderr"):
            assert np.isfinite(values).all(), f"{name}: {var_name} has NaN"
            assert ((values >= -TOL) & (values <= 1 + TOL)).all(), f"{name}: {var_name} outside [0, 1]"
        if var_name in ds.coords and var_name not in ("gamma",):      # gamma is NaN for specular by design
            assert np.isfinite(values).all(), f"{name}: coordinate {var_name} has NaN"
        if var_name in ("n_collisions", "t_final", "x_final", "y_final"):
            assert np.isfinite(values).all(), f"{name}: {var_name} has NaN"
    if "vt_unit" in ds and "w_unit" in ds:                             # velocity portraits: the unit disk
        r = np.hypot(ds.vt_unit.values, ds.w_unit.values)
        assert (r[np.isfinite(r)] <= 1 + TOL).all(), f"{name}: portrait point off the unit disk"
    if "arrived" in ds:
        assert set(np.unique(ds.arrived.values)) <= {0, 1}


def test_every_dataset_opens_with_provenance_and_sane_values(repo):
    results = repo / ".test" / "results"
    found = sorted(p.relative_to(results).as_posix() for p in results.rglob("*.nc"))
    assert set(DATASET_CHECKS) <= set(found), f"missing datasets: {set(DATASET_CHECKS) - set(found)}"
    for name in found:
        with xr.open_dataset(results / name) as ds:
            ds.load()
        generic_checks(name, ds)
        if name in DATASET_CHECKS:
            DATASET_CHECKS[name](ds)


#: Attributes that say when and with what a dataset was made, not what it holds.
RUN_ATTRS = ("history", "software", "git_commit", "git_dirty")


def _science_attrs(ds):
    """The global attributes that describe what a dataset holds, as JSON (arrays as lists, NaN as NaN)."""
    return json.dumps({k: np.asarray(v).tolist() for k, v in ds.attrs.items() if k not in RUN_ATTRS},
                      sort_keys=True)


def holds_data(ds):
    """Some data variable has a finite float or, if not a float, any element."""
    return any(np.isfinite(v.values).any() if v.dtype.kind == "f" else v.size for v in ds.data_vars.values())


def test_datasets_do_not_depend_on_the_cache_or_the_order_of_jobs(repo, reruns):
    """Two runs (-j2, then -j1 from the cache it filled) of the reduced pipeline: data in every dataset, same bits."""
    results = repo / ".test" / "results"
    names = sorted(p.relative_to(results).as_posix() for p in results.rglob("*.nc"))
    assert len(names) >= len(DATASET_CHECKS)
    for name in names:
        first = xr.load_dataset(results / name)
        assert holds_data(first), f"{name}: no data"
        for label, other in reruns.items():
            second = xr.load_dataset(other / ".test" / "results" / name)
            assert holds_data(second), f"{name} ({label}): no data"
            xr.testing.assert_identical(first.drop_attrs(deep=False), second.drop_attrs(deep=False))
            assert _science_attrs(first) == _science_attrs(second), f"{name} ({label})"


# ---------------------------------------------------------------- figures
def test_every_figure_is_a_pdf_and_a_png_and_redraws_byte_identically(repo):
    outputs = summary(repo)
    figures = sorted({Path(f).stem for f in outputs if f.startswith("figures/fig")})
    assert figures, "the workflow makes no figure"
    for stem in figures:
        for ext in (".pdf", ".png"):
            path = repo / ".test" / "figures" / f"{stem}{ext}"
            assert path.is_file() and path.stat().st_size > 1000, f"{path.name} missing or empty"
        assert (repo / ".test" / "figures" / f"{stem}.pdf").read_bytes().startswith(b"%PDF")
        assert (repo / ".test" / "figures" / f"{stem}.png").read_bytes().startswith(b"\x89PNG")
    before = digests(repo / ".test" / "figures")
    rules = sorted({rule for f, rule in outputs.items() if f.startswith("figures/")})
    snakemake(repo, "--cores", "2", "--forcerun", *rules)
    after = digests(repo / ".test" / "figures")
    assert after == before, [k for k in before if before[k] != after.get(k)]


def test_numbers_are_gathered_and_rendered(repo):
    numbers = json.loads((repo / ".test" / "figures" / "numbers.json").read_text(encoding="utf-8"))
    assert "galton" in numbers and "share_not_arrived_noslip" in numbers["galton"]
    for records in numbers.values():
        for record in records.values():
            if isinstance(record["value"], float):
                assert math.isfinite(record["value"])
    table = (repo / ".test" / "figures" / "numbers.md").read_text(encoding="utf-8")
    assert table == numbers_markdown(numbers)


# ---------------------------------------------------------------- parameter tracking, lint, report
def planned_jobs(repo, *args):
    """``{rule: count}`` of a dry run (``args``: more snakemake options)."""
    out = snakemake(repo, "-n", "--cores", "2", *args).stdout
    jobs = {}
    table = re.search(r"job\s+count\n[-\s]+\n(.*?)\ntotal", out, re.S)
    if table:
        for line in table.group(1).splitlines():
            rule, count = line.split()
            jobs[rule] = int(count)
    return jobs


def test_changing_one_config_value_reruns_only_what_depends_on_it(repo):
    assert planned_jobs(repo) == {}                     # everything is up to date
    cfg = repo / ".test" / "config" / "config.yaml"
    text = cfg.read_text()
    # galton.orbits.max_collisions: only Figure 2's dataset and the figure depend on it
    key = re.compile(r"(\ngalton:\n(?:  .*\n)*?  orbits:\n(?:    .*\n)*?    max_collisions: )(\d+)")
    assert key.search(text), "the reduced config changed shape: update this test's key"
    cfg.write_text(key.sub(lambda m: m.group(1) + str(int(m.group(2)) + 1), text, count=1))
    try:
        assert planned_jobs(repo) == {"galton_orbits": 1, "fig02_galtonboard": 1, "all": 1}
    finally:
        cfg.write_text(text)
    assert planned_jobs(repo) == {}


def test_a_classification_threshold_redraws_without_rerunning_a_simulation(repo):
    """portraits.regular_threshold is a reading of the exponents: only the figures and numbers that use it."""
    cfg = repo / ".test" / "config" / "config.yaml"
    text = cfg.read_text()
    key = re.compile(r"(\n  regular_threshold: )([0-9.]+)")
    assert key.search(text), "the reduced config changed shape: update this test's key"
    cfg.write_text(key.sub(lambda m: m.group(1) + str(2 * float(m.group(2))), text, count=1))
    try:
        assert planned_jobs(repo) == {"fig10_phaseportraits": 1, "fig12_lorentzgamma": 1, "fig13_VPPforce": 1,
                                      "figS3_hex_readings": 1, "numbers_portraits": 1, "numbers": 1, "all": 1}
    finally:
        cfg.write_text(text)


@pytest.mark.parametrize("runtime", [
    '{dask_scheduler: "tcp://127.0.0.1:1", chunk_size: 7, chunk_folder: results/chunks}',
    "{dask_cluster: slurm, dask_workers: 4, dask_worker_cores: 2, dask_interface: ib0}",
])
def test_runtime_settings_rerun_nothing(repo, runtime):
    """Where and in what chunks the ensembles run is not science: no setting plans a job (every
    setting in one of two dry runs: a scheduler address and a SLURM cluster exclude each other)."""
    assert planned_jobs(repo, "--config", f"runtime={runtime}") == {}


def test_lint_is_clean(repo):
    out = snakemake(repo, "--lint")
    assert "Lints for" not in out.stdout + out.stderr and "Congratulations" in out.stdout + out.stderr


#: What docutils writes for a problem in a caption: into the HTML as a system message, and to the log.
CAPTION_PROBLEMS = r"\((?:INFO|WARNING|ERROR|SEVERE)/\d\)|system-message|System Message|Undefined substitution"
#: ... and what else a failing report build writes to its log (the HTML holds "Traceback" in its style sheet).
LOG_PROBLEMS = re.compile(CAPTION_PROBLEMS + r"|Traceback|^WARNING|^Warning|^Error", re.M)


def test_every_caption_is_clean_restructuredtext():
    """Each report caption renders with docutils without a message (``|x|`` is a substitution: write ``\\|x\\|``)."""
    import io

    from docutils.core import publish_parts

    for rst in sorted((ROOT / "workflow" / "report").glob("*.rst")):
        log = io.StringIO()
        publish_parts(rst.read_text(encoding="utf-8"), source_path=str(rst), writer="html",
                      settings_overrides={"warning_stream": log, "report_level": 1, "halt_level": 5})
        assert log.getvalue() == "", f"{rst.name}: {log.getvalue()}"


def test_report_holds_every_figure_with_its_caption(repo):
    out = snakemake(repo, "--report", "report.html")
    html = (repo / ".test" / "report.html").read_text(encoding="utf-8", errors="replace")
    problems = LOG_PROBLEMS.findall(out.stdout + out.stderr) + re.findall(CAPTION_PROBLEMS, html)
    assert not problems, f"the report build warned: {problems}\n{out.stderr[-3000:]}"
    for caption in sorted((ROOT / "workflow" / "report").glob("fig*.rst")):
        assert caption.stem in html
        title = re.search(r"\*\*(Figure [^*]+)\*\*", caption.read_text(encoding="utf-8")).group(1)
        assert title in html, f"caption of {caption.stem} not in the report"


# ---------------------------------------------------------------- the committed paper-size numbers
def test_readme_table_is_the_generated_numbers_table():
    numbers = json.loads((ROOT / "figures" / "numbers.json").read_text(encoding="utf-8"))
    table = (ROOT / "figures" / "numbers.md").read_text(encoding="utf-8")
    assert table == numbers_markdown(numbers)
    readme = (ROOT / "README.md").read_text(encoding="utf-8")
    block = re.search(r"<!-- numbers:start -->\n(.*?)<!-- numbers:end -->", readme, re.S)
    assert block, "README.md has no <!-- numbers:start --> ... <!-- numbers:end --> block"
    assert block.group(1).strip() == table.strip(), "README numbers table differs from figures/numbers.md"


# ---------------------------------------------------------------- Figure 15 under every reading (not in `all`)
def test_readings_target_writes_the_dataset_and_the_table(repo):
    from noslipsim.experiments.readings import READINGS

    snakemake(repo, "--cores", "2", "readings")
    results = repo / ".test" / "results" / "stability"
    ds = xr.load_dataset(results / "readings.nc")
    generic_checks("stability/readings.nc", ds)
    assert list(ds.reading.values) == list(READINGS)
    assert ds.sizes["radius"] == 2 and ds.sizes["theta_read"] == 12      # .test/config/config.yaml
    assert set(np.unique(ds.survived.values)) <= {-1, 0, 1}
    lines = (results / "readings.md").read_text(encoding="utf-8").strip().splitlines()
    assert lines[0].startswith("<!-- generated by `snakemake -j2 readings`")
    assert [c.strip() for c in lines[2].strip("|").split("|")][2:4] == ["R = 0.3", "R = 0.8"]
    names = [re.split(r"(?<!\\)\|", r)[1].strip() for r in lines[4:]]  # a cell's escaped \| is no column
    assert names == [*READINGS, "\\|λ\\| at θ = 1.3", "inverted grey scale"]
