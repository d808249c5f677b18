"""Dataset metadata declared once: one table of long names and units, one annotate, attributes that round-trip.

* Every variable and coordinate of the datasets the public functions return
  (simulate, simulate_many for each record, a reference orbit, sphere3d and
  every experiment, at tiny sizes) carries the ``long_name`` and ``units`` of
  the table in ``noslipsim._metadata``.
* No other module of the package spells out ``long_name`` (AST check).
* Attributes that hold structure come back through ``json.loads`` after
  ``write_dataset`` / ``open_dataset``.
* The table is consistent with itself and with docs/datasets.md (the doc's list
  is generated from it).
"""
import ast
import json
import math
import re
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

import noslipsim
from noslipsim import experiments as ex
from noslipsim import simulate, simulate_many, tables
from noslipsim._metadata import ALIASES, VARIABLES, annotate, entry, markdown_table
from noslipsim.reference import simulate_reference
from noslipsim.sphere3d import simulate_sphere

ROOT = Path(__file__).resolve().parents[1]
PACKAGE = ROOT / "src" / "noslipsim"
DOC = ROOT / "docs" / "datasets.md"

#: Modules outside this table's scope that still write or read ``long_name`` themselves: the analysis
#: functions' own tables (their datasets are not in VARIABLES yet) and a plot that reads the attribute.

G = 1 / math.sqrt(2)
BOX = tables.rectangle(2.0, 1.0, disks=[(1.0, 0.5, 0.2)])
TORUS = tables.sinai_torus(0.3)


def _check(ds, case_dim=None):
    """Every variable and coordinate of ``ds`` has the table's long name and units."""
    assert ds.variables, "empty dataset"
    for name, var in ds.variables.items():
        want = entry(name, case_dim)
        assert want is not None, f"{name}: not in noslipsim._metadata.VARIABLES"
        assert var.attrs.get("long_name") == want[0], name
        assert var.attrs.get("units") == want[1], name


# ----------------------------------------------------------------------------- (a) the datasets
def _starts(n=3):
    rng = np.random.default_rng(1)
    pos = np.c_[rng.uniform(0.2, 0.8, n), rng.uniform(0.2, 0.8, n)]
    ang = rng.uniform(0, 2 * np.pi, n)
    return pos, np.c_[np.cos(ang), np.sin(ang)], rng.uniform(-0.5, 0.5, n)


def _torus_starts(n=3):
    ang = np.linspace(0.3, 5.0, n)
    return np.tile([0.5, 0.0], (n, 1)), np.c_[np.cos(ang), np.sin(ang)], np.zeros(n)


CORE = {
    "simulate": lambda: simulate(BOX, (0.3, 0.5), (1.0, 0.37), spin=0.2, max_collisions=5),
    "simulate lattice": lambda: simulate(TORUS, (0.5, 0.0), (0.6, 0.8), max_collisions=5),
    "reference": lambda: simulate_reference(BOX, (0.3, 0.5), (1.0, 0.37), 0.2, max_collisions=3),
    "reference lattice": lambda: simulate_reference(TORUS, (0.5, 0.0), (0.6, 0.8), 0.0,
                                                    max_collisions=3),
    "sphere3d": lambda: simulate_sphere([0, 0, 1], [0.1, 0.2, 0.3], [0.3, -0.1, 0.2], n_bounces=3),
}
for _record in ("count", "final", "portrait", "log"):
    CORE[f"simulate_many {_record}"] = (lambda r: lambda: simulate_many(
        BOX, *_starts(), max_collisions=6, record=r, scheduler="sync"))(_record)
    CORE[f"simulate_many {_record} lattice"] = (lambda r: lambda: simulate_many(
        TORUS, *_torus_starts(), max_collisions=6, record=r, scheduler="sync"))(_record)


@pytest.mark.parametrize("name", sorted(CORE))
def test_core_datasets_carry_the_table(name):
    _check(CORE[name]())


TINY = {"chunk_size": None, "scheduler": "sync"}
EXPERIMENTS = {
    "galton_distribution": lambda: ex.galton_distribution(4, gamma=(G, 1.0), rows=2, max_time=30.0, **TINY),
    "galton_radius_sweep": lambda: ex.galton_radius_sweep(3, radii=(0.5, 0.6), rows=2, max_time=30.0),
    "galton_orbits": lambda: ex.galton_orbits(rows=2, max_collisions=20),
    "galton_evidence": lambda: ex.galton_evidence(
        [{"name": "board", "group": "drop", "top_row": 0, "start": (0.0, 2.0), "spread": 0.5},
         {"name": "gap", "group": "drop", "start": (1.0, 0.0)}], 3, laws=("specular", "no-slip"), rows=2,
        max_time=30.0, radius=0.8, **TINY),
    "orbit_set": lambda: ex.orbit_set([BOX, BOX], [(0.3, 0.5), (0.4, 0.6)], [(1.0, 0.3), (0.2, 1.0)],
                                      max_collisions=5),
    "phase_portrait": lambda: ex.phase_portrait(BOX, n_orbits=3, n_collisions=10, **TINY),
    "specular_noslip_orbits": lambda: ex.specular_noslip_orbits(),
    "pentagon_orbits": lambda: ex.pentagon_orbits(n_generic=5, n_corridor=20),
    "bounce_orbits": lambda: ex.bounce_orbits(),
    "newwedge_orbits": lambda: ex.newwedge_orbits(),
    "two_disk_box_orbits": lambda: ex.two_disk_box_orbits(n_specular=5, n_noslip=10),
    "sphere_bounce": lambda: ex.sphere_bounce(),
    "wedge_periodic_orbits": lambda: ex.wedge_periodic_orbits(
        0.6, G, reversing=[{"opening": "up", "theta": 0.4, "ell": 1.0}],
        searches=[{"name": "not path-reversing", "opening": "up", "position": [-0.041, 1.052],
                   "velocity": [0.29, -1.2], "spin": 0.249, "period": 2}], periods=2),
    "perturbed_wedge_orbits": lambda: ex.perturbed_wedge_orbits(
        [{"opening": "up", "theta": 0.3, "ell": 1.0}], phi=math.pi / 7, n_collisions=10),
    "wedge_launch_scan": lambda: ex.wedge_launch_scan([0.6], [0.3, 0.6, 0.9, 1.2], G),
    "sinai_gamma_portraits": lambda: ex.sinai_gamma_portraits((0.0, 0.5), n_orbits=3, n_collisions=20,
                                                              lyapunov_collisions=20, **TINY),
    "sinai_islands_sweep": lambda: ex.sinai_islands_sweep((0.45,), (0.0, 0.5), n_orbits=3, n_collisions=20),
    "hex_force_portraits": lambda: ex.hex_force_portraits((G,), (0.0, 0.1), n_orbits=3, n_collisions=20,
                                                          lyapunov_collisions=20, **TINY),
    "hex_force_readings": lambda: ex.hex_force_readings((G,), (0.0, 1.0), readings=("closed", "thermostat"),
                                                        n_orbits=2, lyapunov_collisions=12, attractor_collisions=9),
    "polygon_portraits": lambda: ex.polygon_portraits((4, 5), n_orbits=3, n_collisions=20, **TINY),
    "lemon_sinai_portraits": lambda: ex.lemon_sinai_portraits(n_orbits=3, n_collisions=20, lyapunov_collisions=20,
                                                              **TINY),
    "accessible_pair_census": lambda: ex.accessible_pair_census(["wedge", "two disks"], G, pairs=1),
}


def test_every_experiment_is_covered():
    assert set(ex.EXPERIMENTS) <= set(EXPERIMENTS)


@pytest.mark.parametrize("name", sorted(EXPERIMENTS))
def test_experiment_datasets_carry_the_table(name):
    _check(EXPERIMENTS[name]())


def test_a_case_dimension_without_an_entry_is_a_case():
    ds = ex.portrait_set([BOX, tables.rectangle(2.0, 1.0)], ["with disk", "empty"], dim="variant", n_orbits=2,
                         n_collisions=10, scheduler="sync")
    _check(ds, case_dim="variant")
    assert ds.variant.attrs["long_name"] == VARIABLES["case"][0]


def test_parameters_are_attributes_not_long_names():
    ds = EXPERIMENTS["sinai_islands_sweep"]()
    assert ds.attrs["lyapunov_collisions"] == 20
    assert "20" not in ds.ftle.attrs["long_name"]
    assert EXPERIMENTS["sinai_gamma_portraits"]().attrs["lyapunov_collisions"] == 20


def test_annotate_keeps_what_a_variable_already_says():
    ds = xr.Dataset({"x": ("n", [1.0], {"long_name": "mine"}), "unknown": ("n", [2.0])})
    annotate(ds)
    assert ds.x.attrs == {"long_name": "mine", "units": "1"}
    assert ds.unknown.attrs == {}


# ----------------------------------------------------------------------------- (b) no long names elsewhere
def _spells_long_name(path):
    tree = ast.parse(path.read_text(), filename=str(path))
    for node in ast.walk(tree):
        if isinstance(node, ast.Constant) and node.value == "long_name":
            return node.lineno
        if isinstance(node, ast.keyword) and node.arg == "long_name":
            return node.value.lineno
    return None


def test_no_module_but_the_table_spells_long_name():
    offenders = {}
    for path in sorted(PACKAGE.rglob("*.py")):
        rel = path.relative_to(PACKAGE).as_posix()
        if rel == "_metadata.py":
            continue
        line = _spells_long_name(path)
        if line is not None:
            offenders[rel] = line
    assert not offenders, f"long_name outside noslipsim/_metadata.py: {offenders}"


# ----------------------------------------------------------------------------- (c) attributes round-trip
STRUCTURES = {
    "config": {"a": 1, "b": [1.5, None], "c": {"d": "e"}, "flag": True},
    "vertices": [[0.0, 0.0], [1.0, 0.0], [0.5, 1.0]],
    "ragged": [[1], [2, 3]],
    "names": ["lemon", "sinai"],
    "mixed": [1, "a", None],
    "matrix": np.eye(2),
}


def test_structured_attributes_round_trip(tmp_path):
    ds = xr.Dataset({"x": ("n", [1.0, 2.0], dict(STRUCTURES))}, attrs=dict(STRUCTURES, numbers=[1.0, 2.5, 3.0]))
    noslipsim.write_dataset(ds, tmp_path / "d.nc")
    back = noslipsim.open_dataset(tmp_path / "d.nc")
    for attrs in (back.attrs, back.x.attrs):
        for key, value in STRUCTURES.items():
            want = value.tolist() if isinstance(value, np.ndarray) else value
            assert json.loads(attrs[key]) == want, key
    np.testing.assert_array_equal(back.attrs["numbers"], [1.0, 2.5, 3.0])   # flat numbers: a numeric attribute
    assert json.loads(back.attrs["software"])["numpy"] == np.__version__


def test_package_attributes_round_trip(tmp_path):
    many = simulate_many(BOX, *_starts(), max_collisions=4, max_time=10.0, scheduler="sync")
    assert json.loads(many.attrs["limits"]) == {"max_collisions": 4.0, "max_time": 10.0, "stop_below": None}
    orbit = simulate(BOX, (0.3, 0.5), (1.0, 0.37), spin=0.2, max_collisions=3)
    ref = CORE["reference"]()
    sphere = CORE["sphere3d"]()
    for name, ds in (("many", many), ("orbit", orbit), ("ref", ref), ("sphere", sphere)):
        path = tmp_path / f"{name}.nc"
        noslipsim.write_dataset(ds, path)
        back = noslipsim.open_dataset(path)
        for key in ("limits", "start", "scene"):
            if key in ds.attrs:
                assert json.loads(back.attrs[key]) == json.loads(ds.attrs[key]), (name, key)
        for var in back.variables:
            assert back[var].attrs.get("long_name") == VARIABLES[var][0], (name, var)
    assert json.loads(ref.attrs["start"]) == json.loads(orbit.attrs["start"])


def test_no_attribute_is_a_python_repr():
    """``str(dict)`` / ``str(list)`` is not JSON: no package dataset stores one."""
    for ds in (CORE["simulate_many final"](), CORE["reference"](), CORE["simulate"]()):
        for _key, value in ds.attrs.items():
            if isinstance(value, str) and value[:1] in "{[":
                json.loads(value)


# ----------------------------------------------------------------------------- (d) the table and the docs
def test_table_entries_are_well_formed():
    for name, (long_name, units) in VARIABLES.items():
        assert re.fullmatch(r"[a-z][a-z0-9_]*", name), name
        assert long_name and long_name == long_name.strip() and "{" not in long_name, name
        assert units in ("1", "rad", "degree"), name
    for alias, name in ALIASES.items():
        assert name in VARIABLES and name not in ALIASES and VARIABLES[alias] == VARIABLES[name]


def test_one_long_name_one_entry():
    """Two names share a long name only as a declared alias (one meaning, one entry)."""
    seen = {}
    for name, (long_name, _) in VARIABLES.items():
        key = ALIASES.get(name, name)
        assert seen.setdefault(long_name, key) == key, f"{name} and {seen[long_name]} share a long name"


def _doc_block():
    text = DOC.read_text()
    begin = text.index("<!-- BEGIN VARIABLES")
    begin = text.index("\n", begin) + 1
    return text, text[begin:text.index("<!-- END VARIABLES -->")].strip("\n") + "\n"


def test_docs_list_is_the_table():
    _, block = _doc_block()
    assert block == markdown_table(), ("docs/datasets.md is out of date: replace the block between the VARIABLES "
                                       "markers by noslipsim._metadata.markdown_table()")


def test_docs_tables_name_only_known_variables():
    """The per-function tables of docs/datasets.md (first column) name only variables of the table."""
    text, _ = _doc_block()
    text = text[:text.index("<!-- BEGIN VARIABLES")]
    named = set()
    for line in text.splitlines():
        if line.startswith("| `"):
            first = line.split("|")[1]
            named |= {n for n in re.findall(r"`([^`]+)`", first) if re.fullmatch(r"[a-z][a-z0-9_]*", n)}
    assert named and named <= set(VARIABLES), named - set(VARIABLES)
