# Dataset rules, generated from DATASETS (common.smk): each runs one experiment of the package and
# writes one netCDF file in results/ (noslipsim.write_dataset: every parameter, the package version,
# the software and the config section in the attributes).  `params:` carry exactly the config
# sections a dataset depends on, so that changing a value reruns exactly the datasets (and figures)
# that use it; runtime settings (config key `runtime`: where the ensembles run) are never params.


rule compile_kernel:
    # Compile (or load from numba's cache) one kernel variant (KERNELS in common.smk) before the
    # simulation jobs that need it fan out, so that two parallel jobs never compile it twice.
    output:
        stamp="results/kernels/{entry}.json",
    params:
        entry=lambda wildcards: wildcards.entry.replace(".", ":"),
        core=core_digest(),
    wildcard_constraints:
        entry="|".join(re.escape(entry.replace(":", ".")) for entry in ALL_KERNELS),
    log:
        log_file("compile_kernel_{entry}"),
    threads: 1
    conda:
        SOFTWARE
    script:
        "../scripts/compile_kernels.py"


for name, spec in DATASETS.items():

    rule:
        name:
            name
        input:
            kernels=kernels_of(spec["subject"]),
        output:
            **{spec["key"]: spec["output"]},
        params:
            **spec["params"](),
        log:
            log_file(name),
        benchmark:
            benchmark_file(name)
        threads: spec["threads"]
        conda:
            SOFTWARE
        script:
            script_of(vars().get("rule"), name)
