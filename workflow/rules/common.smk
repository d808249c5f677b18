# All Python helpers of the workflow: config validation, the tables of datasets, figures and numbers
# from which simulations.smk, figures.smk and report.smk generate their rules, paths.
# How to add a figure: workflow/README.md.
import re

from snakemake.utils import validate


validate(config, schema="../schemas/config.schema.yaml")


# ---------------------------------------------------------------- config sections
def section(path, only=None, without=()):
    """The config section at ``path`` ("stability.launch"), optionally restricted to some keys.

    A rule passes the sections it depends on as params, so that changing a value reruns exactly
    the jobs that use it (and nothing that does not)."""
    value = config
    for key in path.split("."):
        value = value[key]
    if only is not None:
        return {k: value[k] for k in only}
    return {k: v for k, v in value.items() if k not in without} if without else value


def stability_common():
    """The stability config values every stability dataset depends on (gamma, gravity)."""
    return {k: config["stability"][k] for k in ("gamma", "gravity")}


# ---------------------------------------------------------------- kernels
# Kernel variants each subject's simulations run, compiled by rule compile_kernel (one job per
# variant) before the simulation jobs fan out, so that parallel jobs never compile one variant twice.
# An entry is "table:law": table in {plain, plain+force, mixed, mixed+force, walls+force, lattice,
# lattice+force, lattice+thermostat, disks} (disks: disk scatterers on a lattice, no force; lattice+thermostat:
# a lattice under a force flown with the isokinetic thermostat; mixed, mixed+force: a plain table of mixed laws
# without and with a force, law the scatterer's, the walls the other one), law in {no-slip, specular}.  One
# kernel serves every record mode (final states, logs, portrait points; _engine/table.py, recording_slot).
KERNELS = {
    # the boards (lattice) and, for Figure S2's side walls, the walled boards (plain scenes: walls of the pegs'
    # law, or specular walls around no-slip pegs)
    "galton": ["lattice+force:no-slip", "lattice+force:specular", "plain+force:no-slip", "plain+force:specular",
               "mixed+force:no-slip"],
    # wedges (simulate, monodromy, the periodic-orbit finder) and the two-disk grids
    "stability": ["walls+force:no-slip", "plain:no-slip"],
    # the rectangle and polygons; the bouncing ball (half-plane) and the wedges of Figure 6 under gravity
    "orbits": ["plain:specular", "plain:no-slip", "walls+force:no-slip"],
    # portraits (lemon, polygons, closed hexagonal cell), first flights, Lyapunov runs and twin orbits; the
    # Sinai torus and the force-free hexagonal gas are "disks", the hexagonal gas under a force "lattice+force"
    # (free fall) or "lattice+thermostat" (Figure 13's readings, Figure S3); the closed cell of specular walls
    # around the no-slip disk (Figure S3's reading specular_walls) "mixed(+force)"; the specular thermostatted
    # gas beside them (Figure S3's specular_thermostat) "lattice+thermostat:specular"
    "portraits": ["plain:specular", "plain:no-slip", "plain+force:no-slip", "plain+force:specular", "mixed:no-slip",
                  "mixed+force:no-slip", "disks:no-slip", "lattice+force:no-slip", "lattice+thermostat:no-slip",
                  "lattice+thermostat:specular"],
}
ALL_KERNELS = sorted({entry for entries in KERNELS.values() for entry in entries})


def kernel_stamp(entry):
    """The file rule compile_kernel writes once the kernel variant ``entry`` is compiled (or loaded)."""
    return f"results/kernels/{entry.replace(':', '.')}.json"


def kernels_of(subject):
    return [kernel_stamp(entry) for entry in KERNELS[subject]]


# ---------------------------------------------------------------- datasets
# One entry per dataset (simulations.smk makes its rule, of the same name). Its subject, output
# file results/<subject>/<file>, script workflow/scripts/<script>.py, the config sections it
# depends on (params), and its threads (ENSEMBLE for the dask ensembles; Snakemake lowers it to --cores).
ENSEMBLE = 8


def dataset(subject, file, key, script, params, threads=1):
    return {"subject": subject, "output": f"results/{subject}/{file}", "key": key, "script": script,
            "params": params, "threads": threads}


def _grid(kind):
    return dataset("stability", f"grid_{kind}.nc", "grid", "stability_grid",
                   lambda: {"common": stability_common(), "shared": section("stability.grids.shared"),
                            "grid": section(f"stability.grids.{kind}"), "kind": kind})


def _orbits(name):
    return dataset("orbits", f"{name}.nc", name, f"orbits_{name}", lambda: {name: section(f"orbits.{name}")})


DATASETS = {
    # Figures 2, 3, S1
    "galton_orbits": dataset("galton", "orbits.nc", "orbits", "galton_orbits",
                             lambda: {"board": section("galton.board"), "orbits": section("galton.orbits")}),
    "galton_distribution": dataset("galton", "distribution.nc", "distribution", "galton_distribution",
                                   lambda: {"board": section("galton.board"), "run": section("galton.distribution")},
                                   ENSEMBLE),
    "galton_arrivals": dataset("galton", "arrivals.nc", "arrivals", "galton_arrivals",
                               lambda: {"board": section("galton.board"), "run": section("galton.arrivals")},
                               ENSEMBLE),
    "galton_radius_sweep": dataset("galton", "radius_sweep.nc", "sweep", "galton_radius_sweep",
                                   lambda: {"board": section("galton.board"), "run": section("galton.radius_sweep")},
                                   ENSEMBLE),
    "galton_rows": dataset("galton", "rows.nc", "rows", "galton_rows",
                           lambda: {"board": section("galton.board"), "run": section("galton.rows_sweep")},
                           ENSEMBLE),
    # Figure S2 (snakemake -j2 evidence)
    "galton_evidence": dataset("galton", "evidence.nc", "evidence", "galton_evidence",
                               lambda: {"board": section("galton.board"), "run": section("galton.evidence")},
                               ENSEMBLE),
    # Figures 1, 4, 5, 6, 8, 16
    **{f"orbits_{name}": _orbits(name) for name in ("specnoslip", "pentagons", "bounce", "newwedge", "twodisks",
                                                     "sphere")},
    # Figures 10-13
    **{f"portraits_{name}": dataset("portraits", f"{name}.nc", "portraits", f"portraits_{name}",
                                    (lambda name=name: {"run": section(f"portraits.{name}")}), ENSEMBLE)
       for name in ("phaseportraits", "polygons", "sinai_gamma", "hex_force", "hex_readings")},
    # Lyapunov exponents orbit after orbit (one thread: the Benettin loop holds the GIL)
    "portraits_islands": dataset("portraits", "islands.nc", "islands", "portraits_islands",
                                 lambda: {"run": section("portraits.islands", without=("level",))}),
    # Figures 7, 9, 14, 15
    "stability_wedge_orbits": dataset("stability", "wedge_orbits.nc", "orbits", "stability_wedge_orbits",
                                      lambda: {"common": stability_common(), "run": section("stability.wedge")}),
    "stability_wedge_perturbed": dataset("stability", "wedge_perturbed.nc", "orbits", "stability_perturbed",
                                         lambda: {"common": stability_common(), "run": section("stability.perturbed"),
                                                  "section": "perturbed"}),
    "stability_launch_orbits": dataset("stability", "launch_orbits.nc", "orbits", "stability_perturbed",
                                       lambda: {"common": stability_common(),
                                                "run": section("stability.launch", without=("scan",)),
                                                "section": "launch"}),
    "stability_launch_scan": dataset("stability", "launch_scan.nc", "scan", "stability_launch_scan",
                                     lambda: {"common": stability_common(),
                                              "run": section("stability.launch", only=("ell", "thetas", "scan"))}),
    **{f"stability_grid_{kind}": _grid(kind) for kind in ("noforce", "force", "theta")},
    # Figure 15 under every reading (target `readings`, not in `all`)
    "stability_readings": dataset("stability", "readings.nc", "readings", "stability_readings",
                                  lambda: {"run": section("stability.readings", without=("min_run",))}),
}


def dataset_file(name):
    return DATASETS[name]["output"]


# ---------------------------------------------------------------- figures
# One entry per figure (figures.smk; DESIGN numbering figNN_topic, figS1 beyond the paper): the
# report category, its datasets ({input name: dataset}) and the config values that only the
# drawing depends on (classification thresholds, bin widths, sketch geometry).
def figure(category, inputs, params=lambda: {}):
    return {"category": category, "inputs": inputs, "params": params}


THRESHOLD = lambda: {"threshold": config["portraits"]["regular_threshold"]}
ONSETS = lambda: {**THRESHOLD(), "level": config["portraits"]["islands"]["level"]}

FIGURES = {
    "fig01_specnoslip": figure("Orbits", {"specnoslip": "orbits_specnoslip"}),
    "fig02_galtonboard": figure("Galton board", {"orbits": "galton_orbits"}),
    "fig03_normal": figure("Galton board", {"distribution": "galton_distribution", "rows": "galton_rows"},
                           lambda: {"histogram": section("galton.histogram")}),
    "fig04_pentagons": figure("Orbits", {"pentagons": "orbits_pentagons"}),
    "fig05_bouncingball": figure("Orbits", {"bounce": "orbits_bounce"}),
    "fig06_newwedge": figure("Orbits", {"newwedge": "orbits_newwedge"}),
    "fig07_wedge": figure("Stability", {"orbits": "stability_wedge_orbits"}),
    "fig08_noslipstablesinai": figure("Orbits", {"twodisks": "orbits_twodisks"}),
    "fig09_2perunstablea": figure("Stability", {"orbits": "stability_wedge_perturbed"}),
    "fig10_phaseportraits": figure("Phase portraits", {"portraits": "portraits_phaseportraits"}, THRESHOLD),
    "fig11_vppregpoly": figure("Phase portraits", {"portraits": "portraits_polygons"}),
    "fig12_lorentzgamma": figure("Phase portraits", {"portraits": "portraits_sinai_gamma",
                                                      "islands": "portraits_islands"}, ONSETS),
    "fig13_VPPforce": figure("Phase portraits", {"portraits": "portraits_hex_force"}, THRESHOLD),
    "fig14_2perunstable": figure("Stability", {"orbits": "stability_launch_orbits", "scan": "stability_launch_scan"}),
    "fig15_stabexp": figure("Stability", {"noforce": "stability_grid_noforce", "force": "stability_grid_force",
                                          "theta": "stability_grid_theta"},
                            lambda: {"sketch": section("stability.grids.sketch")}),
    "fig16_3dbounce": figure("Orbits", {"sphere": "orbits_sphere"}),
    "figS1_galton_trapping": figure("Galton board", {"arrivals": "galton_arrivals", "sweep": "galton_radius_sweep"}),
    "figS2_galton_evidence": figure("Galton board", {"evidence": "galton_evidence"}),
    "figS3_hex_readings": figure("Phase portraits", {"readings": "portraits_hex_readings",
                                                     "portraits": "portraits_hex_force"}, THRESHOLD),
}


def figure_files(name):
    """The PDF and PNG of one figure."""
    return [f"figures/{name}.pdf", f"figures/{name}.png"]


# ---------------------------------------------------------------- numbers
# Subjects that compute numbers the paper states (numbers_<subject> in report.smk): their
# datasets and the config values the computation alone depends on.
NUMBERS = {
    "galton": figure(None, {"distribution": "galton_distribution", "arrivals": "galton_arrivals",
                            "sweep": "galton_radius_sweep", "rows": "galton_rows"}),
    "evidence": figure(None, {"evidence": "galton_evidence", "sweep": "galton_radius_sweep"}),
    "orbits": figure(None, {"specnoslip": "orbits_specnoslip", "pentagons": "orbits_pentagons",
                            "bounce": "orbits_bounce", "twodisks": "orbits_twodisks", "sphere": "orbits_sphere"}),
    "stability": figure(None, {"noforce": "stability_grid_noforce", "force": "stability_grid_force",
                               "theta": "stability_grid_theta", "scan": "stability_launch_scan",
                               "launch": "stability_launch_orbits", "wedge": "stability_wedge_orbits"},
                        lambda: {"band": config["stability"]["grids"]["threshold_band"],
                                 "min_run": config["stability"]["grids"]["min_run"],
                                 "thetas": config["stability"]["launch"]["thetas"]}),
    "portraits": figure(None, {"islands": "portraits_islands", "hex_force": "portraits_hex_force",
                               "hex_readings": "portraits_hex_readings"}, ONSETS),
}


def number_fragments():
    return [f"results/numbers/{subject}.json" for subject in NUMBERS]


def inputs_of(entry):
    """``{input name: dataset file}`` of a figure or numbers entry."""
    return {key: dataset_file(name) for key, name in entry["inputs"].items()}


# ---------------------------------------------------------------- scripts of generated rules
#: The script of each generated rule, by rule name.
SCRIPTS = {**{name: spec["script"] for name, spec in DATASETS.items()}, **{name: name for name in FIGURES},
           **{f"numbers_{subject}": f"numbers_{subject}" for subject in NUMBERS}}


def script_of(running, defining):
    """The script path of a rule made in a loop.

    Snakemake evaluates a rule's `script:` twice: when the rule is defined (the loop's current
    entry) and when its job runs (after the loop, so the loop variable is the last entry).  The
    job's own rule name (``rule`` inside the running job, ``vars().get("rule")``) decides then."""
    return f"../scripts/{SCRIPTS[running or defining]}.py"


# ---------------------------------------------------------------- what `rule all` builds
def all_targets():
    """Everything `snakemake` builds by default: every figure and the computed numbers."""
    files = [f for name in FIGURES for f in figure_files(name)]
    return files + ["figures/numbers.json", "figures/numbers.md"]


# ---------------------------------------------------------------- paths and software
# The software of every rule (used with --software-deployment-method conda), relative to rules/.
SOFTWARE = "../envs/noslipsim.yaml"


def log_file(name):
    return f"logs/{name}.log"


def benchmark_file(name):
    return f"logs/benchmarks/{name}.tsv"


def core_digest():
    """Hash of the compiled core's sources: the kernels are recompiled when it changes."""
    from noslipsim.core.jit import SOURCE_DIGEST

    return SOURCE_DIGEST
