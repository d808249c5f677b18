# All Python helpers of the workflow: config validation, the lists of targets, paths.
# Rules live in simulations.smk (datasets), figures.smk (figures) and report.smk (numbers).
# How to add a figure: workflow/README.md.
import json

from snakemake.utils import validate


validate(config, schema="../schemas/config.schema.yaml")


# ---------------------------------------------------------------- what `rule all` builds
# One entry per figure, grouped by subject (DESIGN numbering: figNN_topic; figS1 beyond the paper).
FIGURES = {
    "galton": ["fig02_galtonboard", "fig03_normal", "figS1_galton_trapping"],
    "orbits": ["fig01_specnoslip", "fig04_pentagons", "fig05_bouncingball", "fig06_newwedge",
               "fig08_noslipstablesinai", "fig16_3dbounce"],
    "portraits": ["fig10_phaseportraits", "fig11_vppregpoly", "fig12_lorentzgamma", "fig13_VPPforce"],
    "stability": ["fig07_wedge", "fig09_2perunstablea", "fig14_2perunstable", "fig15_stabexp"],
}

# Subjects that compute numbers the paper states (rule numbers_<subject> in report.smk).
NUMBER_SUBJECTS = ["galton", "orbits", "stability", "portraits"]

# Kernel variants each subject's simulations run, compiled by rule compile_kernels before the
# simulation jobs fan out (numba's cache is not safe to fill from parallel processes, numba #4807).
# An entry is "table:law:record": table in {plain, plain+force, lattice, lattice+force, disks}
# (disks: one disk per lattice cell, no force), law in {no-slip, specular}, record in
# {final, count, portrait, log} (simulate_many) or orbit (one simulate() call).
KERNELS = {
    "galton": ["lattice+force:no-slip:final", "lattice+force:specular:final",
               "lattice+force:no-slip:orbit", "lattice+force:specular:orbit"],
    # wedges (simulate, monodromy, the periodic-orbit finder) and the two-disk grids (sync scheduler: serial kernels)
    "stability": ["walls+force:no-slip:orbit", "plain:no-slip:orbit", "plain:no-slip:log",
                  "plain:no-slip:count", "walls+force:no-slip:log", "walls+force:no-slip:count"],
    # the rectangle and polygons; the bouncing ball (half-plane) and the wedges of Figure 6 under gravity
    "orbits": ["plain:specular:orbit", "plain:no-slip:orbit", "walls+force:no-slip:orbit"],
    # portraits (lemon, polygons, closed hexagonal cell), first flights (final), Lyapunov runs (orbit);
    # the Sinai torus and the force-free hexagonal gas are "disks", the hexagonal gas under a force "lattice+force"
    "portraits": ["plain:specular:portrait", "plain:specular:final", "plain:specular:orbit",
                  "plain:no-slip:portrait", "plain:no-slip:final", "plain:no-slip:orbit",
                  "plain+force:no-slip:portrait", "plain+force:no-slip:final", "plain+force:no-slip:orbit",
                  "disks:no-slip:portrait", "disks:no-slip:final", "disks:no-slip:orbit",
                  "lattice+force:no-slip:final"],
}


def figure_files(name):
    """The PDF and PNG of one figure."""
    return [f"figures/{name}.pdf", f"figures/{name}.png"]


def all_figures():
    return [name for names in FIGURES.values() for name in names]


def all_targets():
    """Everything `snakemake` builds by default: every figure and the computed numbers."""
    files = [f for name in all_figures() for f in figure_files(name)]
    return files + ["figures/numbers.json", "figures/numbers.md"]


def number_fragments():
    return [f"results/numbers/{subject}.json" for subject in NUMBER_SUBJECTS]


def core_digest():
    """Hash of the compiled core's sources: the kernels are recompiled when it changes."""
    from noslipsim._numba_cache import source_digest

    return source_digest()


def stability_common():
    """The stability config values every stability dataset depends on (gamma, gravity)."""
    return {k: config["stability"][k] for k in ("gamma", "gravity")}


# ---------------------------------------------------------------- runtime
# Threads of an ensemble job (its dask thread pool).  Snakemake lowers it to --cores (-j2: two
# threads); on a cluster the profile's set-threads decides (workflow/profiles/slurm).
ENSEMBLE_THREADS = 8


def dask_scheduler():
    """The dask.distributed scheduler address of the config, or None for local threads."""
    return config.get("dask_scheduler")


# ---------------------------------------------------------------- paths
# The software of every rule (used with --software-deployment-method conda), relative to rules/.
SOFTWARE = "../envs/noslipsim.yaml"


def log_file(name):
    return f"logs/{name}.log"


def benchmark_file(name):
    return f"logs/benchmarks/{name}.tsv"


def kernel_entries(wildcards):
    """The KERNELS entries of the subject of a compile_kernels job."""
    return KERNELS[wildcards.subject]


def kernels_done(subject):
    """The stamp of one subject's compiled kernels, made by compile_kernels; every simulation
    rule of the subject takes it as an input, so that its jobs start once the kernels are cached."""
    if subject not in KERNELS:
        raise ValueError(f"kernels_done: no KERNELS entry for subject {subject!r} (common.smk)")
    return f"results/kernels/{subject}.json"
