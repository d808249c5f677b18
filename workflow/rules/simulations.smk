# Dataset rules: each runs one experiment of the package and writes one netCDF file in results/
# (noslipsim.write_dataset: every parameter, the package version and the config section in the
# attributes).  `params:` carry the config sections a dataset depends on, so that changing a
# value reruns exactly the datasets (and figures) that use it.  One section per subject.


rule compile_kernels:
    # Compile (or load from numba's cache) the kernel variants one subject's simulations need
    # (KERNELS in common.smk) before its simulation jobs fan out.  Compile jobs of different
    # subjects take turns (a file lock): numba's cache is not safe to fill from parallel processes.
    output:
        stamp="results/kernels/{subject}.json",
    params:
        entries=kernel_entries,
        core=core_digest(),
    wildcard_constraints:
        subject="|".join(KERNELS),
    log:
        log_file("compile_kernels_{subject}"),
    threads: 1
    conda:
        SOFTWARE
    script:
        "../scripts/compile_kernels.py"


# ---------------------------------------------------------------- galton (Figures 2, 3, S1)
rule galton_orbits:
    input:
        kernels=kernels_done("galton"),
    output:
        orbits="results/galton/orbits.nc",
    params:
        board=config["galton"]["board"],
        orbits=config["galton"]["orbits"],
    log:
        log_file("galton_orbits"),
    benchmark:
        benchmark_file("galton_orbits")
    threads: 1
    conda:
        SOFTWARE
    script:
        "../scripts/galton_orbits.py"


rule galton_distribution:
    input:
        kernels=kernels_done("galton"),
    output:
        distribution="results/galton/distribution.nc",
    params:
        board=config["galton"]["board"],
        run=config["galton"]["distribution"],
        scheduler=dask_scheduler(),
    log:
        log_file("galton_distribution"),
    benchmark:
        benchmark_file("galton_distribution")
    threads: ENSEMBLE_THREADS
    conda:
        SOFTWARE
    script:
        "../scripts/galton_distribution.py"


rule galton_arrivals:
    input:
        kernels=kernels_done("galton"),
    output:
        arrivals="results/galton/arrivals.nc",
    params:
        board=config["galton"]["board"],
        run=config["galton"]["arrivals"],
        scheduler=dask_scheduler(),
    log:
        log_file("galton_arrivals"),
    benchmark:
        benchmark_file("galton_arrivals")
    threads: ENSEMBLE_THREADS
    conda:
        SOFTWARE
    script:
        "../scripts/galton_arrivals.py"


rule galton_radius_sweep:
    input:
        kernels=kernels_done("galton"),
    output:
        sweep="results/galton/radius_sweep.nc",
    params:
        board=config["galton"]["board"],
        run=config["galton"]["radius_sweep"],
        scheduler=dask_scheduler(),
    log:
        log_file("galton_radius_sweep"),
    benchmark:
        benchmark_file("galton_radius_sweep")
    threads: ENSEMBLE_THREADS
    conda:
        SOFTWARE
    script:
        "../scripts/galton_radius_sweep.py"


# ---------------------------------------------------------------- orbits (Figures 1, 4, 5, 6, 8, 16)
rule orbits_specnoslip:
    # Figure 1
    input:
        kernels=kernels_done("orbits"),
    output:
        specnoslip="results/orbits/specnoslip.nc",
    params:
        specnoslip=config["orbits"]["specnoslip"],
    log:
        log_file("orbits_specnoslip"),
    benchmark:
        benchmark_file("orbits_specnoslip")
    threads: 1
    conda:
        SOFTWARE
    script:
        "../scripts/orbits_specnoslip.py"


rule orbits_pentagons:
    # Figure 4
    input:
        kernels=kernels_done("orbits"),
    output:
        pentagons="results/orbits/pentagons.nc",
    params:
        pentagons=config["orbits"]["pentagons"],
    log:
        log_file("orbits_pentagons"),
    benchmark:
        benchmark_file("orbits_pentagons")
    threads: 1
    conda:
        SOFTWARE
    script:
        "../scripts/orbits_pentagons.py"


rule orbits_bounce:
    # Figure 5
    input:
        kernels=kernels_done("orbits"),
    output:
        bounce="results/orbits/bounce.nc",
    params:
        bounce=config["orbits"]["bounce"],
    log:
        log_file("orbits_bounce"),
    benchmark:
        benchmark_file("orbits_bounce")
    threads: 1
    conda:
        SOFTWARE
    script:
        "../scripts/orbits_bounce.py"


rule orbits_newwedge:
    # Figure 6
    input:
        kernels=kernels_done("orbits"),
    output:
        newwedge="results/orbits/newwedge.nc",
    params:
        newwedge=config["orbits"]["newwedge"],
    log:
        log_file("orbits_newwedge"),
    benchmark:
        benchmark_file("orbits_newwedge")
    threads: 1
    conda:
        SOFTWARE
    script:
        "../scripts/orbits_newwedge.py"


rule orbits_twodisks:
    # Figure 8
    input:
        kernels=kernels_done("orbits"),
    output:
        twodisks="results/orbits/twodisks.nc",
    params:
        twodisks=config["orbits"]["twodisks"],
    log:
        log_file("orbits_twodisks"),
    benchmark:
        benchmark_file("orbits_twodisks")
    threads: 1
    conda:
        SOFTWARE
    script:
        "../scripts/orbits_twodisks.py"


rule orbits_sphere:
    # Figure 16
    input:
        kernels=kernels_done("orbits"),
    output:
        sphere="results/orbits/sphere.nc",
    params:
        sphere=config["orbits"]["sphere"],
    log:
        log_file("orbits_sphere"),
    benchmark:
        benchmark_file("orbits_sphere")
    threads: 1
    conda:
        SOFTWARE
    script:
        "../scripts/orbits_sphere.py"



# ---------------------------------------------------------------- portraits (Figures 10-13)
rule portraits_phaseportraits:
    input:
        kernels=kernels_done("portraits"),
    output:
        portraits="results/portraits/phaseportraits.nc",
    params:
        run=config["portraits"]["phaseportraits"],
        threshold=config["portraits"]["regular_threshold"],
        scheduler=dask_scheduler(),
    log:
        log_file("portraits_phaseportraits"),
    benchmark:
        benchmark_file("portraits_phaseportraits")
    threads: ENSEMBLE_THREADS
    conda:
        SOFTWARE
    script:
        "../scripts/portraits_phaseportraits.py"


rule portraits_polygons:
    input:
        kernels=kernels_done("portraits"),
    output:
        portraits="results/portraits/polygons.nc",
    params:
        run=config["portraits"]["polygons"],
        scheduler=dask_scheduler(),
    log:
        log_file("portraits_polygons"),
    benchmark:
        benchmark_file("portraits_polygons")
    threads: ENSEMBLE_THREADS
    conda:
        SOFTWARE
    script:
        "../scripts/portraits_polygons.py"


rule portraits_sinai_gamma:
    input:
        kernels=kernels_done("portraits"),
    output:
        portraits="results/portraits/sinai_gamma.nc",
    params:
        run=config["portraits"]["sinai_gamma"],
        threshold=config["portraits"]["regular_threshold"],
        scheduler=dask_scheduler(),
    log:
        log_file("portraits_sinai_gamma"),
    benchmark:
        benchmark_file("portraits_sinai_gamma")
    threads: ENSEMBLE_THREADS
    conda:
        SOFTWARE
    script:
        "../scripts/portraits_sinai_gamma.py"


rule portraits_islands:
    # Lyapunov exponents of orbit after orbit (one thread: the Benettin loop holds the GIL)
    input:
        kernels=kernels_done("portraits"),
    output:
        islands="results/portraits/islands.nc",
    params:
        run=config["portraits"]["islands"],
        threshold=config["portraits"]["regular_threshold"],
    log:
        log_file("portraits_islands"),
    benchmark:
        benchmark_file("portraits_islands")
    threads: 1
    conda:
        SOFTWARE
    script:
        "../scripts/portraits_islands.py"


rule portraits_hex_force:
    input:
        kernels=kernels_done("portraits"),
    output:
        portraits="results/portraits/hex_force.nc",
    params:
        run=config["portraits"]["hex_force"],
        threshold=config["portraits"]["regular_threshold"],
        scheduler=dask_scheduler(),
    log:
        log_file("portraits_hex_force"),
    benchmark:
        benchmark_file("portraits_hex_force")
    threads: ENSEMBLE_THREADS
    conda:
        SOFTWARE
    script:
        "../scripts/portraits_hex_force.py"


# ---------------------------------------------------------------- stability (Figures 7, 9, 14, 15)
rule stability_wedge_orbits:
    input:
        kernels=kernels_done("stability"),
    output:
        orbits="results/stability/wedge_orbits.nc",
    params:
        common=stability_common(),
        run=config["stability"]["wedge"],
    log:
        log_file("stability_wedge_orbits"),
    benchmark:
        benchmark_file("stability_wedge_orbits")
    threads: 1
    conda:
        SOFTWARE
    script:
        "../scripts/stability_wedge_orbits.py"


rule stability_wedge_perturbed:
    input:
        kernels=kernels_done("stability"),
    output:
        orbits="results/stability/wedge_perturbed.nc",
    params:
        common=stability_common(),
        run=config["stability"]["perturbed"],
        section="perturbed",
    log:
        log_file("stability_wedge_perturbed"),
    benchmark:
        benchmark_file("stability_wedge_perturbed")
    threads: 1
    conda:
        SOFTWARE
    script:
        "../scripts/stability_perturbed.py"


rule stability_launch_orbits:
    input:
        kernels=kernels_done("stability"),
    output:
        orbits="results/stability/launch_orbits.nc",
    params:
        common=stability_common(),
        run={k: v for k, v in config["stability"]["launch"].items() if k != "scan"},
        section="launch",
    log:
        log_file("stability_launch_orbits"),
    benchmark:
        benchmark_file("stability_launch_orbits")
    threads: 1
    conda:
        SOFTWARE
    script:
        "../scripts/stability_perturbed.py"


rule stability_launch_scan:
    input:
        kernels=kernels_done("stability"),
    output:
        scan="results/stability/launch_scan.nc",
    params:
        common=stability_common(),
        run={k: config["stability"]["launch"][k] for k in ("ell", "thetas", "scan")},
    log:
        log_file("stability_launch_scan"),
    benchmark:
        benchmark_file("stability_launch_scan")
    threads: 1
    conda:
        SOFTWARE
    script:
        "../scripts/stability_launch_scan.py"


rule stability_grid:
    # one rule for the three grids of Figure 15 (noforce, force, theta); each depends on its own
    # config section and the shared one only
    input:
        kernels=kernels_done("stability"),
    output:
        grid="results/stability/grid_{kind}.nc",
    wildcard_constraints:
        kind="noforce|force|theta",
    params:
        common=stability_common(),
        shared=config["stability"]["grids"]["shared"],
        grid=lambda wildcards: config["stability"]["grids"][wildcards.kind],
        kind=lambda wildcards: wildcards.kind,
    log:
        log_file("stability_grid_{kind}"),
    benchmark:
        benchmark_file("stability_grid_{kind}")
    threads: 1
    conda:
        SOFTWARE
    script:
        "../scripts/stability_grid.py"
