"""The work-precision benchmark's machinery on tiny sizes (``benchmarks/work_precision.py``).

Flights restarted from a 40-digit reference orbit, one at a time:

* noslipsim (restarted with ``start_elements``) finds every next collision on the three
  benchmark scenes, within 1e-12 of the scene's scale on non-grazing flights;
* scipy's ``solve_ivp`` with terminal events and the default ``max_step`` steps over pegs on
  the Galton box (observed: 3 of the first 11 flights with RK45, rtol 1e-3), while every
  collision it does find is exact to rounding (RK methods integrate q'' = a exactly);
* the full pipeline (CSV, summary, diagram) runs on tiny sizes and its figures carry no dates.
"""
import csv
import importlib.util
import math
import os
import sys

import numpy as np
import pytest

BENCH = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "benchmarks")


def _load(name):
    """Import ``benchmarks/<name>.py`` (not a package) under a private module name."""
    key = f"_noslipsim_bench_{name}"
    if key not in sys.modules:
        spec = importlib.util.spec_from_file_location(key, os.path.join(BENCH, f"{name}.py"))
        module = importlib.util.module_from_spec(spec)
        sys.modules[key] = module  # dataclasses look their module up while the file executes
        spec.loader.exec_module(module)
    return sys.modules[key]


wp = _load("work_precision")

#: Collisions of the reference orbit per scene in these tests (flights = collisions - 1).
N_REF = {"pentagon": 40, "sinai": 40, "galton": 12}


@pytest.fixture(scope="module")
def flights():
    return {name: wp.reference_flights(case, N_REF[name], dps=40) for name, case in wp.cases().items()}


@pytest.mark.parametrize("scene", ["pentagon", "sinai", "galton"])
def test_noslipsim_restarts_find_every_collision_to_1e12(flights, scene):
    fl = flights[scene]
    assert len(fl) == N_REF[scene] - 1 and fl.skipped == 0
    assert (~fl.grazing).sum() > 0
    out = wp.judge(fl, *wp.noslipsim_restarts(fl))
    summary = out.summary()
    assert summary["n_missed"] == 0, summary["miss_kinds"]
    assert summary["max_error_nongrazing"] <= wp.TARGET_ERROR
    assert summary["max_time_error"] <= wp.TARGET_ERROR


def test_scipy_default_max_step_steps_over_pegs(flights):
    fl = flights["galton"]
    element, t, x, y, kinds, _ = wp.scipy_run(fl, "RK45", 1e-3, math.inf)
    out = wp.judge(fl, element, t, x, y, kinds)
    missed = [k for k in out.kind if k]
    assert len(missed) > 0
    assert set(missed) == {"stepped_over"}  # another element hit later: a peg passed through
    # a stepped-over flight really crossed the reference's obstacle: the reported hit comes later
    later = np.array([k == "stepped_over" for k in out.kind])
    assert all(t[i] > float(fl.t[i]) for i in np.flatnonzero(later))
    # what scipy does find is exact to rounding
    assert out.summary()["max_error"] <= wp.TARGET_ERROR


def test_judge_classifies_misses(flights):
    fl = flights["sinai"].subset([0, 1, 2, 3])
    x = np.array([float(v) for v in fl.x])
    y = np.array([float(v) for v in fl.y])
    t = np.array([float(v) for v in fl.t])
    element = fl.element.copy()
    element[1] = -1                               # nothing found
    element[2] = (element[2] + 1) % 5             # another element, later
    t[2] += 1.0
    x[3] += 0.1                                   # right element, another time
    t[3] += 0.1
    out = wp.judge(fl, element, t, x, y)
    assert out.kind == ["", "none", "stepped_over", "later"]
    assert out.found.tolist() == [True, False, False, False]
    assert out.error[0] <= 1e-15


def test_pipeline_writes_csv_summary_and_dateless_figures(tmp_path):
    rows, info = wp.run_benchmark(n_collisions=6, dps=40, scipy_flights={math.inf: 5}, methods=("RK45",),
                                  rtols=(1e-3,), max_steps=(math.inf,), repeats=1, scipy_repeats=1,
                                  orbit_collisions=2000, min_seconds=0.0, log=lambda s: None)
    assert {(r["method"], r["scene"]) for r in rows} == {
        (m, s) for m in ("noslipsim", "scipy") for s in ("pentagon", "sinai", "galton")}
    assert all(r["seconds_per_collision"] > 0 for r in rows)
    assert all(r["n_missed"] == 0 for r in rows if r["method"] == "noslipsim")
    path = tmp_path / "work_precision.csv"
    wp.write_csv(rows, str(path))
    with open(path, newline="", encoding="utf-8") as fh:
        header = next(csv.reader(fh))
    assert header[:8] == ["method", "scene", "setting", "seconds_per_collision", "collisions_per_second",
                          "median_error", "max_error", "missed_share"]
    md = tmp_path / "work_precision.md"
    wp.write_markdown(rows, info, str(md), wp.machine(), 1.0,
                      dict(n_collisions=6, dps=40, scipy_flights={math.inf: 5}, repeats=1, scipy_repeats=1,
                           load="n/a", argv=""))
    text = md.read_text(encoding="utf-8")
    assert "≥ 1000× faster" in text and "≤ 1e-12" in text and "Accuracy target" in text

    plot = _load("plot_work_precision")
    png, pdf = plot.draw(plot.read_rows(str(path)), str(tmp_path / "work_precision"))
    first = open(pdf, "rb").read(), open(png, "rb").read()
    assert b"CreationDate" not in first[0] and b"Software" not in first[1]
    plot.draw(plot.read_rows(str(path)), str(tmp_path / "work_precision"))
    assert (open(pdf, "rb").read(), open(png, "rb").read()) == first  # byte-stable
