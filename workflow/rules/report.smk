# The paper's stated numbers, computed from the datasets.  Each subject has a rule
# numbers_<subject> writing results/numbers/<subject>.json ({key: record}, see
# noslipsim.plot.numbers); rule numbers gathers the fragments of NUMBER_SUBJECTS (common.smk)
# into figures/numbers.json and the markdown table figures/numbers.md that the README shows.


rule numbers:
    input:
        number_fragments(),
    output:
        json="figures/numbers.json",
        table="figures/numbers.md",
    log:
        log_file("numbers"),
    threads: 1
    conda:
        SOFTWARE
    script:
        "../scripts/numbers.py"


# ---------------------------------------------------------------- galton
rule numbers_galton:
    input:
        distribution="results/galton/distribution.nc",
        arrivals="results/galton/arrivals.nc",
        sweep="results/galton/radius_sweep.nc",
    output:
        numbers="results/numbers/galton.json",
    log:
        log_file("numbers_galton"),
    threads: 1
    conda:
        SOFTWARE
    script:
        "../scripts/numbers_galton.py"


# ---------------------------------------------------------------- orbits
rule numbers_orbits:
    input:
        specnoslip="results/orbits/specnoslip.nc",
        pentagons="results/orbits/pentagons.nc",
        bounce="results/orbits/bounce.nc",
        twodisks="results/orbits/twodisks.nc",
        sphere="results/orbits/sphere.nc",
    output:
        numbers="results/numbers/orbits.json",
    log:
        log_file("numbers_orbits"),
    threads: 1
    conda:
        SOFTWARE
    script:
        "../scripts/numbers_orbits.py"



# ---------------------------------------------------------------- portraits
rule numbers_portraits:
    input:
        islands="results/portraits/islands.nc",
    output:
        numbers="results/numbers/portraits.json",
    log:
        log_file("numbers_portraits"),
    threads: 1
    conda:
        SOFTWARE
    script:
        "../scripts/numbers_portraits.py"


# ---------------------------------------------------------------- stability
rule numbers_stability:
    input:
        noforce="results/stability/grid_noforce.nc",
        force="results/stability/grid_force.nc",
        theta="results/stability/grid_theta.nc",
        scan="results/stability/launch_scan.nc",
        wedge="results/stability/wedge_orbits.nc",
    output:
        numbers="results/numbers/stability.json",
    params:
        band=config["stability"]["grids"]["threshold_band"],
        min_run=config["stability"]["grids"]["min_run"],
        thetas=config["stability"]["launch"]["thetas"],
    log:
        log_file("numbers_stability"),
    threads: 1
    conda:
        SOFTWARE
    script:
        "../scripts/numbers_stability.py"
