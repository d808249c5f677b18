# Dataset rules: each runs one experiment of the package and writes one netCDF file in results/
# (noslipsim.write_dataset: every parameter, the package version and the config section in the
# attributes).  `params:` carry the config sections a dataset depends on, so that changing a
# value reruns exactly the datasets (and figures) that use it.  One section per subject.


rule compile_kernels:
    # Compile (or load from numba's cache) every kernel variant the simulations need, once,
    # before the simulation jobs fan out.
    output:
        KERNELS_DONE,
    params:
        entries=kernel_entries(),
        core=core_digest(),
    log:
        log_file("compile_kernels"),
    threads: 1
    conda:
        SOFTWARE
    script:
        "../scripts/compile_kernels.py"


# ---------------------------------------------------------------- galton (Figures 2, 3, S1)
rule galton_orbits:
    input:
        kernels=KERNELS_DONE,
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
        kernels=KERNELS_DONE,
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
        kernels=KERNELS_DONE,
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
        kernels=KERNELS_DONE,
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

# ---------------------------------------------------------------- portraits (Figures 10-13)

# ---------------------------------------------------------------- stability (Figures 7, 9, 14, 15)
